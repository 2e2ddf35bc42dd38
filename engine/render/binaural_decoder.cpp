// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/binaural_decoder.hpp"

#include <mysofa.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <sys/stat.h>

#include "engine/core/fft.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/render/binaural_design.hpp"

namespace ameoto {

namespace {

constexpr double binaural_min_rate_hz = 8000.0, binaural_max_rate_hz = 384000.0;
constexpr int binaural_max_block = 8192;
// The crossover's responses are cut where both stay under 1e-6 of their peak (-120 dB, below float's
// resolution of a full-scale sample).
constexpr double binaural_crossover_tail_eps = 1e-6;
// The diffuse-field equaliser: its boost or cut is capped at 15 dB (order 1 needs about 12 dB at 10 kHz with
// KEMAR) and its minimum-phase response is cut to 5 ms (240 taps at 48 kHz; third-octave detail above
// 200 Hz needs about 1 / (0.23 f), 22 ms at 200 Hz, but the correction there is near 0 dB).
constexpr double diffuse_eq_max_db = 15.0;
constexpr double diffuse_eq_seconds = 0.005;

std::string sofa_number_text(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

std::string mysofa_reason(int err) {
    switch (err) {
    case MYSOFA_INVALID_FORMAT: return "not a SOFA file (not HDF5 / netCDF-4 with SOFA's variables)";
    case MYSOFA_UNSUPPORTED_FORMAT: return "a SOFA convention libmysofa does not read";
    case MYSOFA_NO_MEMORY: return "out of memory reading it";
    case MYSOFA_READ_ERROR: return "read error";
    case MYSOFA_INVALID_ATTRIBUTES: return "SOFA attributes missing or invalid";
    case MYSOFA_INVALID_DIMENSIONS: return "SOFA dimensions invalid";
    case MYSOFA_INVALID_DIMENSION_LIST: return "SOFA dimension list invalid";
    case MYSOFA_INVALID_COORDINATE_TYPE: return "SOFA coordinate type invalid";
    case MYSOFA_ONLY_EMITTER_WITH_ECI_SUPPORTED: return "only one emitter per measurement is supported";
    case MYSOFA_ONLY_DELAYS_WITH_IR_OR_MR_SUPPORTED: return "delays only with dimensions IR or MR are supported";
    case MYSOFA_ONLY_THE_SAME_SAMPLING_RATE_SUPPORTED: return "one sampling rate for all measurements is required";
    case MYSOFA_RECEIVERS_WITH_RCI_SUPPORTED: return "receivers must be RCI (two ears)";
    case MYSOFA_RECEIVERS_WITH_CARTESIAN_SUPPORTED: return "receiver positions must be cartesian";
    case MYSOFA_INVALID_RECEIVER_POSITIONS: return "receiver positions invalid (not two ears on the y axis)";
    case MYSOFA_ONLY_SOURCES_WITH_MC_SUPPORTED: return "source positions must be MC";
    default: return "libmysofa error " + std::to_string(err);
    }
}

struct SofaCloser {
    void operator()(MYSOFA_EASY* e) const { mysofa_close_cached(e); }
};

// libmysofa's cache (mysofa_open_cached) is a global list without a lock of its own: every use here holds
// this one. The cache keeps each (file, rate) set opened, resampled, for the process's life (the default set
// at 48 kHz: 710 x 2 x 558 floats, 3 MB), because resampling it takes seconds (speex, 1420 responses) and a
// stream restart or a test's second decoder should not pay it again. A file changed on disk under the same
// path is therefore not read again until the program restarts.
std::mutex& sofa_cache_mutex() {
    static std::mutex* const m = new std::mutex;   // never destroyed (as fftw_planner_mutex)
    return *m;
}

}  // namespace

BinauralDecoder::Made BinauralDecoder::create(const std::string& sofa_path, int order, double rate_hz,
                                              int block_frames) {
    Made made;
    if (order < min_order || order > max_order) {
        made.error = "binaural decoder: order " + std::to_string(order) + " (1..3)";
        return made;
    }
    if (!std::isfinite(rate_hz) || rate_hz < binaural_min_rate_hz || rate_hz > binaural_max_rate_hz) {
        made.error = "binaural decoder: sample rate " + sofa_number_text(rate_hz) + " Hz (" + sofa_number_text(binaural_min_rate_hz) + ".." +
                     sofa_number_text(binaural_max_rate_hz) + ")";
        return made;
    }
    if (block_frames < 1 || block_frames > binaural_max_block) {
        made.error = "binaural decoder: block of " + std::to_string(block_frames) + " frames (1.." +
                     std::to_string(binaural_max_block) + ")";
        return made;
    }
    // libmysofa reports a missing file as errno; say it in words, before it is asked.
    struct stat info{};
    if (sofa_path.empty() || ::stat(sofa_path.c_str(), &info) != 0) {
        made.error = sofa_path + ": no such HRTF file (a SOFA file, e.g. " + default_sofa_path + " from libmysofa1)";
        return made;
    }
    if (!S_ISREG(info.st_mode) || !std::ifstream(sofa_path).good()) {
        made.error = sofa_path + ": cannot be read as a file";
        return made;
    }

    const std::lock_guard<std::mutex> cache_lock(sofa_cache_mutex());
    // mysofa_open (through its cache): load, check the SOFA conventions, resample every response to rate_hz (speex resampler),
    // scale the set by one factor set on a frontal reference (mysofa_loudness), positions to cartesian.
    int filter_length = 0, err = 0;
    std::unique_ptr<MYSOFA_EASY, SofaCloser> sofa(
        mysofa_open_cached(sofa_path.c_str(), static_cast<float>(rate_hz), &filter_length, &err));
    if (!sofa || err != MYSOFA_OK) {
        made.error = sofa_path + ": " + mysofa_reason(err);
        return made;
    }
    const MYSOFA_HRTF* hrtf = sofa->hrtf;
    if (!hrtf || hrtf->DataSamplingRate.elements < 1 ||
        std::abs(hrtf->DataSamplingRate.values[0] - rate_hz) > 0.5) {
        made.error = sofa_path + ": libmysofa gave responses at " +
                     (hrtf && hrtf->DataSamplingRate.elements ? sofa_number_text(hrtf->DataSamplingRate.values[0]) : std::string("?")) +
                     " Hz, not the stream's " + sofa_number_text(rate_hz) + " Hz";
        return made;
    }
    if (hrtf->R != 2 || filter_length < 1 || hrtf->M < 1) {
        made.error = sofa_path + ": " + std::to_string(hrtf->R) + " receivers, " + std::to_string(hrtf->M) +
                     " measurements of " + std::to_string(filter_length) + " samples (two ears and responses needed)";
        return made;
    }

    // The lowest measured elevation and the mean measurement radius (positions are cartesian now).
    double lowest = 90.0, radius = 0.0;
    for (unsigned i = 0; i < hrtf->M; ++i) {
        const float* p = &hrtf->SourcePosition.values[3 * i];
        const double r = std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]);
        radius += r;
        if (r > 0) lowest = std::min(lowest, std::asin(std::clamp(p[2] / r, -1.0, 1.0)) * 180.0 / constants::pi);
    }
    radius /= hrtf->M;

