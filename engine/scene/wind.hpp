// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Wind over a rain scene: a ramped mean wind with gusts, and what it does to the drops.
//
// Interface:
//   Wind wind(Wind::Config{.turbulence_intensity = 0.27});   // no allocation, ever
//   wind.set_speed(m_per_s);         // target mean speed (clamped to 0..60 m/s); ramps linearly in ramp_s
//   wind.set_direction(rad);         // target direction; ramps along the shorter arc in ramp_s
//   wind.set_now(m_per_s, rad);      // jump there, gusts calm, drops settled (a scene's initial state)
//   wind.advance(dt, rng);           // one step of the ramps, the gusts and the drops' lag (per sample or
//                                    // at a fixed control interval; see Determinism)
//   wind.mean_speed(), wind.direction(), wind.velocity()   // ramped mean (m/s, rad); air velocity now (m/s)
//   wind.horizontal_velocity(d_m)    // a drop's horizontal velocity: the wind, lagged by its response time
//   wind.drop_velocity(d_m)          // ... with -v_t(D) as z: the drop's velocity over the ground
//   wind.tilt(d_m)                   // its fall direction's angle from the vertical, atan(|u_h| / v_t)
//   wind.impact(d_m, normal)         // its velocity on a static surface of unit normal n (DropImpact)
//   wind.surface_rate_factor(d_m, n) // drops of size D striking the surface / those striking a horizontal one
//   wind.max_surface_rate_factor(n, d_min_m)   // an upper bound of that over D >= d_min, now (for thinning)
//   wind.gust_factor()               // peak gust / mean speed, sqrt(1 + 7 I) (EN 1991-1-4, eq. 4.8)
//
// Frame: canopy coordinates (engine/models/canopy.hpp): x, y horizontal, z up. The direction is the
// azimuth the wind blows TOWARD, counter-clockwise from +x (a meteorological "wind from theta" is theta + pi).
//
// Mean wind: speed and direction each ramp linearly to a new target in ramp_s (1 s, like the rain rate's
// ramp in rain_spawner.hpp), the direction along the shorter arc, so no change is a step.
//
// Gusts (a documented simplification of atmospheric turbulence): the longitudinal and lateral velocity
// fluctuations u', v' are independent Ornstein-Uhlenbeck processes,
//   du' = -u'/T_u dt + sigma_u sqrt(2 / T_u) dW,   sigma_u = I U,   T_u = L_u / U,
// with v' the same using sigma_v = 0.8 sigma_u and L_v = L_u / 3: the variances and integral scales of the
// Kaimal model in IEC 61400-1 ed. 3 (2005), Annex B (sigma_2 = 0.8 sigma_1, L_1 = 8.1 Lambda_1,
// L_2 = 2.7 Lambda_1, Lambda_1 = 0.7 z below 60 m; so L_u = 11.3 m at z = 2 m, the default). An OU
// process has the Kaimal spectrum's variance and integral time scale, hence its low-frequency level,
// but falls as f^-2 above 1 / (2 pi T_u) where Kaimal falls as f^-5/3: the fastest gusts are a little weak.
// Turbulence intensity I = sigma_u / U: near the ground EN 1991-1-4 (2005) eq. 4.7 gives
// I = 1 / ln(z / z0): 0.27 at z = 2 m over open country (terrain category II, z0 = 0.05 m); 0.43 in a town
// (category IV, z0 = 1 m, at its z_min = 10 m; nearer the ground among buildings the code gives no more).
// The default is 0 (a steady wind); turbulence_intensity_at(z, z0) computes the code's value.
// Each step is the exact OU transition x <- a x + sigma sqrt(1 - a^2) xi, a = exp(-dt / T), so the
// statistics do not depend on dt. The fluctuations are not clamped: the air may briefly reverse.
// The vertical fluctuation w' (sigma_3 = 0.5 sigma_1) is left out: it would change the fall speed.
//
// Drops in the wind (a documented simplification, derived here): in a steady wind a falling drop's
// horizontal velocity relaxes to the wind's, so every drop, small or large, moves with the mean wind
// (the relaxation distance v_t^2 / g is at most 8.6 m of fall, far shorter than the fall from a cloud).
// Gusts are followed with a lag: linearising the drag m g (V_rel / v_t)^2 about terminal fall gives a
// first-order response of time constant tau = v_t(D) / g to horizontal changes (0.21 s for 0.5 mm,
// 0.41 s for 1 mm, 0.94 s for 5.8 mm; a 0.1 mm drizzle drop follows within 0.03 s). Each drop's
// horizontal velocity is the wind (mean + gusts) through that one-pole low-pass, taken from a bank of 12
// one-poles with tau from 0.0275 s (0.1 mm) to 0.935 s (5.8 mm), interpolated linearly in ln tau
// (and linearly in tau between the raw wind, tau = 0, and the first filter; against the closed-form
// response to a 0 -> 10 m/s ramp in 1 s the error is at most 0.037 m/s for 0.05..5.8 mm, tested). The
// drop's own history over the ground (it has fallen through the gusts upwind) is not tracked: all drops
// see the wind here.
//
// Rain rate seen by a surface (why gusts modulate it): rain falling with velocity V = (u_h, -v_t) through
// air crosses a surface of unit normal n at N(D) max(0, -V.n) per m^2, so relative to a horizontal surface
// (N v_t) the rate is f(D, n) = max(0, n_z - u_h.n_h / v_t): 1 on a horizontal surface (gusts change
// nothing there), U / v_t on a wall facing the wind (the wind-driven rain relation R_wdr = R_h U / V_t;
// Blocken & Carmeliet 2004, J. Wind Eng. Ind. Aerodyn. 92:1079, eq. 2), 0 in the lee. With gusts u_h
// fluctuates, so a tilted surface sees the rate swing with them, small drops (small v_t, short lag) most.
// To realise it with a RainSpawner on the surface's area A (rain_spawner.hpp; exact thinning):
//   const double f_max = wind.max_surface_rate_factor(n, cfg.d_min_mm * 1e-3);
//   int k = rain.advance(dt, rng, f_max);
//   for each of the k: d = rain.sample_diameter_m(rng);
//                      keep it if rng.uniform() * f_max < wind.surface_rate_factor(d, n)
//   -> drops of size D strike at N(D) v(D) f(D, n) A per second, with velocity wind.impact(d, n).
//
// Determinism: advance() draws 2 uniforms per call when turbulence_intensity > 0 (none otherwise), so a
// wind that shares a Random with the rain changes the rain's draws; give it its own Random. Results depend
// on the sequence of dt, so advance per sample or at a fixed interval, never per audio block.
// No allocation; safe on the audio thread.

