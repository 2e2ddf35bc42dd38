// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A per-block record of the audio callback, for finding the rare slow blocks (issue 5's xruns).
//
// Interface:
//   BlockTrace trace(8192);                      // control thread, allocates the ring once
//   audio thread:  BlockTrace::Reading r0 = BlockTrace::read_thread();   // at the block's start
//                  ... the block ...
//                  trace.record(callback, frame, frames, start_ns, wall_ns, r0, BlockTrace::read_thread(), activity);
//   reader thread: trace.pop(record)             // false when empty; trace.lost() counts a full ring
//   BlockTraceFile file(path, sample_rate, threshold);   // opens or throws std::runtime_error
//                  file.add(record)               // writes it when it is slow, counts it either way
//                  file.close()                   // the summary line, flushed
//
// Each block's wall time comes from the monotonic clock (vDSO). Its CPU time comes from
// clock_gettime(CLOCK_THREAD_CPUTIME_ID), its page faults and context switches from
// getrusage(RUSAGE_THREAD). Neither is a vDSO call on x86-64 (the vDSO serves only the wall clocks):
// both are system calls, but ones that read the calling task's own counters and never sleep (no
// allocation, no sleeping lock, no I/O), about 2-2.5 us each on this VM, so the four per block cost
// about 0.7 % of a 64-frame period; they run only while the trace is on. getrusage's CPU time is not
// used: the kernel brings a running task's ru_utime/ru_stime up to date only at ticks and switches
// (measured: 0 us for blocks of 450 us), while the thread CPU clock reads the runtime up to now.

// A block is slow when its wall time or its CPU time passes `threshold` of the period. Its cause is
// "ours" when the CPU time alone passes the threshold (the work of the block), "machine" when only the
// wall time does (the thread was kept off the CPU: preemption, a hypervisor's steal, a page fault's wait).
// A block that was not slow is still written, with cause "late", when it started more than 1 + threshold
// periods after the one before although that one had finished within its period: the audio thread was
// woken late (the machine's; a late wake-up is an xrun that no callback's duration shows).
// Caveat: without CONFIG_IRQ_TIME_ACCOUNTING the interrupts served while the thread runs count as its
// CPU time, so "ours" is an upper bound (docs/bench.md, "Slow blocks").

#include <sys/resource.h>
#include <time.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "engine/render/renderer.hpp"
#include "server/realtime/spsc_queue.hpp"

namespace ameoto {

struct BlockRecord {
    std::uint64_t callback = 0;       // the callback's number since start
    std::uint64_t frame = 0;          // the first sample of the block
    int frames = 0;
    std::int64_t start_ns = 0;        // monotonic clock at the callback's start
    std::int64_t wall_ns = 0;         // the callback's duration, wall clock
    std::int64_t cpu_ns = 0;          // the audio thread's CPU time in it (user + system)
    long minor_faults = 0;            // page faults in it served without I/O
    long major_faults = 0;            // page faults in it that waited for I/O
    long voluntary_switches = 0;      // times it gave up the CPU (should be 0: it never blocks)
    long involuntary_switches = 0;    // times it was preempted
    BlockActivity activity;
};

class BlockTrace {
public:
    struct Reading {
        std::int64_t cpu_ns = 0;
        long minor_faults = 0, major_faults = 0, voluntary = 0, involuntary = 0;
    };
    static Reading read_thread() {
        rusage u{};
        getrusage(RUSAGE_THREAD, &u);
        timespec cpu{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu);
        return Reading{static_cast<std::int64_t>(cpu.tv_sec) * 1000000000 + cpu.tv_nsec, u.ru_minflt, u.ru_majflt,
                       u.ru_nvcsw, u.ru_nivcsw};
    }

    explicit BlockTrace(std::size_t capacity) : ring_(capacity) {}

    // audio thread
    void record(std::uint64_t callback, std::uint64_t frame, int frames, std::int64_t start_ns, std::int64_t wall_ns,
                const Reading& before, const Reading& after, const BlockActivity& activity) {
        BlockRecord r;
        r.callback = callback;
        r.frame = frame;
        r.frames = frames;
        r.start_ns = start_ns;
        r.wall_ns = wall_ns;
        r.cpu_ns = after.cpu_ns - before.cpu_ns;
        r.minor_faults = after.minor_faults - before.minor_faults;
        r.major_faults = after.major_faults - before.major_faults;
        r.voluntary_switches = after.voluntary - before.voluntary;
        r.involuntary_switches = after.involuntary - before.involuntary;
        r.activity = activity;
        if (!ring_.try_push(r)) lost_.fetch_add(1, std::memory_order_relaxed);
    }

    // reader thread
    bool pop(BlockRecord& record) { return ring_.try_pop(record); }
    std::uint64_t lost() const { return lost_.load(std::memory_order_relaxed); }

private:
    SpscQueue<BlockRecord> ring_;
    std::atomic<std::uint64_t> lost_{0};
};

// The trace file: comment lines start with '#'; one header line names the columns; then one line per
// slow block, space-separated, in the order they were played (docs/bench.md, "Slow blocks").
class BlockTraceFile {
public:
    BlockTraceFile(const std::string& path, double sample_rate, double threshold);
    ~BlockTraceFile();
    BlockTraceFile(const BlockTraceFile&) = delete;
    BlockTraceFile& operator=(const BlockTraceFile&) = delete;

    bool add(const BlockRecord& record);   // true when the block was written (slow or late)
    void flush();
    void close(std::uint64_t lost);        // writes the summary; later calls do nothing

    std::uint64_t blocks() const { return blocks_; }
    std::uint64_t slow_ours() const { return slow_ours_; }
    std::uint64_t slow_machine() const { return slow_machine_; }
    std::uint64_t late() const { return late_; }
    static const char* columns();

private:
    std::FILE* file_ = nullptr;
    double sample_rate_;
    double threshold_;
    std::int64_t first_start_ns_ = -1;
    std::int64_t previous_start_ns_ = -1;
    double previous_wall_ = 0.0;
    std::uint64_t previous_callback_ = 0;
    std::uint64_t blocks_ = 0, slow_ours_ = 0, slow_machine_ = 0, late_ = 0;
    long minor_faults_ = 0, major_faults_ = 0, involuntary_ = 0;
    double cpu_sum_ = 0.0, wall_max_ = 0.0, cpu_max_ = 0.0;
};

}  // namespace ameoto
