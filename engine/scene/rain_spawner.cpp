// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/scene/rain_spawner.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/scene/terminal_speed.hpp"

namespace ameoto {

RainSpawner::RainSpawner(const Config& config) : config_(config) {
    if (!(config.area_m2 > 0.0)) throw std::invalid_argument("rain area must be positive");
    if (!(config.d_min_mm > 0.0 && config.d_max_mm > config.d_min_mm)) throw std::invalid_argument("bad drop size range");
    log_rate_min_ = std::log(table_min_rate);
    log_rate_step_ = (std::log(max_rate_mm_per_h) - log_rate_min_) / (table_size - 1);
    for (int i = 0; i < table_size; ++i) {
        const double r = std::exp(log_rate_min_ + i * log_rate_step_);
        // Lambda and mu are monotone or parabolic in R, so checking every table rate (0.01..500 mm/h,
        // 4 % apart) catches a shape that turns invalid anywhere in the range.
        const double lambda = config.dsd.lambda_per_mm(r), mu = config.dsd.mu_at(r);
        if (!(lambda > 0.0 && std::isfinite(lambda))) throw std::invalid_argument("drop size distribution: Lambda must be positive");
        if (!(mu > -1.0 && std::isfinite(mu))) throw std::invalid_argument("drop size distribution: mu must exceed -1");
        log_flux_[static_cast<std::size_t>(i)] = std::log(impact_flux(config.dsd, r, config.d_min_mm, config.d_max_mm));
    }
    v_max_ = terminal_speed(config.d_max_mm * 1e-3);
    update_shape();
}

void RainSpawner::update_shape() {
    // Below the table's lowest rate (0.01 mm/h, where the flux falls linearly to 0) its shape stands in:
    // the validity checks above cover it, and the drops there are a few per hour per m^2.
    const double r = std::max(current_rate_, table_min_rate);
    lambda_ = config_.dsd.lambda_per_mm(r);
    mu_ = config_.dsd.mu_at(r);
}

double RainSpawner::flux_per_m2_s(double mm_per_h) const {
    if (mm_per_h <= 0.0) return 0.0;
    if (mm_per_h < table_min_rate) return std::exp(log_flux_[0]) * mm_per_h / table_min_rate;
    // Linear in log-log: the flux is close to a power law of R, so 128 points over 4.7 decades
    // interpolate to well under 0.1 % (checked against impact_flux in the tests).
    const double pos = std::min((std::log(mm_per_h) - log_rate_min_) / log_rate_step_, table_size - 1.0);
    const int i = std::min(static_cast<int>(pos), table_size - 2);
    const double t = pos - i;
    return std::exp(log_flux_[static_cast<std::size_t>(i)] * (1.0 - t) + log_flux_[static_cast<std::size_t>(i + 1)] * t);
}

void RainSpawner::set_rate(double mm_per_h) {
    target_rate_ = std::clamp(mm_per_h, 0.0, max_rate_mm_per_h);
    ramp_step_ = 0.0;   // computed per sample in advance(), which knows dt
}

void RainSpawner::set_rate_now(double mm_per_h) {
    set_rate(mm_per_h);
    current_rate_ = target_rate_;
    arrivals_per_s_ = flux_per_m2_s(current_rate_) * config_.area_m2;
    update_shape();
}

int RainSpawner::advance(double dt, Random& rng, double flux_scale) {
    if (current_rate_ != target_rate_) {
        if (ramp_step_ == 0.0) ramp_step_ = std::abs(target_rate_ - current_rate_) * dt / config_.ramp_s;
        if (std::abs(target_rate_ - current_rate_) <= ramp_step_) {
            current_rate_ = target_rate_;
        } else {
            current_rate_ += current_rate_ < target_rate_ ? ramp_step_ : -ramp_step_;
        }
        arrivals_per_s_ = flux_per_m2_s(current_rate_) * config_.area_m2;
        update_shape();
    }
    if (arrivals_per_s_ <= 0.0 || !(flux_scale > 0.0)) return 0;
    if (!threshold_drawn_) {
        threshold_ = rng.exponential();
        threshold_drawn_ = true;
    }
    // Time rescaling with the scaled intensity: exact for any flux_scale(t) >= 0 held over each step.
    hazard_ += arrivals_per_s_ * flux_scale * dt;
    int arrivals = 0;
    while (hazard_ >= threshold_) {
        hazard_ -= threshold_;
        threshold_ = rng.exponential();
        ++arrivals;
    }
    return arrivals;
}

double RainSpawner::sample_diameter_m(Random& rng) const {
    const double lambda = lambda_;
    const double lo = config_.d_min_mm, hi = config_.d_max_mm;
    double d_mm = lo;
    if (mu_ == 0.0) {
        // Inverse CDF of exp(-lambda D) truncated to [lo, hi]; then accept with v(D) / v_max.
        const double span = 1.0 - std::exp(-lambda * (hi - lo));
        for (int attempt = 0; attempt < 64; ++attempt) {
            d_mm = lo - std::log(1.0 - rng.uniform() * span) / lambda;
            if (rng.uniform() * v_max_ <= terminal_speed(d_mm * 1e-3)) break;
        }
        return d_mm * 1e-3;
    }
    // Gamma: proposal exp(-rate D) on [lo, hi]; the remaining factor g(D) = D^mu exp(-a D), a = lambda -
    // rate, is bounded by its value at d_peak (its maximum over [lo, hi]), so accepting with
    // g(D) / g(d_peak) * v(D) / v_max leaves exactly D^mu exp(-lambda D) v(D) on [lo, hi].
    const double mu = mu_;
    const double rate = mu > 0.0 ? lambda / (1.0 + mu) : lambda;
    const double a = lambda - rate;
    // mu > 0: g peaks at mu / a = (1 + mu) / lambda; mu < 0 (a = 0): g = D^mu falls, largest at lo.
    const double d_peak = mu > 0.0 ? std::clamp(mu / a, lo, hi) : lo;
    const double span = 1.0 - std::exp(-rate * (hi - lo));
    for (int attempt = 0; attempt < 1000; ++attempt) {
        d_mm = lo - std::log(1.0 - rng.uniform() * span) / rate;
        const double g_ratio = std::exp(mu * std::log(d_mm / d_peak) - a * (d_mm - d_peak));
        if (rng.uniform() * v_max_ <= g_ratio * terminal_speed(d_mm * 1e-3)) break;
    }
    return d_mm * 1e-3;
}

}  // namespace ameoto