#include <array>

#include "engine/core/body3d_vec3.hpp"
#include "engine/core/random.hpp"

namespace ameoto {

// A drop striking a static surface (wind.impact).
struct DropImpact {
    Vec3 velocity;              // m/s over the ground: (u_h, -v_t)
    double normal_speed = 0.0;  // m/s into the surface, -V.n; <= 0: it cannot strike this face
    Vec3 tangential;            // m/s along the surface, V + (normal_speed) n
    double incidence_rad = 0.0; // angle between -V and n (0: head-on)
};

class Wind {
public:
    struct Config {
        double ramp_s = 1.0;                 // speed and direction changes take this long
        double turbulence_intensity = 0.0;   // I = sigma_u / U; 0: steady wind
        double length_scale_m = 11.3;        // L_u, Kaimal integral length (IEC 61400-1: 8.1 * 0.7 z)
        double lateral_sigma_ratio = 0.8;    // sigma_v / sigma_u (IEC 61400-1 ed. 3, Kaimal)
        double lateral_length_ratio = 2.7 / 8.1;   // L_v / L_u (IEC 61400-1 ed. 3, Kaimal)
    };

    Wind() : Wind(Config{}) {}
    explicit Wind(const Config& config);   // throws std::invalid_argument on a negative or zero scale

    static constexpr double max_speed_m_per_s = 60.0;
    static constexpr int lag_filters = 12;

    void set_speed(double m_per_s);
    void set_direction(double rad);
    void set_now(double m_per_s, double rad);
    void advance(double dt, Random& rng);

    double mean_speed() const { return speed_; }
    double target_speed() const { return target_speed_; }
    double direction() const { return direction_; }   // in (-pi, pi]
    Vec3 velocity() const { return air_; }
    double longitudinal_gust() const { return gust_u_; }   // u' (m/s), along the mean direction
    double lateral_gust() const { return gust_v_; }        // v' (m/s), 90 degrees counter-clockwise from it
    double gust_time_s() const;                            // T_u = L_u / U (U floored at 0.1 m/s)
    double gust_factor() const;

    Vec3 horizontal_velocity(double diameter_m) const;
    Vec3 drop_velocity(double diameter_m) const;
    double tilt(double diameter_m) const;
    DropImpact impact(double diameter_m, Vec3 normal) const;
    double surface_rate_factor(double diameter_m, Vec3 normal) const;
    double max_surface_rate_factor(Vec3 normal, double d_min_m) const;

    // EN 1991-1-4 (2005) eq. 4.7 with k_I = c_o = 1: I = 1 / ln(z / z0), z floored at the z_min of its
    // Table 4.1 for the first terrain category as rough as z0 (1 m up to z0 = 0.01 m, 2 m to 0.05 m, 5 m to
    // 0.3 m, 10 m beyond).
    static double turbulence_intensity_at(double height_m, double roughness_m);
    // The drops' horizontal response time tau = v_t(D) / g (header).
    static double response_time_s(double diameter_m);

    const Config& config() const { return config_; }

private:
    void update_air();

    Config config_;
    double speed_ = 0.0, target_speed_ = 0.0, speed_step_ = 0.0;
    double direction_ = 0.0, target_direction_ = 0.0, direction_step_ = 0.0;
    double gust_u_ = 0.0, gust_v_ = 0.0;
    Vec3 air_{};
    std::array<double, lag_filters> tau_{};          // s, geometric
    std::array<Vec3, lag_filters> lagged_{};         // each filter's output (horizontal)
    std::array<double, lag_filters> coefficient_{};  // 1 - exp(-dt / tau) for last_dt_
    double last_dt_ = -1.0;
};

}  // namespace ameoto
