// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Deterministic random numbers for the engine.
//
// Interface:
//   Random rng(seed);            // any 64-bit seed; same seed -> same sequence on every platform
//   rng.next_u64();              // raw 64 bits
//   rng.uniform();               // double in [0, 1)
//   rng.uniform(a, b);           // double in [a, b)
//   rng.exponential();           // Exp(1) variate
//
// Why not <random>: std::uniform_real_distribution and friends are implementation-defined, so the
// same seed would render different samples with another standard library. Offline renders must be
// reproducible to the sample, so the engine owns its generator (xoshiro256**, Blackman & Vigna 2018,
// seeded through SplitMix64 as its authors recommend). No allocation; safe on the audio thread.

#include <cmath>
#include <cstdint>

namespace ameoto {

class Random {
public:
    explicit Random(std::uint64_t seed = 0) { reseed(seed); }

    void reseed(std::uint64_t seed) {
        std::uint64_t x = seed;
        for (auto& word : state_) word = split_mix(x);
    }

    std::uint64_t next_u64() {
        const std::uint64_t result = rotl(state_[1] * 5, 7) * 9;
        const std::uint64_t t = state_[1] << 17;
        state_[2] ^= state_[0];
        state_[3] ^= state_[1];
        state_[1] ^= state_[2];
        state_[0] ^= state_[3];
        state_[2] ^= t;
        state_[3] = rotl(state_[3], 45);
        return result;
    }

    // 53 random bits scaled to [0, 1).
    double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
    double uniform(double low, double high) { return low + (high - low) * uniform(); }

    // Inverse-CDF exponential; 1 - u lies in (0, 1], so the log is finite.
    double exponential() { return -std::log(1.0 - uniform()); }

private:
    static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    static std::uint64_t split_mix(std::uint64_t& x) {
        std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    std::uint64_t state_[4]{};
};

}  // namespace ameoto
