// SPDX-License-Identifier: GPL-3.0-or-later
// The binaural decoder (engine/render/binaural_decoder.hpp) on the audio it puts out: a plane wave encoded in
// AmbiX from the left and from the front, through Debian's MIT KEMAR set (libmysofa1), gives the ears the
// level and time differences a head gives; blocks of any size give the same samples as direct convolution;
// bad requests get clear errors; process() passes the real-time probe.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <fstream>
#include <vector>

#include <mysofa.h>

#include "engine/core/fft.hpp"
#include "engine/core/random.hpp"
#include "engine/render/binaural_decoder.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/temp_dir.hpp"

using namespace ameoto;

namespace {

constexpr double bin_rate = 48000.0;
constexpr double bin_pi = 3.14159265358979323846;

// AmbiX encoding of a plane wave from the unit vector (x front, y left, z up), written out here apart from
// the decoder's own table: b_acn = Y_n^m(u) s(t), real harmonics, ACN order, SN3D, no Condon-Shortley phase
// (Nachbar et al. 2011, "AmbiX - a suggested Ambisonics format", table 1). From 90 degrees left (0, 1, 0):
// W = 1, Y = 1, Z = X = 0; order 2: V = T = S = 0, R = -1/2, U = -sqrt(3)/2; order 3: Q = -sqrt(5/8),
// O = -sqrt(3/8), the rest 0.
std::vector<double> binaural_encode(int order, double x, double y, double z) {
    std::vector<double> g{1.0, y, z, x};
    if (order >= 2) {
        const double r3 = std::sqrt(3.0);
        for (double v : {r3 * x * y, r3 * y * z, (3 * z * z - 1) / 2, r3 * x * z, r3 / 2 * (x * x - y * y)}) g.push_back(v);
    }
    if (order >= 3) {
        const double a = std::sqrt(5.0 / 8.0), b = std::sqrt(15.0), c = std::sqrt(3.0 / 8.0);
        for (double v : {a * y * (3 * x * x - y * y), b * x * y * z, c * y * (5 * z * z - 1), z * (5 * z * z - 3) / 2,
                         c * x * (5 * z * z - 1), b / 2 * z * (x * x - y * y), a * x * (x * x - 3 * y * y)})
            g.push_back(v);
    }
    return g;
}

struct BinauralEars {
    std::vector<float> left, right;
};

// White noise s(t) (uniform, seeded) encoded from direction u, decoded in blocks of `block`.
BinauralEars binaural_decode_noise(BinauralDecoder& d, const std::vector<double>& gains, int frames, int block, std::uint64_t seed = 5) {
    Random rng(seed);
    std::vector<float> s(static_cast<std::size_t>(frames));
    for (auto& v : s) v = static_cast<float>(rng.uniform() - 0.5);
    const int ch = d.channels();
    std::vector<std::vector<float>> bus(static_cast<std::size_t>(ch), std::vector<float>(static_cast<std::size_t>(block)));
    BinauralEars e{std::vector<float>(static_cast<std::size_t>(frames)), std::vector<float>(static_cast<std::size_t>(frames))};
    std::vector<const float*> in(static_cast<std::size_t>(ch));
    for (int at = 0; at + block <= frames; at += block) {
        for (int c = 0; c < ch; ++c) {
            for (int n = 0; n < block; ++n)
                bus[static_cast<std::size_t>(c)][static_cast<std::size_t>(n)] = static_cast<float>(gains[static_cast<std::size_t>(c)] * s[static_cast<std::size_t>(at + n)]);
            in[static_cast<std::size_t>(c)] = bus[static_cast<std::size_t>(c)].data();
        }
        d.process(in.data(), block, &e.left[static_cast<std::size_t>(at)], &e.right[static_cast<std::size_t>(at)]);
    }
    return e;
}

// Energy of x[from, from + 2^k) between f_lo and f_hi (Hz), from its DFT.
double binaural_band_energy(const std::vector<float>& x, int from, int length, double f_lo, double f_hi) {
    std::vector<std::complex<double>> a(static_cast<std::size_t>(length));
    for (int n = 0; n < length; ++n) a[static_cast<std::size_t>(n)] = x[static_cast<std::size_t>(from + n)];
    fft_in_place(a);
    double e = 0.0;
    for (int k = 1; k < length / 2; ++k) {
        const double f = k * bin_rate / length;
        if (f >= f_lo && f < f_hi) e += std::norm(a[static_cast<std::size_t>(k)]);
    }
    return e;
}

// The lag (s) at which right best matches left: positive when the right ear hears it later. Peak of the
// cross-correlation of the two ears over +-1.5 ms, taken from their cross-spectrum L* R restricted to
// f < f_max (zero-padded to twice the length, so the correlation is linear, not circular), refined by a
// parabola through the peak and its neighbours. The band limit: the interaural time difference is a
// low-frequency cue (Wightman & Kistler 1992, JASA 91(3), "The dominant role of low-frequency interaural time
// differences in sound localization"), and an order-N decode reproduces the ears' signals only below
// N c / (2 pi r) (docs/binaural.md); above it, the far ear hears leakage from the virtual speakers on its
// own side first, and the broadband peak moves to ~0.1 ms (printed, not asserted).
double binaural_itd(const BinauralEars& e, int from, int length, double f_max) {
    const int n = 2 * length;
    std::vector<std::complex<double>> l(static_cast<std::size_t>(n)), r(static_cast<std::size_t>(n));
    for (int i = 0; i < length; ++i) {
        l[static_cast<std::size_t>(i)] = e.left[static_cast<std::size_t>(from + i)];
        r[static_cast<std::size_t>(i)] = e.right[static_cast<std::size_t>(from + i)];
    }
    fft_in_place(l);
    fft_in_place(r);
    std::vector<std::complex<double>> c(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) {
        const int folded = k <= n / 2 ? k : n - k;
        if (folded * bin_rate / n < f_max) c[static_cast<std::size_t>(k)] = std::conj(std::conj(l[static_cast<std::size_t>(k)]) * r[static_cast<std::size_t>(k)]);
    }
    fft_in_place(c);   // conj(FFT(conj(C))) is n times the inverse; only the peak's place matters
    const int max_lag = static_cast<int>(0.0015 * bin_rate);
    auto at = [&](int lag) { return c[static_cast<std::size_t>((lag + n) % n)].real(); };
    int peak = -max_lag;
    for (int lag = -max_lag; lag <= max_lag; ++lag)
        if (at(lag) > at(peak)) peak = lag;
    const double a = at(peak - 1), b = at(peak), cc = at(peak + 1);
    const double shift = (a - 2 * b + cc) != 0.0 ? 0.5 * (a - cc) / (a - 2 * b + cc) : 0.0;
    return (peak + shift) / bin_rate;
}

BinauralDecoder& binaural_decoder_for(int order, int block) {
    static std::vector<std::unique_ptr<BinauralDecoder>> kept;   // one decoder per (order, block) for the file
    for (auto& d : kept)
        if (d->order() == order && d->block_frames() == block) {
            d->reset();
            return *d;
        }
    auto made = BinauralDecoder::create(BinauralDecoder::default_sofa_path, order, bin_rate, block);
    INFO(made.error);
    REQUIRE(made.decoder);
    kept.push_back(std::move(made.decoder));
    return *kept.back();
}

constexpr int binaural_from = 4096;    // past the filters' start-up (their length is ~900 taps)
constexpr int binaural_length = 16384;
constexpr int binaural_noise_frames = binaural_from + binaural_length + 1024;

}  // namespace

