// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/water_surface.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "engine/core/physical_constants.hpp"
#include "engine/models/impact_force.hpp"

namespace ameoto {

namespace {

bool finite_positive(double x) { return std::isfinite(x) && x > 0.0; }

}  // namespace

SplashClass splash_class(double diameter_m) {
    using namespace entrainment;
    if (!(diameter_m >= small_min_m)) return SplashClass::tiny;   // also NaN
    if (diameter_m <= small_max_m) return SplashClass::small;
    if (diameter_m <= medium_max_m) return SplashClass::medium;
    return SplashClass::large;
}

double entrainment_probability(double diameter_m) {
    using namespace entrainment;
    switch (splash_class(diameter_m)) {
        case SplashClass::tiny: return 0.0;
        case SplashClass::small: return small_probability;
        case SplashClass::medium: return medium_probability;
        case SplashClass::large: {
            const double s = std::clamp((diameter_m - medium_max_m) / (large_probability_full_m - medium_max_m), 0.0, 1.0);
            return large_probability_min + (large_probability_max - large_probability_min) * s;
        }
    }
    return 0.0;
}

Entrainment draw_entrainment(double diameter_m, Random& rng) {
    using namespace entrainment;
    const double u_trap = rng.uniform();
    const double u_size = rng.uniform();
    Entrainment e;
    if (!finite_positive(diameter_m)) return e;
    e.splash = splash_class(diameter_m);
    if (!(u_trap < entrainment_probability(diameter_m))) return e;
    e.bubble = true;
    if (e.splash == SplashClass::small) {
        // log-linear across the band, then a uniform scatter in ln a.
        const double s = (diameter_m - small_min_m) / (small_max_m - small_min_m);
        const double ln_a = (1.0 - s) * std::log(small_radius_at_min_m) + s * std::log(small_radius_at_max_m);
        e.radius_m = std::exp(ln_a + small_scatter * (2.0 * u_size - 1.0));
    } else {
        // log-uniform in [0.1 mm, D / 4] (D > 1.1 mm here, so D / 4 > 0.1 mm).
        const double hi = irregular_radius_per_diameter * diameter_m;
        e.radius_m = irregular_radius_min_m * std::pow(hi / irregular_radius_min_m, u_size);
    }
    return e;
}

WaterSurface::WaterSurface(const WaterSurfaceConfig& config) : config_(config) {
    if (!(std::isfinite(config.sample_rate_hz) && config.sample_rate_hz >= 8000.0 && config.sample_rate_hz <= 1e7))
        throw std::invalid_argument("water surface: sample rate must be 8 kHz..10 MHz, got " +
                                    std::to_string(config.sample_rate_hz));
    if (config.max_bubbles < 1 || config.max_bubbles > 1 << 20)
        throw std::invalid_argument("water surface: max_bubbles must be 1..1048576, got " +
                                    std::to_string(config.max_bubbles));
    if (!(config.sin_angle_from_vertical >= 0.0 && config.sin_angle_from_vertical <= 1.0))
        throw std::invalid_argument("water surface: sin_angle_from_vertical must be in [0, 1]");
    dt_ = 1.0 / config.sample_rate_hz;
    impact_gain_ = (constants::air_density / constants::water_density) * config.sin_angle_from_vertical /
                   (2.0 * constants::pi * bubble::reference_distance_m * constants::speed_of_sound_air);
    impacts_ = std::make_unique<ImpactPool>();
    bubbles_.resize(static_cast<std::size_t>(config.max_bubbles));
    scratch_.resize(scratch_frames);
}

WaterSurface::~WaterSurface() = default;
WaterSurface::WaterSurface(WaterSurface&&) noexcept = default;
WaterSurface& WaterSurface::operator=(WaterSurface&&) noexcept = default;

int WaterSurface::active_impacts() const noexcept { return impacts_->active(); }

Entrainment WaterSurface::strike(double diameter_m, double speed_m_per_s, Random& rng) noexcept {
    // Draw first, so that a refused strike consumes the stream like any other.
    Entrainment e = draw_entrainment(diameter_m, rng);
    if (!finite_positive(diameter_m) || !finite_positive(speed_m_per_s)) {
        ++stats_.rejected;
        return Entrainment{};
    }
    ++stats_.strikes;
    ++stats_.by_class[static_cast<std::size_t>(e.splash)];

    // Impact: impulse m V over D / V (impact_force.hpp).
    const double mass = constants::water_density * constants::pi / 6.0 * diameter_m * diameter_m * diameter_m;
    if (!impacts_->add(CanopyHit{}, mass * speed_m_per_s, diameter_m / speed_m_per_s, dt_)) ++stats_.impacts_dropped;

    if (e.bubble) {
        ++stats_.bubbles_entrained;
        if (active_ == config_.max_bubbles) {
            ++stats_.bubbles_dropped;
        } else if (bubbles_[static_cast<std::size_t>(active_)].start(
                       e.radius_m, bubble_pressure_amplitude_pa(e.radius_m), config_.sample_rate_hz)) {
            ++active_;
            ++stats_.bubbles_started;
        } else {
            ++stats_.bubbles_above_band;
        }
    }
    return e;
}

void WaterSurface::process(double* out, int frames) noexcept {
    if (frames <= 0) return;
    // Impact: p = gain dF/dt, with F the force averaged over each sample (the pool delivers each
    // sample's exact share of the impulse).
    const double inverse_dt = 1.0 / dt_;
    for (int n = 0; n < frames; ++n) {
        double force = 0.0;
        if (impacts_->active() > 0) impacts_->emit(dt_, [&force](CanopyHit, double f) { force += f; });
        out[n] = impact_gain_ * (force - previous_force_) * inverse_dt;
        previous_force_ = force;
    }
    // Bubbles, in the order they started; the finished ones leave afterwards, order kept, so every
    // sample sums the same bubbles in the same order whatever the block size.
    int kept = 0;
    for (int i = 0; i < active_; ++i) {
        Bubble& b = bubbles_[static_cast<std::size_t>(i)];
        b.render_add(out, frames);
        if (b.active()) {
            if (kept != i) bubbles_[static_cast<std::size_t>(kept)] = b;
            ++kept;
        }
    }
    active_ = kept;
}

void WaterSurface::process(float* out, int frames) noexcept {
    while (frames > 0) {
        const int n = std::min(frames, scratch_frames);
        process(scratch_.data(), n);
        for (int i = 0; i < n; ++i) out[i] = static_cast<float>(scratch_[static_cast<std::size_t>(i)]);
        out += n;
        frames -= n;
    }
}

void WaterSurface::reset() noexcept {
    for (int i = 0; i < active_; ++i) bubbles_[static_cast<std::size_t>(i)].stop();
    active_ = 0;
    impacts_->clear();
    previous_force_ = 0.0;
}

}  // namespace ameoto
