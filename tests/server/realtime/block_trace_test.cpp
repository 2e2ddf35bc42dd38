// SPDX-License-Identifier: GPL-3.0-or-later
// The per-block trace (--block-trace): the thread readings measure this thread's CPU time, the file
// holds exactly the slow blocks with their cause, and the bridge records every block without breaking
// the real-time contract (the probe is linked into this binary).

#include "server/realtime/block_trace.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "server/realtime/audio_bridge.hpp"
#include "server/realtime/rt_probe.hpp"
#include "tests/support/rt_probe_scope.hpp"   // the probe's counters (ameoto_rt_probe_*)
#include "tests/support/temp_dir.hpp"
#include "tests/support/relative_approx.hpp"

namespace {

std::vector<std::string> lines_of(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

std::vector<std::string> fields(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> out;
    for (std::string f; in >> f;) out.push_back(f);
    return out;
}

ameoto::BlockRecord block(std::uint64_t callback, double wall_fraction, double cpu_fraction) {
    ameoto::BlockRecord r;
    r.callback = callback;
    r.frame = callback * 64;
    r.frames = 64;
    const double period_ns = 1e9 * 64 / 48000.0;
    r.start_ns = 1'000'000'000 + static_cast<std::int64_t>(callback * period_ns);
    r.wall_ns = static_cast<std::int64_t>(wall_fraction * period_ns);
    r.cpu_ns = static_cast<std::int64_t>(cpu_fraction * period_ns);
    return r;
}

}  // namespace

TEST_CASE("BlockTrace::read_thread counts this thread's CPU time, not the wall clock's") {
    const auto before = ameoto::BlockTrace::read_thread();
    volatile double x = 0.0;
    for (int i = 0; i < 20'000'000; ++i) x = x + 1e-9 * i;   // tens of ms of CPU
    const auto busy = ameoto::BlockTrace::read_thread();
    timespec pause{0, 50'000'000};
    nanosleep(&pause, nullptr);   // 50 ms asleep: no CPU time
    const auto after = ameoto::BlockTrace::read_thread();
    CHECK(busy.cpu_ns - before.cpu_ns > 1'000'000);
    CHECK(after.cpu_ns - busy.cpu_ns < 20'000'000);
    CHECK(after.voluntary - busy.voluntary >= 1);   // the sleep gave up the CPU
}

TEST_CASE("the trace file holds the slow blocks, each with its cause, and a summary") {
    const std::string path = ameoto::test::temp_path("blocks.trace");
    ameoto::BlockTraceFile file(path, 48000.0, 0.5);
    CHECK_FALSE(file.add(block(0, 0.2, 0.19)));             // fast
    ameoto::BlockRecord heavy = block(1, 0.9, 0.85);         // our own work
    heavy.activity.lattice_spawned = 3;
    heavy.activity.link_breaks = 250;
    heavy.minor_faults = 7;
    CHECK(file.add(heavy));
    CHECK(file.add(block(2, 1.4, 0.2)));                     // kept off the CPU
    CHECK_FALSE(file.add(block(3, 0.5, 0.5)));               // at the threshold: not over it
    ameoto::BlockRecord woken_late = block(4, 0.2, 0.2);
    woken_late.start_ns += static_cast<std::int64_t>(1e9 * 64 / 48000.0);   // two periods after block 3's start
    CHECK(file.add(woken_late));
    CHECK_FALSE(file.add(block(6, 0.2, 0.2)));   // 5 is missing (not a late wake-up: a lost record)
    file.close(4);
    CHECK(file.blocks() == 6);
    CHECK(file.slow_ours() == 1);
    CHECK(file.slow_machine() == 1);
    CHECK(file.late() == 1);

    const auto lines = lines_of(path);
    REQUIRE(lines.size() == 7);   // 2 comments, the columns, 3 blocks, the summary
    CHECK(lines[0].rfind("# ameotod block trace 1", 0) == 0);
    CHECK(lines[2] == ameoto::BlockTraceFile::columns());
    const auto names = fields(lines[2]);
    const auto ours = fields(lines[3]), machine = fields(lines[4]);
    REQUIRE(ours.size() == names.size());
    REQUIRE(machine.size() == names.size());
    auto column = [&](const std::vector<std::string>& row, const std::string& name) {
        for (std::size_t i = 0; i < names.size(); ++i)
            if (names[i] == name) return row[i];
        FAIL("no column " << name);
        return std::string();
    };
    CHECK(column(ours, "callback") == "1");
    CHECK(column(ours, "cause") == "ours");
    CHECK(std::stod(column(ours, "cpu_pct")) == doctest::Approx(85.0).epsilon(0.01));
    CHECK(std::stod(column(ours, "time_s")) == ameoto::test::relative(64 / 48000.0).epsilon(0.01));
    CHECK(column(ours, "spawned") == "3");
    CHECK(column(ours, "link_breaks") == "250");
    CHECK(column(ours, "minflt") == "7");
    CHECK(column(machine, "callback") == "2");
    CHECK(column(machine, "cause") == "machine");
    CHECK(std::stod(column(machine, "wall_pct")) == doctest::Approx(140.0).epsilon(0.01));
    const auto late = fields(lines[5]);
    REQUIRE(late.size() == names.size());
    CHECK(column(late, "callback") == "4");
    CHECK(column(late, "cause") == "late");
    CHECK(std::stod(column(late, "gap_us")) == doctest::Approx(2e6 * 64 / 48000.0).epsilon(0.01));
    CHECK(std::stod(column(ours, "gap_us")) == doctest::Approx(1e6 * 64 / 48000.0).epsilon(0.01));
    CHECK(lines[6].rfind("# blocks 6 slow 2 ours 1 machine 1 late 1 lost 4 ", 0) == 0);
}

TEST_CASE("an unwritable trace file is refused with the reason") {
    CHECK_THROWS_WITH_AS(ameoto::BlockTraceFile("/nonexistent-dir/x.trace", 48000.0, 0.5),
                         doctest::Contains("/nonexistent-dir/x.trace"), std::runtime_error);
}

TEST_CASE("a full trace ring counts what it lost and never waits") {
    ameoto::BlockTrace trace(4);
    const ameoto::BlockTrace::Reading r{};
    for (int i = 0; i < 6; ++i) trace.record(static_cast<std::uint64_t>(i), 0, 64, 0, 1000, r, r, {});
    CHECK(trace.lost() == 2);
    ameoto::BlockRecord out;
    for (std::uint64_t i = 0; i < 4; ++i) {
        REQUIRE(trace.pop(out));
        CHECK(out.callback == i);
    }
    CHECK_FALSE(trace.pop(out));
}

TEST_CASE("the bridge records every block with its work, inside the real-time contract") {
    ameoto::rt::init_probe();
    REQUIRE(bool(ameoto::rt::probe_enter));
    ameoto::RendererConfig config;
    config.rain_rate_mm_per_h = 30.0;
    config.adaptive_lod = true;
    ameoto::AudioBridge bridge(std::make_unique<ameoto::Renderer>(config), 16);
    bridge.enable_block_trace(256);
    constexpr int block = 64;
    std::vector<float> l(block), r(block);
    float* outs[2] = {l.data(), r.data()};
    ameoto::Command drop;
    drop.kind = ameoto::CommandKind::drop;
    drop.values[0] = 0.004;
    drop.values[1] = 7.0;
    drop.values[2] = 0.2;
    REQUIRE(bridge.send(drop));
    ameoto_rt_probe_reset();
    for (int n = 0; n < 100; ++n) bridge.process(block, outs);
    CHECK(ameoto_rt_probe_entries() == 100);
    INFO("first violation: " << std::string(ameoto_rt_probe_first_violation()));
    CHECK(ameoto_rt_probe_violations() == 0);

    ameoto::BlockRecord rec;
    std::vector<ameoto::BlockRecord> records;
    while (bridge.block_trace()->pop(rec)) records.push_back(rec);
    REQUIRE(records.size() == 100);
    CHECK(bridge.block_trace()->lost() == 0);
    long spawned = 0, commands = 0, rain = 0;
    for (std::size_t i = 0; i < records.size(); ++i) {
        CHECK(records[i].callback == i);
        CHECK(records[i].frame == i * block);
        CHECK(records[i].wall_ns > 0);
        CHECK(records[i].cpu_ns >= 0);
        spawned += records[i].activity.lattice_spawned;
        commands += records[i].activity.commands;
        rain += records[i].activity.full_rain + records[i].activity.template_impacts + records[i].activity.texture_grains;
    }
    CHECK(records[0].activity.commands == 1);   // the /drop, applied in the first block
    CHECK(records[0].activity.lattice_spawned >= 1);
    CHECK(commands == 1);
    CHECK(spawned >= 1);
    CHECK(rain > 10);   // 30 mm/h on the umbrella: hundreds of drops a second
}
