// SPDX-License-Identifier: GPL-3.0-or-later
// The uniformly partitioned convolver (engine/render/partitioned_convolver.hpp) against a direct
// convolution in double, for several blocks and filters of several lengths.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "engine/core/random.hpp"
#include "engine/render/partitioned_convolver.hpp"

using namespace ameoto;

TEST_CASE("partitioned convolver: equals direct convolution within float rounding, any block") {
    Random rng(21);
    const int inputs = 3, outputs = 2, frames = 3000;
    // Filters of 1 tap, shorter than a block, and longer than several blocks.
    const int lengths[inputs][outputs] = {{1, 37}, {300, 1000}, {64, 129}};
    std::vector<std::vector<std::vector<float>>> h(inputs, std::vector<std::vector<float>>(outputs));
    for (int c = 0; c < inputs; ++c)
        for (int o = 0; o < outputs; ++o)
            for (int t = 0; t < lengths[c][o]; ++t) h[c][o].push_back(static_cast<float>(rng.uniform() - 0.5));
    std::vector<std::vector<float>> x(inputs, std::vector<float>(frames));
    for (auto& ch : x)
        for (auto& v : ch) v = static_cast<float>(rng.uniform() - 0.5);
    std::vector<std::vector<double>> direct(outputs, std::vector<double>(frames, 0.0));
    for (int o = 0; o < outputs; ++o)
        for (int c = 0; c < inputs; ++c)
            for (int n = 0; n < frames; ++n)
                for (std::size_t t = 0; t < h[c][o].size() && t <= static_cast<std::size_t>(n); ++t)
                    direct[o][n] += static_cast<double>(h[c][o][t]) * x[c][n - static_cast<int>(t)];
    for (int block : {1, 64, 100, 256, 1024}) {
        PartitionedConvolver conv(inputs, outputs, block, h);
        CHECK(conv.partitions() == (1000 + block - 1) / block);
        std::vector<std::vector<float>> y(outputs, std::vector<float>(frames, 0.0f));
        for (int at = 0; at + block <= frames; at += block) {
            const float* in[inputs];
            float* out[outputs];
            for (int c = 0; c < inputs; ++c) in[c] = &x[c][at];
            for (int o = 0; o < outputs; ++o) out[o] = &y[o][at];
            conv.process(in, out);
        }
        const int done = frames / block * block;
        double err = 0.0, ref = 0.0;
        for (int o = 0; o < outputs; ++o)
            for (int n = 0; n < done; ++n) {
                err = std::max(err, std::abs(y[o][n] - direct[o][n]));
                ref = std::max(ref, std::abs(direct[o][n]));
            }
        // Float FFTs of 2B points: error ~ eps log2(2B) times the sum of |terms| (up to ~1000 terms of 0.25
        // here); 1e-5 of the peak is above that and far below any real mistake (a wrong partition is ~1).
        INFO("block " << block << ": max error " << err << " of peak " << ref);
        CHECK(err < 1e-5 * ref);
        conv.reset();
        std::vector<float> silence(block, 0.0f), o0(block, 1.0f), o1(block, 1.0f);
        const float* in[inputs] = {silence.data(), silence.data(), silence.data()};
        float* out[outputs] = {o0.data(), o1.data()};
        conv.process(in, out);
        CHECK(std::abs(o0[0]) + std::abs(o1[block - 1]) == 0.0f);   // reset forgot the past
    }
    CHECK_THROWS(PartitionedConvolver(inputs, outputs, 0, h));
    CHECK_THROWS(PartitionedConvolver(2, outputs, 64, h));
}
