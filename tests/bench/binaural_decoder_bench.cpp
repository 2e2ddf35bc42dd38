// SPDX-License-Identifier: GPL-3.0-or-later
// What the binaural decoder (engine/render/binaural_decoder.hpp) costs on the audio thread: orders 1..3 of
// an AmbiX bus of noise through Debian's MIT KEMAR set, per sample and as a share of one core in real time,
// and each order's cost against order 1 measured in the same run (docs/binaural.md, "Cost").
//
//   build/tests/binaural_decoder_bench [--rate HZ] [--block FRAMES] [--seconds S] [--sofa FILE]
// defaults 48000 Hz, 256 frames, 2 s of CPU time per order, /usr/share/libmysofa/default.sofa. Prints one
// line per order: filter taps, partitions, ns per sample (the median of 5 runs, thread CPU time), percent of
// a core at the rate, the ratio to order 1, and the time create() took. Exit 2 on a usage or file error.
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "engine/core/random.hpp"
#include "engine/render/binaural_decoder.hpp"

namespace {

double thread_seconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return t.tv_sec + t.tv_nsec * 1e-9;
}

double wall_seconds() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + t.tv_nsec * 1e-9;
}

}  // namespace

int main(int argc, char** argv) {
    double rate = 48000.0, seconds = 2.0;
    int block = 256;
    std::string sofa = ameoto::BinauralDecoder::default_sofa_path;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--rate" && i + 1 < argc) rate = std::atof(argv[++i]);
        else if (a == "--block" && i + 1 < argc) block = std::atoi(argv[++i]);
        else if (a == "--seconds" && i + 1 < argc) seconds = std::atof(argv[++i]);
        else if (a == "--sofa" && i + 1 < argc) sofa = argv[++i];
        else {
            std::fprintf(stderr, "usage: binaural_decoder_bench [--rate HZ] [--block FRAMES] [--seconds S] [--sofa FILE]\n");
            return 2;
        }
    }
    if (!(seconds > 0.0 && seconds <= 600.0)) {
        std::fprintf(stderr, "--seconds: 0..600\n");
        return 2;
    }
    std::printf("binaural decoder, %s, %g Hz, blocks of %d frames\n", sofa.c_str(), rate, block);
    std::printf("%5s %6s %10s %12s %10s %9s %10s\n", "order", "taps", "partitions", "ns/sample", "% of core", "x order 1", "create ms");
    double first = 0.0;
    for (int order = 1; order <= 3; ++order) {
        const double t0 = wall_seconds();
        auto made = ameoto::BinauralDecoder::create(sofa, order, rate, block);
        const double create_ms = (wall_seconds() - t0) * 1e3;
        if (!made.decoder) {
            std::fprintf(stderr, "%s\n", made.error.c_str());
            return 2;
        }
        auto& d = *made.decoder;
        ameoto::Random rng(static_cast<std::uint64_t>(order));
        std::vector<std::vector<float>> bus(static_cast<std::size_t>(d.channels()), std::vector<float>(static_cast<std::size_t>(block)));
        for (auto& ch : bus)
            for (auto& v : ch) v = static_cast<float>(rng.uniform() - 0.5);
        std::vector<const float*> in;
        for (auto& ch : bus) in.push_back(ch.data());
        std::vector<float> left(static_cast<std::size_t>(block)), right(static_cast<std::size_t>(block));
        // Blocks per run: about seconds / 5 of CPU each, found from a short trial.
        double trial = thread_seconds();
        int trial_blocks = 0;
        while (thread_seconds() - trial < 0.05) {
            d.process(in.data(), block, left.data(), right.data());
            ++trial_blocks;
        }
        const double per_block = (thread_seconds() - trial) / trial_blocks;
        const long blocks = std::max(1L, static_cast<long>(seconds / 5.0 / per_block));
        std::vector<double> runs;
        for (int r = 0; r < 5; ++r) {
            const double s = thread_seconds();
            for (long b = 0; b < blocks; ++b) d.process(in.data(), block, left.data(), right.data());
            runs.push_back((thread_seconds() - s) / (static_cast<double>(blocks) * block));
        }
        std::sort(runs.begin(), runs.end());
        const double per_sample = runs[2];
        if (order == 1) first = per_sample;
        const int partitions = (d.filter_frames() + block - 1) / block;
        std::printf("%5d %6d %10d %12.1f %10.2f %9.2f %10.0f\n", order, d.filter_frames(), partitions, per_sample * 1e9,
                    per_sample * rate * 100.0, per_sample / first, create_ms);
    }
    return 0;
}
