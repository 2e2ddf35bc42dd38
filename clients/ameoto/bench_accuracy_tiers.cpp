// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_accuracy_tiers.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "clients/ameoto/bench_timer.hpp"
#include "engine/core/fft.hpp"
#include "engine/render/renderer.hpp"

namespace ameoto::client {

namespace {

constexpr int block = 64;
constexpr double kPi = 3.14159265358979323846;
constexpr int welch_points = 16384;   // 2.9 Hz bins: the 25 Hz third-octave band (5.8 Hz wide) holds two
constexpr double band_floor_db = 60.0;

// The thresholds that put every rain drop in one tier (as bench scene forces them): full: every drop
// loud enough, the pool as large as it goes; template: none full, none texture; texture: every drop.
RendererConfig forced(LodTier tier, double rate_mm_per_h, std::uint64_t seed) {
    RendererConfig c;
    c.sample_rate = bench_sample_rate;
    c.channels = 2;
    c.seed = seed;
    c.rain_rate_mm_per_h = rate_mm_per_h;
    switch (tier) {
        case LodTier::full:
            c.lod_full_level_db = -1000.0;
            c.lod_texture_margin_db = 1000.0;   // bench scene keeps 20 dB here, which sends faint drops to texture
            c.full_drops = Renderer::max_full_drops;
            break;
        case LodTier::template_:
            c.lod_full_level_db = 1000.0;
            c.lod_texture_margin_db = 1000.0;
            c.full_drops = 0;
            break;
        case LodTier::texture:
            c.lod_full_level_db = 1000.0;
            c.lod_texture_margin_db = -1000.0;
            c.full_drops = 0;
            break;
    }
    return c;
}


// Welch's PSD (Hann window, half overlap), unnormalised: only ratios between renders are used.
std::vector<double> welch(const std::vector<float>& x) {
    std::vector<double> psd(welch_points / 2 + 1, 0.0);
    std::vector<double> window(welch_points);
    for (int i = 0; i < welch_points; ++i) window[static_cast<std::size_t>(i)] = 0.5 - 0.5 * std::cos(2 * kPi * i / welch_points);
    std::vector<std::complex<double>> a(welch_points);
    for (std::size_t start = 0; start + welch_points <= x.size(); start += welch_points / 2) {
        for (int i = 0; i < welch_points; ++i) a[static_cast<std::size_t>(i)] = x[start + static_cast<std::size_t>(i)] * window[static_cast<std::size_t>(i)];
        fft_in_place(a);
        for (std::size_t k = 0; k < psd.size(); ++k) psd[k] += std::norm(a[k]);
    }
    return psd;
}

double median_of(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace

const char* tier_name(LodTier tier) {
    switch (tier) {
        case LodTier::full: return "full";
        case LodTier::template_: return "template";
        case LodTier::texture: return "texture";
    }
    return "?";
}

TierRender render_tier(LodTier tier, double rate_mm_per_h, double seconds, std::uint64_t seed, double warm_s) {
    Renderer r(forced(tier, rate_mm_per_h, seed));
    TierRender out;
    std::vector<float> scratch_l(block), scratch_r(block);
    float* scratch[2] = {scratch_l.data(), scratch_r.data()};
    for (long b = 0; b < static_cast<long>(warm_s * bench_sample_rate / block); ++b) r.process(block, scratch);
    const LodCounts before = r.stats().rain_tiers;
    const long blocks = static_cast<long>(seconds * bench_sample_rate / block);
    out.left.resize(static_cast<std::size_t>(blocks * block));
    out.right.resize(out.left.size());
    const double start = thread_cpu_seconds();
    for (long b = 0; b < blocks; ++b) {
        float* channels[2] = {out.left.data() + b * block, out.right.data() + b * block};
        r.process(block, channels);
    }
    out.cpu_s = thread_cpu_seconds() - start;
    const LodCounts& after = r.stats().rain_tiers;
    out.full = after.full - before.full;
    out.template_ = after.template_ - before.template_;
    out.texture = after.texture - before.texture;
    out.drops = out.full + out.template_ + out.texture;
    return out;
}

BandSpectrum long_term_spectrum(const TierRender& render, double fs) {
    const std::vector<double> l = welch(render.left), r = welch(render.right);
    BandSpectrum s;
    for (int b = 0; b < third_octave_bands; ++b) {
        // Exact base-2 third octaves around 1 kHz: 24.8 Hz (k = -16) .. 20.2 kHz (k = 13).
        const double centre = 1000.0 * std::pow(2.0, (b - 16) / 3.0);
        const double lo = centre * std::pow(2.0, -1.0 / 6.0), hi = centre * std::pow(2.0, 1.0 / 6.0);
        s.centre_hz[static_cast<std::size_t>(b)] = centre;
        double p = 0.0;
        for (std::size_t k = 1; k < l.size(); ++k) {
            const double f = static_cast<double>(k) * fs / welch_points;
            if (f >= lo && f < hi) p += l[k] + r[k];
        }
        s.power[static_cast<std::size_t>(b)] = p;
    }
    return s;
}

double band_distance_db(const BandSpectrum& x, const BandSpectrum& reference) {
    const double loudest = *std::max_element(reference.power.begin(), reference.power.end());
    const double floor = loudest * std::pow(10.0, -band_floor_db / 10.0);
    double sum = 0.0;
    int n = 0;
    for (int b = 0; b < third_octave_bands; ++b) {
        const double p_ref = reference.power[static_cast<std::size_t>(b)];
        if (!(p_ref > floor)) continue;
        const double p = std::max(x.power[static_cast<std::size_t>(b)], floor);   // a lost band: large, finite
        const double d = 10.0 * std::log10(p / p_ref);
        sum += d * d;
        ++n;
    }
    return n > 0 ? std::sqrt(sum / n) : std::numeric_limits<double>::quiet_NaN();
}

double level_difference_db(const BandSpectrum& x, const BandSpectrum& reference) {
    double p = 0.0, p_ref = 0.0;
    for (int b = 0; b < third_octave_bands; ++b) {
        p += x.power[static_cast<std::size_t>(b)];
        p_ref += reference.power[static_cast<std::size_t>(b)];
    }
    return 10.0 * std::log10(p / p_ref);
}

double spectral_centroid_hz(const BandSpectrum& s) {
    double moment = 0.0, power = 0.0;
    for (int b = 0; b < third_octave_bands; ++b) {
        moment += s.centre_hz[static_cast<std::size_t>(b)] * s.power[static_cast<std::size_t>(b)];
        power += s.power[static_cast<std::size_t>(b)];
    }
    return moment / power;
}

std::vector<TierRow> measure_tiers(const TierOptions& o) {
    std::vector<TierRow> rows;
    const TierRender full = render_tier(LodTier::full, o.error_rate_mm_per_h, o.error_seconds, o.seed);
    const BandSpectrum reference = long_term_spectrum(full, bench_sample_rate);
    for (LodTier tier : {LodTier::full, LodTier::template_, LodTier::texture}) {
        TierRow row;
        row.name = tier_name(tier);
        const TierRender r = tier == LodTier::full ? full : render_tier(tier, o.error_rate_mm_per_h, o.error_seconds, o.seed);
        const BandSpectrum s = long_term_spectrum(r, bench_sample_rate);
        row.lsd_db = tier == LodTier::full ? 0.0 : band_distance_db(s, reference);
        row.level_db = tier == LodTier::full ? 0.0 : level_difference_db(s, reference);
        row.drops = r.full + r.template_ + r.texture;
        row.fallbacks = tier == LodTier::full ? r.template_ + r.texture : tier == LodTier::template_ ? r.full + r.texture : r.full + r.template_;
        // Cost as bench scene measures it: the tier's run against the dry scene's, in pairs (the
        // machine's load drifts), the tier's timed after a second of rain has built up (the rain's ramp,
        // the pool filling), the dry one after 0.2 s.
        // Full at the error run's rate: at bench scene's 0.3 mm/h (about 170 drops a second) the 64-drop
        // pool fills and the drops it cannot take play as templates, which would count as cheap lattice drops.
        row.rate_mm_per_h = tier == LodTier::full ? o.error_rate_mm_per_h : 200.0;
        std::vector<double> per_drop;
        for (int run = 0; run < o.runs; ++run) {
            const TierRender dry = render_tier(tier, 0.0, o.cost_seconds, o.seed, 0.2);
            const TierRender wet = render_tier(tier, row.rate_mm_per_h, o.cost_seconds, o.seed, 1.0);
            per_drop.push_back(wet.drops > 0 ? (wet.cpu_s - dry.cpu_s) / static_cast<double>(wet.drops) * 1e9 : 0.0);
            row.cost_fallbacks += wet.drops - (tier == LodTier::full ? wet.full : tier == LodTier::template_ ? wet.template_ : wet.texture);
        }
        row.ns_per_drop = median_of(per_drop);
        rows.push_back(row);
    }
    return rows;
}

}  // namespace ameoto::client
