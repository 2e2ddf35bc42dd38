// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/texture_grains.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <optional>

#include "engine/core/fft.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/models/drop.hpp"

namespace ameoto {

namespace {


// Linear interpolation in log D over an ascending grid, clamped at its ends.
double interpolate(const std::vector<double>& d, const std::vector<double>& v, double diameter) {
    if (diameter <= d.front()) return v.front();
    if (diameter >= d.back()) return v.back();
    const auto hi = static_cast<std::size_t>(std::upper_bound(d.begin(), d.end(), diameter) - d.begin());
    const double t = std::log(diameter / d[hi - 1]) / std::log(d[hi] / d[hi - 1]);
    return v[hi - 1] + t * (v[hi] - v[hi - 1]);
}


}  // namespace

// Energy spans decades (about D^8 here): interpolated in log E against log D.
double TextureCalibration::energy(double diameter_m) const { return std::exp(interpolate(diameters_m, log_energy, diameter_m)); }
double TextureCalibration::centre(double diameter_m) const { return interpolate(diameters_m, centre_hz, diameter_m); }
double TextureCalibration::decay(double diameter_m) const { return interpolate(diameters_m, decay_s, diameter_m); }

namespace {

TextureCalibration calibrate(const DropOnCanopyConfig& scene, const ImpactTemplateTable& templates, const Canopy* given,
                             CanopyBuild build) {
    TextureCalibration cal;
    cal.density = templates.density;
    DropOnCanopyConfig c = scene;
    c.output = SceneOutput::far_field;
    c.channels = 1;
    c.listener = ListenerStyle::panned;   // one point (an Ambisonic scene calibrates on the same mono)
    c.capacity = 1;
    const double fs = scene.sample_rate;
    const int frames = static_cast<int>(0.05 * fs);
    const double x = 0.5 * scene.geometry.radius_m, y = 0.0;
    // Each size's scene starts from the same canopy at rest: built once, copied per size (a copy of a
    // canopy never stepped is what its constructor builds: the same calibration bit for bit, tested).
    std::optional<Canopy> built;
    if (!given && build == CanopyBuild::shared && !templates.diameters_m.empty()) built.emplace(DropOnCanopy::fresh_canopy(c));
    const Canopy* prototype = given ? given : built ? &*built : nullptr;
    // With a prototype, each size's scene shares the first's push filters (the same canopy and point:
    // DipoleRadiation's sibling, the same bits), which were most of each scene's build in air.
    std::optional<DropOnCanopy> first, later;
    for (std::size_t k = 0; k < templates.diameters_m.size(); k += 5) {
        DropOnCanopy& run = !first ? (prototype ? first.emplace(c, *prototype) : first.emplace(c))
                                   : (prototype ? later.emplace(c, *prototype, *first) : later.emplace(c));
        TemplatePool pool;
        const CanopyHit hit = run.canopy().locate(x, y);
        const double d = templates.diameters_m[k];
        pool.add(hit, templates, d, templates.speeds_m_per_s[k], templates.density);
        std::vector<double> out(static_cast<std::size_t>(frames));
        float frame[1];
        for (int i = 0; i < frames; ++i) {
            pool.emit(templates, [&](CanopyHit h, double f) { run.surface().apply_force(h, f); });
            run.process_frame(frame);
            out[static_cast<std::size_t>(i)] = frame[0];
        }
        double energy = 0.0;
        for (double v : out) energy += v * v;
        // Decay: energy over the peak of the 1 ms power envelope (the length of a rectangle of that energy).
        const int window = std::max(1, static_cast<int>(0.001 * fs));
        double peak_power = 0.0, sum = 0.0;
        for (int i = 0; i < frames; ++i) {
            sum += out[static_cast<std::size_t>(i)] * out[static_cast<std::size_t>(i)];
            if (i >= window) sum -= out[static_cast<std::size_t>(i - window)] * out[static_cast<std::size_t>(i - window)];
            peak_power = std::max(peak_power, sum / window);
        }
        std::size_t n = 1;
        while (n < out.size()) n <<= 1;
        std::vector<std::complex<double>> spectrum(n);
        for (std::size_t i = 0; i < out.size(); ++i) spectrum[i] = out[i];
        fft_in_place(spectrum);
        double weighted = 0.0, total = 0.0;
        for (std::size_t b = 1; b < n / 2; ++b) {
            const double p = std::norm(spectrum[b]);
            weighted += p * fs * static_cast<double>(b) / static_cast<double>(n);
            total += p;
        }
        cal.diameters_m.push_back(d);
        cal.speeds_m_per_s.push_back(templates.speeds_m_per_s[k]);
        cal.energy_fs2.push_back(energy);
        cal.log_energy.push_back(std::log(std::max(energy, 1e-300)));
        cal.centre_hz.push_back(total > 0.0 ? weighted / total : 1000.0);
        cal.decay_s.push_back(peak_power > 0.0 ? std::clamp(energy / peak_power / fs, 1e-4, 0.5) : 1e-3);
    }
    return cal;
}

}  // namespace

TextureCalibration calibrate_texture(const DropOnCanopyConfig& scene, const ImpactTemplateTable& templates, CanopyBuild build) {
    return calibrate(scene, templates, nullptr, build);
}

TextureCalibration calibrate_texture(const DropOnCanopyConfig& scene, const ImpactTemplateTable& templates, const Canopy& prototype) {
    return calibrate(scene, templates, &prototype, CanopyBuild::shared);
}

TextureGrains::TextureGrains(const TextureCalibration& calibration, double sample_rate)
    : calibration_(&calibration), sample_rate_(sample_rate) {
    const double low = 150.0, high = std::min(16000.0, 0.4 * sample_rate);
    const double ratio = std::pow(high / low, 1.0 / (bands - 1));
    const double q = std::sqrt(ratio) / (ratio - 1.0);
    for (int k = 0; k < bands; ++k) {
        const double fc = low * std::pow(ratio, k);
        centre_[static_cast<std::size_t>(k)] = fc;
        const double w0 = 2.0 * constants::pi * fc / sample_rate;
        const double alpha = std::sin(w0) / (2.0 * q);
        const double a0 = 1.0 + alpha;
        for (auto& channel : bed_) {
            Band& b = channel[static_cast<std::size_t>(k)];
            b.b0 = alpha / a0;
            b.b2 = -alpha / a0;
            b.a1 = -2.0 * std::cos(w0) / a0;
            b.a2 = (1.0 - alpha) / a0;
        }
        unit_[static_cast<std::size_t>(k)] = 1.0 / std::sqrt(alpha / a0 / 3.0);   // uniform noise has variance 1/3
        // The power centroid of white noise through it: sum of f |H(f)|^2 over sum of |H(f)|^2, on a grid
        // of 8192 frequencies 0..fs/2 (the response is smooth on it: its narrowest band is 1/Q of an
        // octave wide, over 100 grid points at 150 Hz and 48 kHz).
        const Band& b = bed_[0][static_cast<std::size_t>(k)];
        double weighted = 0.0, total = 0.0;
        constexpr int grid = 8192;
        for (int i = 1; i < grid; ++i) {
            const double w = constants::pi * i / grid;
            const std::complex<double> z1 = std::polar(1.0, -w), z2 = z1 * z1;
            const double h2 = std::norm((b.b0 + b.b2 * z2) / (1.0 + b.a1 * z1 + b.a2 * z2));
            weighted += h2 * (0.5 * sample_rate * i / grid);
            total += h2;
        }
        power_centre_[static_cast<std::size_t>(k)] = weighted / total;
    }
    set_calibration(calibration);
}

void TextureGrains::set_calibration(const TextureCalibration& calibration) {
    calibration_ = &calibration;
    if (calibration.empty()) return;
    // Each band decays as the calibrated sizes whose centroids are nearest it (interpolated in log f).
    double longest = 0.0;
    for (int k = 0; k < bands; ++k) {
        const double f = centre_[static_cast<std::size_t>(k)];
        std::size_t best = 0;
        for (std::size_t i = 1; i < calibration.centre_hz.size(); ++i)
            if (std::abs(std::log(calibration.centre_hz[i] / f)) < std::abs(std::log(calibration.centre_hz[best] / f))) best = i;
        const double tau = calibration.decay_s[best];
        longest = std::max(longest, tau);
        const double d = std::exp(-1.0 / (tau * sample_rate_));
        decay_[static_cast<std::size_t>(k)] = d * d;
    }
    // The ring of recent additions spans 5 of the longest decay: sized once, at construction (a later
    // calibration, set on the audio thread, keeps it: no allocation there).
    const auto slots = static_cast<std::size_t>(std::ceil(5.0 * longest * sample_rate_ / slot_samples)) + 1;
    if (added_.empty()) added_.assign(std::max<std::size_t>(slots, 64), 0);
}

bool TextureGrains::add(double diameter_m, double speed_m_per_s, double density, double azimuth_rad, int channels, Random& rng) {
    (void)rng;
    const TextureCalibration& cal = *calibration_;
    if (cal.empty()) return false;
    const double speed = speed_m_per_s > 0.0 ? speed_m_per_s : arrival_speed(diameter_m, density);
    // The calibrated energy at this size (a drop of the recorded liquid at its arrival speed), times the
    // template's gain squared for another liquid or speed (force ~ rho V^2 D^2).
    const double vr = speed / arrival_speed(diameter_m, cal.density), rr = density / cal.density;
    const double energy = cal.energy(diameter_m) * rr * rr * vr * vr * vr * vr;
    // The two bands whose outputs' power centroids lie around f_c, split linearly in f: the bed's
    // expected power centroid is then f_c (the header).
    const double fc = std::clamp(cal.centre(diameter_m), power_centre_.front(), power_centre_.back());
    int lo = 0;
    while (lo < bands - 2 && power_centre_[static_cast<std::size_t>(lo + 1)] < fc) ++lo;
    const double c0 = power_centre_[static_cast<std::size_t>(lo)], c1 = power_centre_[static_cast<std::size_t>(lo + 1)];
    const double t = std::clamp((fc - c0) / (c1 - c0), 0.0, 1.0);
    const auto pan = pan_gains(azimuth_rad, channels);
    for (int c = 0; c < channels; ++c) {
        const double g2 = pan[static_cast<std::size_t>(c)] * pan[static_cast<std::size_t>(c)];
        auto& channel = bed_[static_cast<std::size_t>(c)];
        channel[static_cast<std::size_t>(lo)].power += (1.0 - t) * energy * g2 * (1.0 - decay_[static_cast<std::size_t>(lo)]);
        channel[static_cast<std::size_t>(lo + 1)].power += t * energy * g2 * (1.0 - decay_[static_cast<std::size_t>(lo + 1)]);
    }
    ++added_[static_cast<std::size_t>(slot_)];
    ++active_;
    return true;
}

void TextureGrains::render(float* frame, int channels, Random& rng) {
    for (int c = 0; c < channels; ++c) {
        auto& channel = bed_[static_cast<std::size_t>(c)];
        double sum = 0.0;
        for (int k = 0; k < bands; ++k) {
            Band& b = channel[static_cast<std::size_t>(k)];
            if (b.power < 1e-30) {
                b.power = 0.0;   // silent: nothing to add (and no denormals); the filter keeps its state
                continue;
            }
            const double x = 2.0 * rng.uniform() - 1.0;
            const double y = b.b0 * x + b.b2 * b.x2 - b.a1 * b.y1 - b.a2 * b.y2;
            b.x2 = b.x1;
            b.x1 = x;
            b.y2 = b.y1;
            b.y1 = y;
            sum += std::sqrt(b.power) * unit_[static_cast<std::size_t>(k)] * y;
            b.power *= decay_[static_cast<std::size_t>(k)];
        }
        frame[c] += static_cast<float>(sum);
    }
    if (++in_slot_ == slot_samples) {
        in_slot_ = 0;
        slot_ = (slot_ + 1) % static_cast<int>(added_.size());
        active_ -= added_[static_cast<std::size_t>(slot_)];   // the oldest slot leaves the window
        added_[static_cast<std::size_t>(slot_)] = 0;
    }
}

}  // namespace ameoto
