// SPDX-License-Identifier: GPL-3.0-or-later
// jack_peer SECONDS MEGABYTES PERCENT: a JACK client that stands in for ameotod's audio callback with a
// fixed amount of plain work, to tell the machine's share of slow callbacks and xruns from ours
// (docs/bench.md, "Slow blocks"; run by tests/bench/xrun-floor, not part of CI).
//
// Each callback does the same work: PERCENT of the period (calibrated before activation, on this
// machine's speed at that moment), walking a buffer of MEGABYTES one cache line at a time and carrying
// on where the last callback stopped, so over time it touches as much memory as that, as ameotod's
// scenes do (tens of MB of templates, drop pools and delay lines); MEGABYTES 0 does the same number of
// steps on one cache line (arithmetic only, as jack_cpu does). Like `ameotod --block-trace`, it times
// each callback's thread CPU time (CLOCK_THREAD_CPUTIME_ID) and counts those over 50 % and 100 % of the
// period, and counts JACK's xruns. Every 60 s, and at the end, it prints one line, ending with the wall
// seconds since activation (the count of callbacks a busy machine's oversleeping main thread lets in):
//   60 s: callbacks 11250 mean_cpu_pct 21.0 max_cpu_pct 82.3 over_50 5 over_100 0 xruns 0 wall_s 60.001
// The work never allocates, locks or logs in the callback (it runs under JACK's real-time thread).
#include <jack/jack.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace {

struct Counts {
    std::atomic<long> callbacks{0}, over_50{0}, over_100{0}, xruns{0};
    std::atomic<double> cpu_pct_sum{0.0}, max_cpu_pct{0.0};
};

Counts counts;
std::vector<double> buffer;   // allocated before activation
std::size_t cursor = 0;
std::size_t stride = 8;         // doubles: one 64-byte cache line
std::size_t steps_per_callback = 0;
double period_ns = 0.0;
volatile double sink = 0.0;     // keeps the work from being optimised away

double thread_cpu_ns() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return 1e9 * static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec);
}

// One read-modify-write per step, a cache line apart; wraps to the next offset inside the line so that
// successive passes do not repeat the same addresses.
void work(std::size_t steps) {
    double sum = 0.0;
    for (std::size_t k = 0; k < steps; ++k) {
        double& v = buffer[cursor];
        sum += v;
        v = 1.0 + 1e-9 * sum;
        cursor += stride;
        if (cursor >= buffer.size()) cursor = (cursor + 1) % stride;
    }
    sink = sum;
}

int on_process(jack_nframes_t, void*) {
    const double start = thread_cpu_ns();
    work(steps_per_callback);
    const double pct = 100.0 * (thread_cpu_ns() - start) / period_ns;
    counts.callbacks.fetch_add(1, std::memory_order_relaxed);
    counts.cpu_pct_sum.store(counts.cpu_pct_sum.load(std::memory_order_relaxed) + pct, std::memory_order_relaxed);
    if (pct > counts.max_cpu_pct.load(std::memory_order_relaxed)) counts.max_cpu_pct.store(pct, std::memory_order_relaxed);
    if (pct > 50.0) counts.over_50.fetch_add(1, std::memory_order_relaxed);
    if (pct > 100.0) counts.over_100.fetch_add(1, std::memory_order_relaxed);
    return 0;
}

int on_xrun(void*) {
    counts.xruns.fetch_add(1, std::memory_order_relaxed);
    return 0;
}

void print_line(int seconds, std::chrono::steady_clock::time_point activated) {
    const long n = counts.callbacks.load();
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - activated).count();
    std::printf("%d s: callbacks %ld mean_cpu_pct %.1f max_cpu_pct %.1f over_50 %ld over_100 %ld xruns %ld wall_s %.3f\n", seconds,
                n, n > 0 ? counts.cpu_pct_sum.load() / static_cast<double>(n) : 0.0, counts.max_cpu_pct.load(),
                counts.over_50.load(), counts.over_100.load(), counts.xruns.load(), wall_s);
    std::fflush(stdout);
}

bool parse_int(const char* text, long low, long high, long& out) {
    char* end = nullptr;
    out = std::strtol(text, &end, 10);
    return end != text && *end == '\0' && out >= low && out <= high;
}

}  // namespace

int main(int argc, char** argv) {
    long seconds = 0, megabytes = 0, percent = 0;
    if (argc != 4 || !parse_int(argv[1], 1, 86400, seconds) || !parse_int(argv[2], 0, 4096, megabytes) ||
        !parse_int(argv[3], 1, 90, percent)) {
        std::fprintf(stderr, "usage: jack_peer SECONDS(1..86400) MEGABYTES(0..4096) PERCENT(1..90)\n");
        return 2;
    }
    if (megabytes == 0) {
        buffer.assign(stride, 1.0);
        stride = 1;
    } else {
        buffer.assign(static_cast<std::size_t>(megabytes) * 1024 * 1024 / sizeof(double), 1.0);   // touched: no fault later
    }
    jack_status_t status{};
    jack_client_t* client = jack_client_open("jack_peer", JackNoStartServer, &status);
    if (client == nullptr) {
        std::fprintf(stderr, "jack_peer: cannot open a JACK client (status 0x%x): is jackd running?\n", static_cast<unsigned>(status));
        return 1;
    }
    period_ns = 1e9 * jack_get_buffer_size(client) / jack_get_sample_rate(client);
    // Calibrate: the median of 21 timed runs of a fixed number of steps.
    constexpr std::size_t probe = 1 << 16;
    std::vector<double> per_step;
    for (int r = 0; r < 21; ++r) {
        const double start = thread_cpu_ns();
        work(probe);
        per_step.push_back((thread_cpu_ns() - start) / probe);
    }
    std::sort(per_step.begin(), per_step.end());
    steps_per_callback = static_cast<std::size_t>(static_cast<double>(percent) / 100.0 * period_ns / per_step[per_step.size() / 2]);
    std::printf("jack_peer: %ld MB, %zu steps a callback (%ld %% of a %.0f us period when calibrated)\n", megabytes,
                steps_per_callback, percent, period_ns / 1e3);
    std::fflush(stdout);
    jack_set_xrun_callback(client, &on_xrun, nullptr);
    jack_set_process_callback(client, &on_process, nullptr);
    const auto activated = std::chrono::steady_clock::now();
    if (jack_activate(client) != 0) {
        std::fprintf(stderr, "jack_peer: cannot activate the client\n");
        return 1;
    }
    for (long s = 1; s <= seconds; ++s) {
        std::this_thread::sleep_for(std::chrono::seconds(1));
        if (s % 60 == 0 && s != seconds) print_line(static_cast<int>(s), activated);
    }
    jack_deactivate(client);
    print_line(static_cast<int>(seconds), activated);
    jack_client_close(client);
    return 0;
}
