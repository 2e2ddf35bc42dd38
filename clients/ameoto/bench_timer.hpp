// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Timing for `ameoto bench`: CPU time of the calling thread, warm-up, several runs, the median.
//
// Interface:
//   BenchTiming t = time_per_sample([&](long n) { body.run(n); }, budget_s, runs);
//   t.median_ns, t.min_ns, t.max_ns, t.runs, t.samples_per_run    // ns per sample
//   double s = thread_cpu_seconds();
//   double m = median(values);
//   bench_sample_rate                      // 48 kHz: the rate every suite steps the engine at
//   bench_sink = bench_sink + result;      // keeps a timed loop's result, so the optimiser cannot drop the work
//
// The clock is CLOCK_THREAD_CPUTIME_ID: on a shared machine a thread that waits for a core is not
// charged for the wait (wall time would be), so the figure is the work the step does. Warm-up: the
// body runs for about a tenth of the budget (at least 256 samples), which also estimates its cost;
// the rest of the budget is split into `runs` runs of equal length (at least 64 samples each), and
// the median run is reported (robust to a run disturbed by another process).

#include <functional>
#include <vector>

namespace ameoto::client {

struct BenchTiming {
    double median_ns = 0.0, min_ns = 0.0, max_ns = 0.0;   // per sample
    int runs = 0;
    long samples_per_run = 0;
};

inline constexpr double bench_sample_rate = 48000.0;   // Hz
inline volatile double bench_sink = 0.0;

double thread_cpu_seconds();
double median(std::vector<double> values);
BenchTiming time_per_sample(const std::function<void(long samples)>& run, double budget_s, int runs);

}  // namespace ameoto::client