    const auto grid = binaural_design::lebedev_50();
    const int channels = (order + 1) * (order + 1);
    const auto L = static_cast<std::size_t>(filter_length);
    std::vector<float> ir_left(L), ir_right(L);
    struct Pair {
        std::vector<float> ear[2];
        int delay[2];
    };
    std::vector<Pair> pairs(grid.size());
    int longest_delay = 0;
    for (std::size_t i = 0; i < grid.size(); ++i) {
        double x = grid[i].x, y = grid[i].y, z = grid[i].z;
        double elevation = std::asin(std::clamp(z, -1.0, 1.0)) * 180.0 / constants::pi;
        if (elevation < lowest) {   // unmeasured: the same azimuth at the lowest measured elevation
            const double azimuth = std::hypot(x, y) > 1e-9 ? std::atan2(y, x) : 0.0;
            elevation = lowest * constants::pi / 180.0;
            x = std::cos(elevation) * std::cos(azimuth);
            y = std::cos(elevation) * std::sin(azimuth);
            z = std::sin(elevation);
        }
        float delay_left = 0.0f, delay_right = 0.0f;
        mysofa_getfilter_float_nointerp(sofa.get(), static_cast<float>(x * radius), static_cast<float>(y * radius),
                                        static_cast<float>(z * radius), ir_left.data(), ir_right.data(),
                                        &delay_left, &delay_right);
        const float delays[2] = {delay_left, delay_right};
        for (int e = 0; e < 2; ++e) {
            if (!std::isfinite(delays[e]) || delays[e] < 0.0f || delays[e] > 0.1f) {
                made.error = sofa_path + ": a delay of " + sofa_number_text(delays[e]) + " s (0..0.1 s expected)";
                return made;
            }
            pairs[i].delay[e] = static_cast<int>(std::lround(delays[e] * rate_hz));
            longest_delay = std::max(longest_delay, pairs[i].delay[e]);
        }
        pairs[i].ear[0] = ir_left;
        pairs[i].ear[1] = ir_right;
        for (int e = 0; e < 2; ++e)
            for (float v : pairs[i].ear[e])
                if (!std::isfinite(v)) {
                    made.error = sofa_path + ": a response holds a value that is not a finite number";
                    return made;
                }
    }

