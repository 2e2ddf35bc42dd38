// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/scene/wind.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"
#include "engine/scene/terminal_speed.hpp"

namespace ameoto {
namespace {

constexpr double kTwoPi = 2.0 * constants::pi;
constexpr double kSpeedFloor = 0.1;   // m/s: below it T_u = L_u / U would run away (sigma_u -> 0 anyway)
constexpr double kTauSmallestDropM = 0.1e-3;
constexpr double kTauLargestDropM = 5.8e-3;   // Gunn-Kinzer's last point; v_t is flat beyond

// Into (-pi, pi].
double wrap(double a) {
    a = std::remainder(a, kTwoPi);
    return a <= -constants::pi ? a + kTwoPi : a;
}

}  // namespace

double Wind::response_time_s(double diameter_m) { return terminal_speed(diameter_m) / constants::gravity; }

double Wind::turbulence_intensity_at(double height_m, double roughness_m) {
    if (!(roughness_m > 0.0)) throw std::invalid_argument("roughness length must be positive");
    const double z_min = roughness_m <= 0.01 ? 1.0 : roughness_m <= 0.05 ? 2.0 : roughness_m <= 0.3 ? 5.0 : 10.0;
    return 1.0 / std::log(std::max(height_m, z_min) / roughness_m);
}

Wind::Wind(const Config& config) : config_(config) {
    if (!(config.ramp_s >= 0.0)) throw std::invalid_argument("wind ramp time must not be negative");
    if (!(config.turbulence_intensity >= 0.0)) throw std::invalid_argument("turbulence intensity must not be negative");
    if (!(config.length_scale_m > 0.0)) throw std::invalid_argument("gust length scale must be positive");
    if (!(config.lateral_sigma_ratio >= 0.0 && config.lateral_length_ratio > 0.0))
        throw std::invalid_argument("lateral gust ratios must be positive");
    const double tau0 = response_time_s(kTauSmallestDropM), tau1 = response_time_s(kTauLargestDropM);
    for (int k = 0; k < lag_filters; ++k)
        tau_[static_cast<std::size_t>(k)] = tau0 * std::pow(tau1 / tau0, static_cast<double>(k) / (lag_filters - 1));
}

void Wind::set_speed(double m_per_s) {
    target_speed_ = std::clamp(m_per_s, 0.0, max_speed_m_per_s);
    speed_step_ = 0.0;   // computed in advance(), which knows dt (as RainSpawner::set_rate)
}

void Wind::set_direction(double rad) {
    target_direction_ = wrap(rad);
    direction_step_ = 0.0;
}

void Wind::set_now(double m_per_s, double rad) {
    set_speed(m_per_s);
    set_direction(rad);
    speed_ = target_speed_;
    direction_ = target_direction_;
    gust_u_ = gust_v_ = 0.0;
    update_air();
    lagged_.fill(air_);   // the drops have long settled into this wind
}

double Wind::gust_time_s() const { return config_.length_scale_m / std::max(speed_, kSpeedFloor); }

double Wind::gust_factor() const { return std::sqrt(1.0 + 7.0 * config_.turbulence_intensity); }

void Wind::update_air() {
    const double c = std::cos(direction_), s = std::sin(direction_);
    const double along = speed_ + gust_u_;
    air_ = {along * c - gust_v_ * s, along * s + gust_v_ * c, 0.0};
}

void Wind::advance(double dt, Random& rng) {
    // Linear ramps, as RainSpawner::advance: the step is fixed on the first sample after a change.
    if (speed_ != target_speed_) {
        if (speed_step_ == 0.0) speed_step_ = std::abs(target_speed_ - speed_) * dt / config_.ramp_s;
        if (std::abs(target_speed_ - speed_) <= speed_step_) {
            speed_ = target_speed_;
        } else {
            speed_ += speed_ < target_speed_ ? speed_step_ : -speed_step_;
        }
    }
    if (direction_ != target_direction_) {
        const double delta = wrap(target_direction_ - direction_);   // the shorter arc
        if (direction_step_ == 0.0) direction_step_ = std::abs(delta) * dt / config_.ramp_s;
        if (std::abs(delta) <= direction_step_) {
            direction_ = target_direction_;
        } else {
            direction_ = wrap(direction_ + (delta > 0.0 ? direction_step_ : -direction_step_));
        }
    }
    if (config_.turbulence_intensity > 0.0) {
        // Exact OU transitions (header); Box-Muller gives the two independent normals from two uniforms.
        const double radius = std::sqrt(-2.0 * std::log(1.0 - rng.uniform()));
        const double angle = kTwoPi * rng.uniform();
        const double t_u = gust_time_s(), t_v = t_u * config_.lateral_length_ratio;
        const double sigma_u = config_.turbulence_intensity * speed_;
        const double sigma_v = config_.lateral_sigma_ratio * sigma_u;
        const double a_u = std::exp(-dt / t_u), a_v = std::exp(-dt / t_v);
        // sqrt(1 - a^2) = sqrt(-expm1(-2 dt / T)): accurate when dt << T (a within 1e-5 of 1 at 48 kHz).
        gust_u_ = a_u * gust_u_ + sigma_u * std::sqrt(-std::expm1(-2.0 * dt / t_u)) * radius * std::cos(angle);
        gust_v_ = a_v * gust_v_ + sigma_v * std::sqrt(-std::expm1(-2.0 * dt / t_v)) * radius * std::sin(angle);
    }
    update_air();
    if (dt != last_dt_) {
        for (int k = 0; k < lag_filters; ++k)
            coefficient_[static_cast<std::size_t>(k)] = -std::expm1(-dt / tau_[static_cast<std::size_t>(k)]);
        last_dt_ = dt;
    }
    // One-pole low-passes, exact for a wind held over the step's end (zero-order hold).
    for (int k = 0; k < lag_filters; ++k) {
        auto& y = lagged_[static_cast<std::size_t>(k)];
        y = y + coefficient_[static_cast<std::size_t>(k)] * (air_ - y);
    }
}

Vec3 Wind::horizontal_velocity(double diameter_m) const {
    const double tau = response_time_s(diameter_m);
    if (tau <= 0.0) return air_;
    const double tau0 = tau_.front();
    if (tau <= tau0) {
        const double t = tau / tau0;   // linear in tau between the raw wind (tau = 0) and the first filter
        return (1.0 - t) * air_ + t * lagged_.front();
    }
    const double pos = std::log(tau / tau0) / std::log(tau_.back() / tau0) * (lag_filters - 1);
    if (pos >= lag_filters - 1) return lagged_.back();
    const int i = static_cast<int>(pos);
    const double t = pos - i;
    return (1.0 - t) * lagged_[static_cast<std::size_t>(i)] + t * lagged_[static_cast<std::size_t>(i + 1)];
}

Vec3 Wind::drop_velocity(double diameter_m) const {
    Vec3 v = horizontal_velocity(diameter_m);
    v.z = -terminal_speed(diameter_m);
    return v;
}

double Wind::tilt(double diameter_m) const {
    const Vec3 u = horizontal_velocity(diameter_m);
    return std::atan2(std::hypot(u.x, u.y), terminal_speed(diameter_m));
}

DropImpact Wind::impact(double diameter_m, Vec3 normal) const {
    const double len = norm(normal);
    const Vec3 n = len > 0.0 ? normal / len : Vec3{0.0, 0.0, 1.0};
    DropImpact hit;
    hit.velocity = drop_velocity(diameter_m);
    hit.normal_speed = -dot(hit.velocity, n);
    hit.tangential = hit.velocity + hit.normal_speed * n;
    hit.incidence_rad = std::atan2(norm(hit.tangential), hit.normal_speed);
    return hit;
}

double Wind::surface_rate_factor(double diameter_m, Vec3 normal) const {
    const double v_t = terminal_speed(diameter_m);
    if (v_t <= 0.0) return 0.0;
    const double len = norm(normal);
    if (!(len > 0.0)) return 0.0;
    return std::max(0.0, -dot(drop_velocity(diameter_m), normal) / (len * v_t));
}

double Wind::max_surface_rate_factor(Vec3 normal, double d_min_m) const {
    // Every drop's horizontal velocity is a convex combination of the raw wind and the filters (header), so
    // its length is at most the longest of theirs; v_t(D) >= v_t(d_min) for D >= d_min.
    const double len = norm(normal);
    if (!(len > 0.0)) return 0.0;
    double u_max = std::hypot(air_.x, air_.y);
    for (const auto& y : lagged_) u_max = std::max(u_max, std::hypot(y.x, y.y));
    const double v_min = terminal_speed(d_min_m);
    if (v_min <= 0.0) return 0.0;
    // 1e-9 above: so rounding never puts surface_rate_factor (computed another way) above the bound.
    return std::max(0.0, (normal.z + std::hypot(normal.x, normal.y) * u_max / v_min) / len) * (1.0 + 1e-9);
}

}  // namespace ameoto
