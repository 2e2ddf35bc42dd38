// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_timer.hpp"

#include <algorithm>
#include <ctime>

namespace ameoto::client {

double thread_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

BenchTiming time_per_sample(const std::function<void(long samples)>& run, double budget_s, int runs) {
    runs = std::max(runs, 1);
    // Warm-up and estimate: doubling chunks until a tenth of the budget is spent.
    long warm_samples = 0;
    double warm_time = 0.0;
    for (long chunk = 64; warm_samples < 256 || warm_time < 0.1 * budget_s; chunk *= 2) {
        const double start = thread_cpu_seconds();
        run(chunk);
        warm_time += thread_cpu_seconds() - start;
        warm_samples += chunk;
    }
    const double per_sample = warm_time / static_cast<double>(warm_samples);
    const double run_budget = 0.9 * budget_s / runs;
    BenchTiming t;
    t.runs = runs;
    t.samples_per_run = std::max(64L, static_cast<long>(run_budget / std::max(per_sample, 1e-12)));
    std::vector<double> ns;
    for (int r = 0; r < runs; ++r) {
        const double start = thread_cpu_seconds();
        run(t.samples_per_run);
        ns.push_back(1e9 * (thread_cpu_seconds() - start) / static_cast<double>(t.samples_per_run));
    }
    t.min_ns = *std::min_element(ns.begin(), ns.end());
    t.max_ns = *std::max_element(ns.begin(), ns.end());
    t.median_ns = median(ns);
    return t;
}

}  // namespace ameoto::client