    // The basic (g_n = 1) sampling decode folded into the responses, per ACN and ear, in double.
    const std::size_t basic_length = L + static_cast<std::size_t>(longest_delay);
    const double crossover = order * constants::speed_of_sound_air / (2.0 * constants::pi * head_radius_m);
    const auto tail = static_cast<std::size_t>(binaural_design::linkwitz_riley_4_tail(crossover, rate_hz, binaural_crossover_tail_eps));
    const std::size_t length = basic_length + tail;
    std::vector<double> sh(static_cast<std::size_t>(channels));
    std::vector<std::vector<std::vector<double>>> basic(
        static_cast<std::size_t>(channels), std::vector<std::vector<double>>(2, std::vector<double>(length, 0.0)));
    for (std::size_t i = 0; i < grid.size(); ++i) {
        binaural_design::ambix_sn3d(order, grid[i].x, grid[i].y, grid[i].z, sh.data());
        for (int a = 0; a < channels; ++a) {
            const int n = static_cast<int>(std::sqrt(static_cast<double>(a)) + 1e-9);
            const double gain = grid[i].weight * (2.0 * n + 1.0) * sh[static_cast<std::size_t>(a)];
            for (int e = 0; e < 2; ++e) {
                auto& f = basic[static_cast<std::size_t>(a)][static_cast<std::size_t>(e)];
                const auto& h = pairs[i].ear[e];
                const auto d = static_cast<std::size_t>(pairs[i].delay[e]);
                for (std::size_t t = 0; t < L; ++t) f[t + d] += gain * h[t];
            }
        }
    }

    // Two bands per order: LP + g_n HP (basic below the crossover, max-rE above).
    const auto g = binaural_design::max_re_weights(order);
    std::vector<std::vector<std::vector<double>>> combined(static_cast<std::size_t>(channels),
                                                           std::vector<std::vector<double>>(2));
    std::vector<double> lp, hp;
    for (int a = 0; a < channels; ++a) {
        const int n = static_cast<int>(std::sqrt(static_cast<double>(a)) + 1e-9);
        for (int e = 0; e < 2; ++e) {
            binaural_design::linkwitz_riley_4(basic[static_cast<std::size_t>(a)][static_cast<std::size_t>(e)],
                                              crossover, rate_hz, lp, hp);
            auto& out = combined[static_cast<std::size_t>(a)][static_cast<std::size_t>(e)];
            out.resize(length);
            for (std::size_t t = 0; t < length; ++t) out[t] = lp[t] + g[static_cast<std::size_t>(n)] * hp[t];
        }
    }

