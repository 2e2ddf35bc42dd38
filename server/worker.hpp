// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Heavy work off the audio thread and off the control loop: building a scene, a canopy of a new
// material, a liquid's drop calibration (eigen-solves). One background thread runs the jobs in order;
// each result comes back on the control thread's io_context, which then hands the finished object to
// the audio thread by pointer through the command queue.
//
// Interface:
//   Worker worker(io);
//   worker.submit<Result>([]() { return build(); },                 // on the worker thread
//                         [](Result r) { use(r); },                  // then on the io_context
//                         [](std::string error) { report(error); }); // if the job threw
//   worker.pending();     // jobs queued or running
//   ~Worker               // finishes the running job, drops the queued ones, joins
//
// The worker may allocate, lock and take its time; that is its purpose. It never touches the audio
// thread's objects: it builds new ones.

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace ameoto {

class Worker {
public:
    explicit Worker(boost::asio::io_context& io);
    ~Worker();
    Worker(const Worker&) = delete;
    Worker& operator=(const Worker&) = delete;

    template <typename Result, typename Build, typename Done, typename Failed>
    void submit(Build build, Done done, Failed failed) {
        // The job returns its delivery; run() posts it only after the job has left pending(), so a
        // result seen on the io_context is never still counted as running.
        enqueue([build = std::move(build), done = std::move(done), failed = std::move(failed)]() mutable -> Delivery {
            try {
                auto result = std::make_shared<Result>(build());
                return [done = std::move(done), result]() mutable { done(std::move(*result)); };
            } catch (const std::exception& e) {
                return [failed = std::move(failed), message = std::string(e.what())]() { failed(message); };
            }
        });
    }

    int pending() const;   // jobs queued or running; a job whose result has been posted is neither

private:
    using Delivery = std::function<void()>;   // runs on the io_context
    void enqueue(std::function<Delivery()> job);
    void run();

    boost::asio::io_context& io_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::function<Delivery()>> jobs_;
    int running_ = 0;
    bool stop_ = false;
    std::thread thread_;
};

}  // namespace ameoto
