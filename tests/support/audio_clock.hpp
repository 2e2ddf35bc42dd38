// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The running daemon's audio clock, read over OSC: how much audio it has rendered, and a wait for it to
// render more. A test that needs "a second of audio" waits on this clock, not on the wall's: a loaded
// machine, or the sanitizers (several times slower), can leave the null backend rendering slower than
// real time, and a wall-clock sleep then yields less audio than the test assumes.
//
// Interface:
//   double s = audio_seconds(client);          // /status.reply field 11: seconds of audio rendered
//   std::int64_t n = audio_frames(client);     // the same in frames (field 11 x field 9, the rate)
//   auto status = wait_for_audio(client, 1.2); // polls /status every 50 ms until the clock has moved
//                                              // 1.2 s on; REQUIREs that it does within the give-up
//                                              // time (20 s of wall, scaled under the sanitizers) and
//                                              // returns the /status.reply that showed it

#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <thread>

#include "protocol/osc_codec.hpp"
#include "tests/support/osc_test_client.hpp"
#include "tests/support/timing_scale.hpp"

namespace ameoto::test {

inline protocol::DecodedMessage status_reply(OscTestClient& client) {
    const auto reply = client.request("/status", {}, "/status.reply", std::chrono::seconds(2));
    REQUIRE(reply);
    REQUIRE(reply->types == "fffiiiiififfsfif");   // docs/PROTOCOL.md, /status.reply
    return *reply;
}

inline double audio_seconds(OscTestClient& client) { return status_reply(client).args[10].number; }

inline std::int64_t audio_frames(OscTestClient& client) {
    const auto reply = status_reply(client);
    return std::llround(static_cast<double>(reply.args[10].number) * reply.args[8].number);
}

inline protocol::DecodedMessage wait_for_audio(OscTestClient& client, double seconds_more,
                                               std::chrono::milliseconds give_up = std::chrono::seconds(20)) {
    const double from = audio_seconds(client);
    const auto deadline = std::chrono::steady_clock::now() + scaled(give_up);
    for (;;) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        auto status = status_reply(client);
        if (status.args[10].number - from >= seconds_more) return status;
        REQUIRE_MESSAGE(std::chrono::steady_clock::now() < deadline,
                        "the audio clock moved from " << from << " s only to " << status.args[10].number << " s, not "
                                                      << seconds_more << " s on");
    }
}

}  // namespace ameoto::test