TEST_CASE("binaural decoder: a plane wave from 90 degrees left, orders 1 and 3: louder and earlier at the left ear") {
    for (int order : {1, 3}) {
        auto& d = binaural_decoder_for(order, 256);
        const BinauralEars e = binaural_decode_noise(d, binaural_encode(order, 0.0, 1.0, 0.0), binaural_noise_frames, 256);
        // The head shadows the far ear above a few kHz: KEMAR's own pair at 90 degrees gives the left ear 12.4 dB
        // more than the right between 2 and 20 kHz (white noise, the same band energies); the issue asks more
        // than 6 dB of the decode (issue 21, section 2).
        const double ild = 10 * std::log10(binaural_band_energy(e.left, binaural_from, binaural_length, 2000, 20000) /
                                           binaural_band_energy(e.right, binaural_from, binaural_length, 2000, 20000));
        // Woodworth's ITD for a 0.0875 m head at 90 degrees, r (pi/2 + 1) / c = 0.66 ms; KEMAR's own pair gives
        // 0.71-0.77 ms below 1.5 kHz; the window is 0.5-0.8 ms. Measured below the order's crossover.
        const double itd = binaural_itd(e, binaural_from, binaural_length, d.crossover_hz());
        const double broadband_itd = binaural_itd(e, binaural_from, binaural_length, bin_rate);
        MESSAGE("order " << order << ": ILD above 2 kHz " << ild << " dB, ITD below " << d.crossover_hz() << " Hz "
                         << itd * 1e3 << " ms (broadband cross-correlation: " << broadband_itd * 1e3 << " ms)");
        CHECK(ild > 6.0);
        CHECK(itd > 0.5e-3);
        CHECK(itd < 0.8e-3);
    }
}

