// SPDX-License-Identifier: GPL-3.0-or-later
// The control thread's loop (server/control_loop.hpp): repeating timers, SIGHUP, shutdown.
#include "server/control_loop.hpp"

#include <doctest/doctest.h>
#include <signal.h>

#include <chrono>
#include <thread>
#include <vector>

using namespace std::chrono_literals;

TEST_CASE("control loop: a timer runs at once, then each period after its run; shutdown stops it and runs the handlers once") {
    ameoto::ControlLoop loop;
    int fast = 0, slow = 0, handled = 0;
    std::vector<char> order;
    loop.every(2ms, [&] {
        ++fast;
        if (fast == 20) loop.shutdown();
    });
    CHECK(fast == 1);   // before run(): the first tick is the caller's, as the daemon's first poll
    loop.every(1h, [&] { ++slow; });
    loop.on_shutdown([&] { order.push_back('a'); ++handled; });
    loop.on_shutdown([&] { order.push_back('b'); });
    const auto start = std::chrono::steady_clock::now();
    loop.run();
    const auto took = std::chrono::steady_clock::now() - start;
    CHECK(fast == 20);
    CHECK(slow == 1);
    CHECK(handled == 1);
    CHECK(order == std::vector<char>{'a', 'b'});
    CHECK(took >= 19 * 2ms);   // 19 periods after the first tick
    CHECK(loop.stopping());
    loop.shutdown();           // again: nothing
    CHECK(handled == 1);
}

TEST_CASE("control loop: shutdown_soon from another thread stops run(); SIGHUP reaches its handler each time") {
    ameoto::ControlLoop loop;
    int hangups = 0;
    loop.on_hangup([&] {
        if (++hangups == 2) loop.shutdown();
    });
    loop.every(1ms, [&] {});   // keeps the loop busy, as the daemon's poll does
    std::thread raiser([] {
        std::this_thread::sleep_for(20ms);
        ::kill(::getpid(), SIGHUP);
        std::this_thread::sleep_for(20ms);
        ::kill(::getpid(), SIGHUP);
    });
    loop.run();
    raiser.join();
    CHECK(hangups == 2);

    ameoto::ControlLoop other;
    bool ran_after = false;
    std::thread stopper([&] {
        std::this_thread::sleep_for(20ms);
        other.shutdown_soon();
    });
    other.every(1ms, [&] { ran_after = other.stopping(); });
    other.run();
    stopper.join();
    CHECK(other.stopping());
    CHECK_FALSE(ran_after);   // no tick runs once stopped
}
