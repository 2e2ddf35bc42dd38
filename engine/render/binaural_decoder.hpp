// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The binaural decoder: an AmbiX bus (ACN channel order, SN3D normalisation, no Condon-Shortley phase) of
// order 1..3 to two ears, through head-related impulse responses measured on a dummy head and read from a
// SOFA file (AES69) with libmysofa. docs/binaural.md says what it approximates and why.
//
// Interface:
//   control thread, when the stream starts:
//     auto made = BinauralDecoder::create(BinauralDecoder::default_sofa_path, order, rate_hz, block_frames);
//     if (!made.decoder) report(made.error);   // the file, what is wrong with it, and what was asked
//   audio thread:
//     decoder.process(ambix, frames, left, right);   // ambix[acn][0..frames), acn 0..channels()-1;
//                                                    // frames must equal block_frames() (else: silence out,
//                                                    // rejected_blocks() counts it)
//     decoder.reset();                               // forget the past (e.g. after a stream restart)
//   any thread: order(), channels(), rate_hz(), block_frames(), filter_frames(), crossover_hz(),
//     sh_filter(acn, ear) (the combined filter's taps, for tests and benchmarks)
//   The destructor, like create, runs off the audio thread (it frees, and takes FFTW's planner lock).
//   create may run on several threads at once (it serialises libmysofa and FFTW's planner itself). It takes
//   seconds the first time a file is opened at a rate (libmysofa resamples the whole set), 0.2-0.4 s after
//   (the design alone): the resampled set stays in libmysofa's cache for the process's life.
// process() and reset() never allocate, free, lock, block or log (tests/engine/render/binaural_decoder_test.cpp
// checks them with the real-time probe). A change of JACK's block size means a new decoder, built off the
// audio thread like the first.
//
// Method (everything below runs in create; the audio thread only convolves):
// 1. Virtual loudspeakers: the 50-point Lebedev grid (Lebedev & Laikov 1999), a quadrature rule exact for
//    polynomials on the sphere up to degree 11. The sampling (projection) decoder needs exactness to degree
//    2N = 6 for order 3 so that the speakers reproduce every spherical harmonic exactly (the decoder is then
//    also the mode-matching pseudo-inverse: D^T diag(w) Y = I); the margin to 11 keeps HRTF directional
//    detail up to degree 8 from aliasing into orders 0..3. Fewer points (26, degree 7) would meet the decode
//    but alias more; a t-design or Fliege set of similar size would do as well; Lebedev has tabulated weights
//    and octahedral symmetry (left/right mirror pairs: the decode itself favours neither ear).
// 2. Each speaker's HRIR pair: libmysofa's nearest measured direction (mysofa_getfilter_float_nointerp; the
//    interpolating lookup averages neighbours' impulse responses, which smears their onsets and comb-filters).
//    The SOFA set's own delays (Data.Delay) are applied, rounded to the sample. Directions below the lowest
//    measured elevation (KEMAR: -40 degrees) take the response at that elevation and the same azimuth
//    (the pole straight below: azimuth 0): a sound from below is heard from -40 degrees.
// 3. Decoder: the sampling decoder s_i = w_i sum_acn (2n+1) g_n(f) Y_acn(u_i) b_acn (SN3D input, so the
//    (2n+1) turns it into N3D's projection; Zotter & Frank 2019, "Ambisonics", Springer, ch. 4),
//    with per-order weights g_n(f) in two bands (Heller, Lee & Benjamin 2008, "Is my decoder Ambisonic?",
//    AES 125th convention): below crossover_hz() = N c / (2 pi r) (r = 0.0875 m; 624 Hz at order 1, 1872 Hz
//    at order 3), the basic decode g_n = 1, exact at the ears there; above it, max-rE weights
//    g_n = P_n(cos(137.9 deg / (N + 1.51))) (Zotter & Frank 2012, "All-round ambisonic panning and
//    decoding", JAES 60(10), eq. 10) scaled to keep the diffuse-field energy sum (2n+1) g_n^2 = (N+1)^2.
//    The bands are a 4th-order Linkwitz-Riley pair LP + HP, applied per order as LP + g_n HP: every order
//    gets the same all-pass phase (LR4's LP and HP are in phase), so the orders stay aligned (Heller's
//    phase-matched shelf filters).
// 4. Decode and HRIR convolution are linear, so they are combined into (N+1)^2 filters per ear:
//    F_acn,ear = E * W_n * sum_i w_i (2n+1) Y_acn(u_i) h_i,ear, where E is a diffuse-field equaliser (Ben-Hur
//    et al. 2017, JASA 141(6)): one minimum-phase filter for both ears (so level and time differences are
//    kept) that gives the decode's diffuse-field power, sum_acn |F|^2 / (2n+1), the measured set's, sum_i
//    w_i |H_i|^2, smoothed over third octaves and capped at +-15 dB: without it an order-N decode loses
//    7-13 dB above 8 kHz. The audio thread runs 2 (N+1)^2 convolutions
//    (engine/render/partitioned_convolver.hpp, uniformly partitioned overlap-save on FFTW, blocks of
//    block_frames: no latency beyond the filters', deterministic, no threads of its own) and sums per ear.
//    zita-convolver was left out: its later partitions run in threads of its own, which without real-time
//    rights can lag behind the audio thread, and an offline render (faster than real time) would need its
//    blocking synchronous mode; the filters here are short (558 taps at 48 kHz, the crossover's tail and
//    the equaliser's 240 taps: 889 to 1034), so one uniform partitioning costs little (docs/binaural.md).

#include <memory>
#include <string>
#include <vector>

#include "engine/render/partitioned_convolver.hpp"

namespace ameoto {

class BinauralDecoder {
public:
    static constexpr const char* default_sofa_path = "/usr/share/libmysofa/default.sofa";
    static constexpr int min_order = 1, max_order = 3;
    static constexpr double head_radius_m = 0.0875;   // the common spherical head (Brown & Duda 1998), for the crossover

    struct Made {
        std::unique_ptr<BinauralDecoder> decoder;   // null on error
        std::string error;                          // why, naming the file and the request
    };
    static Made create(const std::string& sofa_path, int order, double rate_hz, int block_frames);

    void process(const float* const* ambix, int frames, float* left, float* right);
    void reset();

    int order() const { return order_; }
    int channels() const { return (order_ + 1) * (order_ + 1); }
    double rate_hz() const { return rate_hz_; }
    int block_frames() const { return convolver_->block_frames(); }
    int filter_frames() const { return filter_frames_; }
    double crossover_hz() const { return crossover_hz_; }
    unsigned long rejected_blocks() const { return rejected_blocks_; }
    const std::vector<float>& sh_filter(int acn, int ear) const {   // ear 0 left, 1 right
        return filters_[static_cast<std::size_t>(acn)][static_cast<std::size_t>(ear)];
    }

private:
    BinauralDecoder() = default;

    int order_ = 1;
    double rate_hz_ = 48000.0;
    int filter_frames_ = 0;
    double crossover_hz_ = 0.0;
    unsigned long rejected_blocks_ = 0;
    std::vector<std::vector<std::vector<float>>> filters_;   // [acn][ear][tap]
    std::unique_ptr<PartitionedConvolver> convolver_;
};

}  // namespace ameoto