TEST_CASE("binaural decoder: a plane wave from the front, orders 1 and 3: ears within 1 dB and 0.1 ms") {
    for (int order : {1, 3}) {
        auto& d = binaural_decoder_for(order, 256);
        const BinauralEars e = binaural_decode_noise(d, binaural_encode(order, 1.0, 0.0, 0.0), binaural_noise_frames, 256);
        const double broadband = 10 * std::log10(binaural_band_energy(e.left, binaural_from, binaural_length, 20, 20000) /
                                                 binaural_band_energy(e.right, binaural_from, binaural_length, 20, 20000));
        const double high = 10 * std::log10(binaural_band_energy(e.left, binaural_from, binaural_length, 2000, 20000) /
                                             binaural_band_energy(e.right, binaural_from, binaural_length, 2000, 20000));
        const double itd = binaural_itd(e, binaural_from, binaural_length, d.crossover_hz());
        MESSAGE("order " << order << ": front, ear difference " << broadband << " dB (above 2 kHz " << high
                         << " dB), ITD " << itd * 1e3 << " ms");
        // The grid mirrors in y, and libmysofa's MIT KEMAR set is the normal pinna's measurements with the
        // right ear mirrored from the left (its SOFA conversion), so here the ears match to rounding; another
        // SOFA set would differ by the dummy's own asymmetry, which 1 dB allows.
        CHECK(std::abs(broadband) < 1.0);
        CHECK(std::abs(high) < 1.0);
        CHECK(std::abs(itd) < 0.1e-3);
    }
}

TEST_CASE("binaural decoder: a frontal plane wave keeps KEMAR's own spectrum within 5 dB per octave, orders 1 and 3") {
    // Without the diffuse-field equaliser the order-N decode loses 7-13 dB between 8 and 20 kHz at the front
    // (the high frequencies of the virtual speakers add with unrelated phases; Ben-Hur et al. 2017). The
    // equaliser corrects the average over all directions, not each one, and Ben-Hur et al. leave a few dB
    // per direction: 5 dB per octave band, which the unequalised decode fails above 4 kHz.
    int length = 0, err = 0;
    MYSOFA_EASY* sofa = mysofa_open_cached(BinauralDecoder::default_sofa_path, static_cast<float>(bin_rate), &length, &err);
    REQUIRE(sofa);
    std::vector<float> left(static_cast<std::size_t>(length)), right(static_cast<std::size_t>(length));
    float delay_left = 0, delay_right = 0;
    mysofa_getfilter_float_nointerp(sofa, 1.4f, 0.0f, 0.0f, left.data(), right.data(), &delay_left, &delay_right);
    mysofa_close_cached(sofa);
    const int n = 4096;
    auto octave = [&](const std::vector<float>& h, double lo) {
        std::vector<float> padded(static_cast<std::size_t>(n), 0.0f);
        std::copy(h.begin(), h.begin() + std::min<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(h.size()), n), padded.begin());
        return binaural_band_energy(padded, 0, n, lo, 2 * lo);
    };
    for (int order : {1, 3}) {
        auto& d = binaural_decoder_for(order, 256);
        const auto gains = binaural_encode(order, 1.0, 0.0, 0.0);
        std::vector<float> decoded(static_cast<std::size_t>(d.filter_frames()), 0.0f);
        for (int a = 0; a < d.channels(); ++a)
            for (std::size_t t = 0; t < decoded.size(); ++t)
                decoded[t] += static_cast<float>(gains[static_cast<std::size_t>(a)] * d.sh_filter(a, 0)[t]);
        for (double lo : {250.0, 500.0, 1000.0, 2000.0, 4000.0, 8000.0}) {
            const double db = 10 * std::log10(octave(decoded, lo) / octave(left, lo));
            INFO("order " << order << ", octave from " << lo << " Hz: " << db << " dB against KEMAR's frontal response");
            CHECK(std::abs(db) < 5.0);
        }
    }
}

