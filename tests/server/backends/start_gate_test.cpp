// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/backends/start_gate.hpp"

#include <doctest/doctest.h>

#include <cstdint>

using ameoto::StartGate;

namespace {
constexpr std::int64_t gate_period_ns = 5'333'333;   // 256 frames at 48 kHz
constexpr std::int64_t gate_epoch = 1'800'000'000'000'000'000;
}  // namespace

TEST_CASE("start gate: no epoch is open from the first cycle") {
    StartGate gate;
    CHECK(gate.open(123, gate_period_ns));
    CHECK(gate.opened());
}

TEST_CASE("start gate: closed before the epoch, opens on the cycle that starts nearest it, and stays open") {
    StartGate gate(gate_epoch);
    CHECK_FALSE(gate.open(gate_epoch - 3 * gate_period_ns, gate_period_ns));
    CHECK_FALSE(gate.opened());
    // A cycle starting just over half a period before the epoch is not the nearest: the next one is.
    CHECK_FALSE(gate.open(gate_epoch - gate_period_ns / 2 - 1, gate_period_ns));
    CHECK(gate.open(gate_epoch + gate_period_ns / 2 - 1, gate_period_ns));
    CHECK(gate.lag_ns() == gate_period_ns / 2 - 1);
    CHECK(gate.open(gate_epoch - 100 * gate_period_ns, gate_period_ns));   // open for good, whatever a later clock says
}

TEST_CASE("start gate: two nodes of one server whose clock readings differ by microseconds open on the same cycle") {
    // The cycles' filtered start times as two clients read them: the same JACK loop, read 3 us apart.
    const std::int64_t first_cycle = gate_epoch - 7 * gate_period_ns + 1'234'567;
    StartGate a(gate_epoch), b(gate_epoch);
    int opened_a = -1, opened_b = -1;
    for (int k = 0; k < 20; ++k) {
        const std::int64_t cycle = first_cycle + k * gate_period_ns;
        if (opened_a < 0 && a.open(cycle, gate_period_ns)) opened_a = k;
        if (opened_b < 0 && b.open(cycle + 3'000, gate_period_ns)) opened_b = k;
    }
    CHECK(opened_a == 7);
    CHECK(opened_b == opened_a);
}

TEST_CASE("start gate: a node that starts after the epoch opens at once and says how late") {
    StartGate gate(gate_epoch);
    CHECK(gate.open(gate_epoch + 2'000'000'000, gate_period_ns));
    CHECK(gate.lag_ns() == 2'000'000'000);
}
