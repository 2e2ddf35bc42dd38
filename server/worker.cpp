// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/worker.hpp"

namespace ameoto {

Worker::Worker(boost::asio::io_context& io) : io_(io), thread_([this] { run(); }) {}

Worker::~Worker() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
        jobs_.clear();
    }
    wake_.notify_all();
    thread_.join();
}

void Worker::enqueue(std::function<Delivery()> job) {
    {
        std::lock_guard lock(mutex_);
        jobs_.push_back(std::move(job));
    }
    wake_.notify_one();
}

int Worker::pending() const {
    std::lock_guard lock(mutex_);
    return static_cast<int>(jobs_.size()) + running_;
}

void Worker::run() {
    for (;;) {
        std::function<Delivery()> job;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
            if (stop_) return;
            job = std::move(jobs_.front());
            jobs_.pop_front();
            ++running_;
        }
        Delivery deliver = job();
        {
            std::lock_guard lock(mutex_);
            --running_;
        }
        // Posted after the count: whoever runs the result on the io_context sees pending() without it.
        boost::asio::post(io_, std::move(deliver));
    }
}

}  // namespace ameoto