TEST_CASE("binaural decoder: a plane wave from straight below, where KEMAR has no measurement: finite, ears equal") {
    // The set stops at -40 degrees; the grid's 9 lower speakers take the -40 degree responses at their azimuths
    // (docs/binaural.md). A source from below must still come out, finite, symmetric (the grid mirrors in y),
    // and without a time difference.
    auto& d = binaural_decoder_for(3, 256);
    const BinauralEars e = binaural_decode_noise(d, binaural_encode(3, 0.0, 0.0, -1.0), binaural_noise_frames, 256);
    double energy = 0.0;
    bool finite = true;
    for (std::size_t n = 0; n < e.left.size(); ++n) {
        finite = finite && std::isfinite(e.left[n]) && std::isfinite(e.right[n]);
        energy += double(e.left[n]) * e.left[n];
    }
    CHECK(finite);
    CHECK(energy > 0.0);
    const double ild = 10 * std::log10(binaural_band_energy(e.left, binaural_from, binaural_length, 20, 20000) /
                                       binaural_band_energy(e.right, binaural_from, binaural_length, 20, 20000));
    CHECK(std::abs(ild) < 1.0);
    CHECK(std::abs(binaural_itd(e, binaural_from, binaural_length, d.crossover_hz())) < 0.1e-3);
}

TEST_CASE("binaural decoder: blocks of 64, 256 and 1024 give direct convolution's samples within float rounding") {
    const int order = 3;
    const int frames = 4096;
    const auto gains = binaural_encode(order, 0.3, 0.8, std::sqrt(1 - 0.73));   // an oblique direction: every ACN nonzero
    auto& d64 = binaural_decoder_for(order, 64);
    const BinauralEars e64 = binaural_decode_noise(d64, gains, frames, 64, 9);
    // Direct convolution (double) of the same input with the decoder's combined filters.
    Random rng(9);
    std::vector<double> s(frames);
    for (auto& v : s) v = static_cast<float>(rng.uniform() - 0.5);
    std::vector<double> left(frames, 0.0), right(frames, 0.0);
    for (int a = 0; a < d64.channels(); ++a) {
        const float ga = static_cast<float>(gains[static_cast<std::size_t>(a)]);
        for (int ear = 0; ear < 2; ++ear) {
            const auto& h = d64.sh_filter(a, ear);
            auto& y = ear == 0 ? left : right;
            for (int n = 0; n < frames; ++n) {
                const double x = static_cast<float>(ga * static_cast<float>(s[static_cast<std::size_t>(n)]));
                for (std::size_t t = 0; t < h.size() && n + static_cast<int>(t) < frames; ++t) y[n + t] += x * h[t];
            }
        }
    }
    double peak = 0.0;
    for (double v : left) peak = std::max(peak, std::abs(v));
    for (int block : {64, 256, 1024}) {
        auto& d = binaural_decoder_for(order, block);
        const BinauralEars e = block == 64 ? e64 : binaural_decode_noise(d, gains, frames, block, 9);
        double err = 0.0;
        for (int n = 0; n < frames; ++n)
            err = std::max({err, std::abs(e.left[static_cast<std::size_t>(n)] - left[static_cast<std::size_t>(n)]),
                            std::abs(e.right[static_cast<std::size_t>(n)] - right[static_cast<std::size_t>(n)])});
        // Float FFTs of 2B points over 16 channels and ~900 taps: rounding ~1e-7 of the sum of |terms|;
        // 1e-5 of the peak bounds it with margin, and any misplaced partition would be of order the peak.
        INFO("block " << block << ": max error " << err << ", peak " << peak);
        CHECK(err < 1e-5 * peak);
        CHECK(d.rejected_blocks() == 0);
    }
}

