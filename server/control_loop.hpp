// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The control thread's loop: one Boost.Asio io_context that every OSC reply, timer, signal and
// worker result runs on, so the daemon's state needs no locks. The signals and the repeating timers
// live here; what each timer does is the caller's (daemon.cpp says it, in one place).
//
// Interface:
//   ControlLoop loop;                          // SIGINT, SIGTERM and SIGHUP caught from here on
//   loop.io()                                  // for the endpoints, the worker, anything that posts here
//   loop.on_hangup([] { ... });                // each SIGHUP
//   loop.on_shutdown([] { ... });              // once, when the loop stops (in the order given)
//   loop.every(5ms, [] { ... });               // runs now, then again 5 ms after each run ends
//   loop.run();                                // until SIGINT/SIGTERM or shutdown(); then returns
//   loop.shutdown();                           // control thread: stop (a second call does nothing)
//   loop.shutdown_soon();                      // any thread: the same, posted to the control thread
//   loop.stopping()                            // shutdown() has run
//
// Threads: everything but shutdown_soon() on the control thread (the one that calls run(), and before
// run() the main thread, which is the same). A timer's period runs from the end of its work, not on a
// fixed grid: a slow poll never makes ticks pile up.

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include <chrono>
#include <functional>
#include <list>
#include <vector>

namespace ameoto {

class ControlLoop {
public:
    ControlLoop();
    ControlLoop(const ControlLoop&) = delete;
    ControlLoop& operator=(const ControlLoop&) = delete;

    boost::asio::io_context& io() { return io_; }
    void on_hangup(std::function<void()> handler);
    void on_shutdown(std::function<void()> handler) { shutdown_handlers_.push_back(std::move(handler)); }
    void every(std::chrono::steady_clock::duration period, std::function<void()> tick);
    void run();
    void shutdown();
    void shutdown_soon();
    bool stopping() const { return stopping_; }

private:
    struct Repeating {
        boost::asio::steady_timer timer;
        std::chrono::steady_clock::duration period;
        std::function<void()> tick;
    };
    void fire(Repeating& r);
    void wait_hangup();

    boost::asio::io_context io_;
    boost::asio::signal_set stop_signals_{io_, SIGINT, SIGTERM};
    boost::asio::signal_set hangup_signal_{io_, SIGHUP};
    std::function<void()> on_hangup_;
    std::list<Repeating> timers_;   // a list: each timer's handler holds its address
    std::vector<std::function<void()>> shutdown_handlers_;
    bool stopping_ = false;
};

}  // namespace ameoto
