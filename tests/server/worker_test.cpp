// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/worker.hpp"

#include <doctest/doctest.h>

#include <boost/asio/steady_timer.hpp>

#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace std::chrono_literals;

TEST_CASE("Worker runs jobs in order off the control thread and delivers results on it") {
    boost::asio::io_context io;
    ameoto::Worker worker(io);
    const auto control = std::this_thread::get_id();
    std::vector<int> results;
    std::vector<std::thread::id> built_on, delivered_on;
    std::vector<int> pending_at_delivery;
    for (int i = 0; i < 5; ++i) {
        worker.submit<int>(
            [i, &built_on] {
                built_on.push_back(std::this_thread::get_id());
                std::this_thread::sleep_for(2ms);
                return i * i;
            },
            [&](int r) {
                results.push_back(r);
                delivered_on.push_back(std::this_thread::get_id());
                pending_at_delivery.push_back(worker.pending());
            },
            [](std::string) { FAIL("no job should fail"); });
    }
    // Run the control loop until all five results are back (bounded).
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (results.size() < 5 && std::chrono::steady_clock::now() < deadline) {
        io.run_for(10ms);
        io.restart();
    }
    CHECK(results == std::vector<int>{0, 1, 4, 9, 16});
    for (auto id : built_on) CHECK(id != control);
    for (auto id : delivered_on) CHECK(id == control);
    // A delivered job is no longer pending: when job i's result arrives, at most the 4 - i after it are
    // (queued or running; on a loaded machine the worker may have finished the next before the control
    // thread delivers this one, so fewer). Counting it until after its result was posted made the last
    // check here fail under the sanitizers, where the control thread ran the result first.
    REQUIRE(pending_at_delivery.size() == 5);
    for (std::size_t i = 0; i < 5; ++i) {
        INFO("job " << i << ": " << pending_at_delivery[i] << " pending at its delivery");
        CHECK(pending_at_delivery[i] <= 4 - static_cast<int>(i));
        CHECK(pending_at_delivery[i] >= 0);
    }
    CHECK(worker.pending() == 0);
}

TEST_CASE("Worker reports a job that throws, and keeps working") {
    boost::asio::io_context io;
    ameoto::Worker worker(io);
    std::string error;
    int after = -1;
    worker.submit<int>([]() -> int { throw std::runtime_error("material refused: tension 0 N/m"); }, [](int) { FAIL("must not succeed"); },
                       [&](std::string e) { error = e; });
    worker.submit<int>([] { return 7; }, [&](int r) { after = r; }, [](std::string) {});
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (after < 0 && std::chrono::steady_clock::now() < deadline) {
        io.run_for(10ms);
        io.restart();
    }
    CHECK(error == "material refused: tension 0 N/m");
    CHECK(after == 7);
}