TEST_CASE("binaural decoder: the SOFA file is resampled to the stream's rate, and bad requests get clear errors") {
    // MIT KEMAR is measured at 44.1 kHz, 512 taps: at 96 kHz libmysofa's responses have 1115 (its resampler
    // scales the length by the rate ratio), so the filters are longer than at 44.1 kHz by about that much.
    auto at44 = BinauralDecoder::create(BinauralDecoder::default_sofa_path, 1, 44100.0, 256);
    auto at96 = BinauralDecoder::create(BinauralDecoder::default_sofa_path, 1, 96000.0, 256);
    REQUIRE(at44.decoder);
    REQUIRE(at96.decoder);
    CHECK(at96.decoder->filter_frames() - at44.decoder->filter_frames() > 1115 - 512);

    auto missing = BinauralDecoder::create("/nonexistent/hrtf.sofa", 3, bin_rate, 256);
    CHECK(!missing.decoder);
    CHECK(missing.error.find("/nonexistent/hrtf.sofa") != std::string::npos);
    CHECK(missing.error.find("no such") != std::string::npos);

    test::TempDir dir("ameoto-binaural");
    const std::string text = (dir.path() / "not.sofa").string();
    std::ofstream(text) << "this is not an HDF5 file\n";
    auto wrong = BinauralDecoder::create(text, 3, bin_rate, 256);
    CHECK(!wrong.decoder);
    CHECK(wrong.error.find("not a SOFA file") != std::string::npos);
    auto folder = BinauralDecoder::create(dir.path().string(), 3, bin_rate, 256);
    CHECK(!folder.decoder);
    CHECK(folder.error.find("cannot be read") != std::string::npos);

    auto order4 = BinauralDecoder::create(BinauralDecoder::default_sofa_path, 4, bin_rate, 256);
    CHECK(order4.error.find("order 4") != std::string::npos);
    auto rate0 = BinauralDecoder::create(BinauralDecoder::default_sofa_path, 1, 0.0, 256);
    CHECK(rate0.error.find("sample rate") != std::string::npos);
    auto block0 = BinauralDecoder::create(BinauralDecoder::default_sofa_path, 1, bin_rate, 0);
    CHECK(block0.error.find("block") != std::string::npos);
}

TEST_CASE("binaural decoder: process never allocates, frees or locks (real-time audit)") {
    auto& d = binaural_decoder_for(3, 256);
    std::vector<std::vector<float>> bus(16, std::vector<float>(256, 0.25f));
    std::vector<const float*> in;
    for (auto& ch : bus) in.push_back(ch.data());
    std::vector<float> left(256), right(256);
    test::RtAudit audit;
    for (int block = 0; block < 8; ++block) {
        test::RtAudit::Scope scope;
        d.process(in.data(), 256, left.data(), right.data());
        if (block == 4) d.reset();
    }
    {
        test::RtAudit::Scope scope;
        d.process(in.data(), 100, left.data(), right.data());   // a wrong block: silence, counted
    }
    CHECK(audit.entries() > 0);
    INFO("first violation: " << audit.first());
    CHECK(audit.violations() == 0);
    CHECK(d.rejected_blocks() == 1);
    CHECK(left[0] == 0.0f);
}