    // Diffuse-field equalisation (Ben-Hur, Brinkmann, Sheaffer, Weinzierl & Rafaely 2017, JASA 141(6),
    // "Spectral equalization in binaural signals represented by order-truncated spherical harmonics"): an
    // order-N decode loses high frequencies, because above N c / (2 pi r) the virtual speakers' responses add
    // with unrelated phases. In a diffuse field (plane waves of unit power from everywhere, E[b_a b_a'] =
    // delta / (2n+1) in SN3D) the decoded ears have power sum_a |F_a|^2 / (2n+1); the measured set has
    // sum_i w_i |H_i|^2 over the same grid. One minimum-phase filter, the same for both ears (so the ears'
    // level and time differences stay as they are), takes the first to the second, summed over both ears,
    // smoothed over a third of an octave and its boost capped at diffuse_eq_max_db.
    const std::size_t K = [&] { std::size_t k = 1; while (k < 4 * length) k *= 2; return k; }();
    const std::size_t half = K / 2;
    std::vector<double> decoded_power(half + 1, 0.0), measured_power(half + 1, 0.0);
    std::vector<std::complex<double>> spectrum(K);
    auto add_power = [&](const auto& taps, std::size_t shift, double weight, std::vector<double>& power) {
        std::fill(spectrum.begin(), spectrum.end(), std::complex<double>(0.0, 0.0));
        for (std::size_t t = 0; t < taps.size() && t + shift < K; ++t) spectrum[t + shift] = taps[t];
        fft_in_place(spectrum);
        for (std::size_t k = 0; k <= half; ++k) power[k] += weight * std::norm(spectrum[k]);
    };
    for (int a = 0; a < channels; ++a) {
        const int n = static_cast<int>(std::sqrt(static_cast<double>(a)) + 1e-9);
        for (int e = 0; e < 2; ++e)
            add_power(combined[static_cast<std::size_t>(a)][static_cast<std::size_t>(e)], 0, 1.0 / (2.0 * n + 1.0), decoded_power);
    }
    for (std::size_t i = 0; i < grid.size(); ++i)
        for (int e = 0; e < 2; ++e)
            add_power(pairs[i].ear[e], static_cast<std::size_t>(pairs[i].delay[e]), grid[i].weight, measured_power);
    std::vector<double> eq(half + 1);
    const double max_gain = std::pow(10.0, diffuse_eq_max_db / 20.0);
    for (std::size_t k = 0; k <= half; ++k) {
        // Third-octave smoothing: the powers' means over f / 2^(1/6) .. f 2^(1/6) (at least one bin).
        const double f = std::max(static_cast<double>(k), 1.0);
        const auto lo = static_cast<std::size_t>(std::floor(f / std::pow(2.0, 1.0 / 6.0)));
        const auto hi = std::min(half, static_cast<std::size_t>(std::ceil(f * std::pow(2.0, 1.0 / 6.0))));
        double dec = 0.0, mea = 0.0;
        for (std::size_t j = lo; j <= hi; ++j) {
            dec += decoded_power[j];
            mea += measured_power[j];
        }
        eq[k] = dec > 0.0 && mea > 0.0 ? std::clamp(std::sqrt(mea / dec), 1.0 / max_gain, max_gain) : 1.0;
    }
    const int eq_taps = static_cast<int>(std::min<std::size_t>(K, static_cast<std::size_t>(std::lround(diffuse_eq_seconds * rate_hz))));
    const auto equaliser = binaural_design::minimum_phase_fir(eq, eq_taps);
    const std::size_t final_length = length + equaliser.size() - 1;

    std::unique_ptr<BinauralDecoder> decoder(new BinauralDecoder());
    decoder->order_ = order;
    decoder->rate_hz_ = rate_hz;
    decoder->filter_frames_ = static_cast<int>(final_length);
    decoder->crossover_hz_ = crossover;
    decoder->filters_.assign(static_cast<std::size_t>(channels), std::vector<std::vector<float>>(2));
    for (int a = 0; a < channels; ++a)
        for (int e = 0; e < 2; ++e) {
            const auto& f = combined[static_cast<std::size_t>(a)][static_cast<std::size_t>(e)];
            std::vector<double> y(final_length, 0.0);
            for (std::size_t t = 0; t < f.size(); ++t)
                for (std::size_t u = 0; u < equaliser.size(); ++u) y[t + u] += f[t] * equaliser[u];
            auto& out = decoder->filters_[static_cast<std::size_t>(a)][static_cast<std::size_t>(e)];
            out.resize(final_length);
            for (std::size_t t = 0; t < final_length; ++t) {
                out[t] = static_cast<float>(y[t]);
                if (!std::isfinite(out[t])) {
                    made.error = sofa_path + ": the combined filters are not finite (a response out of range?)";
                    return made;
                }
            }
        }
    try {
        decoder->convolver_ = std::make_unique<PartitionedConvolver>(channels, 2, block_frames, decoder->filters_);
    } catch (const std::exception& e) {
        made.error = std::string("binaural decoder: ") + e.what();
        return made;
    }
    made.decoder = std::move(decoder);
    return made;
}

void BinauralDecoder::process(const float* const* ambix, int frames, float* left, float* right) {
    if (frames != convolver_->block_frames()) {
        ++rejected_blocks_;
        std::fill(left, left + std::max(frames, 0), 0.0f);
        std::fill(right, right + std::max(frames, 0), 0.0f);
        return;
    }
    float* const out[2] = {left, right};
    convolver_->process(ambix, out);
}

void BinauralDecoder::reset() { convolver_->reset(); }

}  // namespace ameoto
