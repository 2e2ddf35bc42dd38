// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/soft_ground.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "engine/core/physical_constants.hpp"
#include "engine/core/range_message.hpp"
#include "engine/models/impact_force.hpp"

namespace ameoto {
namespace {

constexpr double kWaterSurfaceTension = 0.0728;   // N/m, 20 C (physics.md section 4)
constexpr double kWaterViscosity = 1.0e-3;        // Pa s, 20 C
constexpr double kMundoSplash = 57.7;             // K = We^1/2 Re^1/4 (Mundo et al. 1995)
constexpr double kMaxLifetimeS = 2.0;

// Standard normal by Box-Muller from the engine's generator (one uniform pair per variate, so the number
// of draws per hit is fixed and the stream stays reproducible).
double normal(Random& rng) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    return std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(2.0 * constants::pi * u2);
}

}  // namespace

SoftGroundSpec SoftGroundSpec::leaves() {
    SoftGroundSpec s;
    s.name = "leaves";
    s.kind = GroundKind::leaves;
    s.efficiency = 3e-6;
    s.splash_share = 0.0;
    return s;
}

SoftGroundSpec SoftGroundSpec::soil() {
    SoftGroundSpec s;
    s.name = "soil";
    s.kind = GroundKind::soil;
    s.efficiency = 3e-7;
    s.splash_share = 0.02;
    return s;
}

void validate_soft_ground_spec(const SoftGroundSpec& s) {
    const char* no_negative = "a spread cannot be negative";
    std::vector<std::string> reasons = {
        s.name.empty() ? std::string("a ground needs a name") : std::string(),
        out_of_range("efficiency", s.efficiency, 1e-9, 1e-2, "", "inaudible: below any surface a drop can hit",
                     "a drop cannot turn that much of its kinetic energy into sound (it spreads, splashes and heats)"),
        out_of_range("leaf f1 minimum", s.leaf_f1_min_hz, 20.0, 20000.0, "Hz", "below hearing", "above hearing"),
        out_of_range("leaf f1 maximum", s.leaf_f1_max_hz, 20.0, 20000.0, "Hz", "below hearing", "above hearing"),
        out_of_range("leaf f1 median", s.leaf_f1_median_hz, 20.0, 20000.0, "Hz", "below hearing", "above hearing"),
        out_of_range("leaf size sigma_ln", s.leaf_size_sigma_ln, 0.0, 1.0, "", no_negative,
                     "wider than the band can hold: most draws would be clamped"),
        out_of_range("leaf stiffness sigma_ln", s.leaf_stiffness_sigma_ln, 0.0, 1.0, "", no_negative,
                     "wider than the band can hold: most draws would be clamped"),
        out_of_range("leaf aspect minimum", s.leaf_aspect_min, 1.0, 4.0, "", "the aspect is long side over short side",
                     "a strip, not a patch"),
        out_of_range("leaf aspect maximum", s.leaf_aspect_max, 1.0, 4.0, "", "the aspect is long side over short side",
                     "a strip, not a patch"),
        out_of_range("leaf loss minimum", s.leaf_loss_min, 0.01, 1.0, "", "a leaf is heavily damped, not a bell",
                     "overdamped (eta 2 is critical): no longer a resonance"),
        out_of_range("leaf loss maximum", s.leaf_loss_max, 0.01, 1.0, "", "a leaf is heavily damped, not a bell",
                     "overdamped (eta 2 is critical): no longer a resonance"),
        out_of_range("soil cutoff", s.soil_cutoff_median_hz, 20.0, 5000.0, "Hz", "below hearing: silence",
                     "not a dull thud any more"),
        out_of_range("soil cutoff sigma_ln", s.soil_cutoff_sigma_ln, 0.0, 1.0, "", no_negative, "too wide to be one ground"),
        out_of_range("soil damping ratio", s.soil_damping_ratio, 0.05, 0.95, "",
                     "soil is lossy: a ringing ground is not soil",
                     "the closed-form energy needs an underdamped pair of poles"),
        out_of_range("splash share", s.splash_share, 0.0, 0.5, "", "a share cannot be negative",
                     "a splash that loud is not 'tiny' and would mask the impact"),
        out_of_range("splash time constant", s.splash_time_constant_s, 1e-4, 0.05, "s", "shorter than a few samples",
                     "a splash is over within tens of milliseconds"),
    };
    if (s.leaf_f1_min_hz > s.leaf_f1_median_hz || s.leaf_f1_median_hz > s.leaf_f1_max_hz)
        reasons.push_back("leaf band: need minimum <= median <= maximum");
    if (s.leaf_aspect_min > s.leaf_aspect_max) reasons.push_back("leaf aspect: minimum above maximum");
    if (s.leaf_loss_min > s.leaf_loss_max) reasons.push_back("leaf loss: minimum above maximum");
    std::string all;
    for (const auto& r : reasons) {
        if (r.empty()) continue;
        all += (all.empty() ? "" : "; ") + r;
    }
    if (!all.empty()) throw std::invalid_argument("ground '" + s.name + "': " + all);
}

SoftGround::SoftGround(const SoftGroundSpec& spec, double sample_rate_hz, std::uint64_t seed, int max_hits)
    : spec_(spec), rng_(seed) {
    validate_soft_ground_spec(spec_);
    if (!std::isfinite(sample_rate_hz) || sample_rate_hz < 8000.0 || sample_rate_hz > 384000.0)
        throw std::invalid_argument("ground: sample rate must be 8000 .. 384000 Hz");
    if (max_hits < 1 || max_hits > ImpactPool::capacity)
        throw std::invalid_argument("ground: max_hits must be 1 .. 2048 (the impulse pool's capacity)");
    dt_ = 1.0 / sample_rate_hz;
    hits_.assign(static_cast<std::size_t>(max_hits), Hit{});
    active_.reserve(hits_.size());
    free_.reserve(hits_.size());
    for (std::size_t s = hits_.size(); s-- > 0;) free_.push_back(static_cast<std::int32_t>(s));
    pulses_ = std::make_unique<ImpactPool>();
    scratch_ = std::make_unique<ImpactPool>();
}

SoftGround::~SoftGround() = default;
SoftGround::SoftGround(SoftGround&&) noexcept = default;
SoftGround& SoftGround::operator=(SoftGround&&) noexcept = default;

LeafDraw SoftGround::draw_leaf(Random& rng, const SoftGroundSpec& s) {
    LeafDraw d;
    for (;; ++d.redraws) {
        const double size = std::exp(s.leaf_size_sigma_ln * normal(rng));
        const double stiffness = std::exp(s.leaf_stiffness_sigma_ln * normal(rng));
        d.f1_hz = s.leaf_f1_median_hz * stiffness / (size * size);
        if (d.f1_hz >= s.leaf_f1_min_hz && d.f1_hz <= s.leaf_f1_max_hz) break;
        if (d.redraws == 15) {
            d.f1_hz = std::clamp(d.f1_hz, s.leaf_f1_min_hz, s.leaf_f1_max_hz);
            break;
        }
    }
    d.aspect = rng.uniform(s.leaf_aspect_min, s.leaf_aspect_max);
    d.loss_factor = rng.uniform(s.leaf_loss_min, s.leaf_loss_max);
    d.u = rng.uniform(0.15, 0.85);
    d.v = rng.uniform(0.15, 0.85);
    return d;
}

bool SoftGround::splashes(double diameter, double speed, double density) {
    const double we = density * speed * speed * diameter / kWaterSurfaceTension;
    const double re = density * speed * diameter / kWaterViscosity;
    return std::sqrt(we) * std::pow(re, 0.25) > kMundoSplash;
}

double SoftGround::radiated_energy_j(double diameter, double speed, double density) const {
    const double mass = density * constants::pi * diameter * diameter * diameter / 6.0;
    return spec_.efficiency * 0.5 * mass * speed * speed;
}

bool SoftGround::strike(double diameter, double speed, double density) {
    const bool valid = diameter > 0.0 && diameter <= 0.02 && speed >= 0.5 && speed <= 100.0 && density >= 100.0 &&
                       density <= 25000.0;
    if (!valid) {
        ++stats_.refused_invalid;
        return false;
    }
    if (free_.empty()) {
        ++stats_.refused_full;
        return false;
    }
    const std::int32_t slot = free_.back();
    Hit& h = hits_[static_cast<std::size_t>(slot)];
    h = Hit{};
    const double nyquist_limit = 0.45 / dt_;

    // The resonators: y[n] = a1 y[n-1] - a2 y[n-2] + g J_n (impulse invariance: y[n] = J h((n + 1) T) for
    // h(t) = e^-at sin(w_d t) / w_d), heard as sum c0 y[n] + c1 y[n-1] before the gain.
    double theta[max_modes]{};   // w_d T of each mode, for the closed-form tail below
    auto set_mode = [&](int k, double omega, double zeta, double drive, double c0, double c1) {
        const double a = zeta * omega;
        const double wd = omega * std::sqrt(1.0 - zeta * zeta);
        const double r = std::exp(-a * dt_);
        theta[k] = wd * dt_;
        h.a1[k] = 2.0 * r * std::cos(wd * dt_);
        h.a2[k] = r * r;
        h.g[k] = drive * r * std::sin(wd * dt_) / wd;
        h.c0[k] = c0;
        h.c1[k] = c1;
    };
    if (spec_.kind == GroundKind::leaves) {
        const LeafDraw d = draw_leaf(rng_, spec_);
        static constexpr int order[max_modes][2] = {{1, 1}, {2, 1}, {1, 2}, {2, 2}};
        const double inv_a2 = 1.0 / (d.aspect * d.aspect);
        for (const auto& mn : order) {
            const int m = mn[0], n = mn[1];
            double f = d.f1_hz * (m * m + n * n * inv_a2) / (1.0 + inv_a2);
            if (h.modes == 0) f = std::min(f, nyquist_limit);
            else if (f > nyquist_limit) continue;
            const double omega = 2.0 * constants::pi * f;
            const double phi = std::sin(m * constants::pi * d.u) * std::sin(n * constants::pi * d.v);
            set_mode(h.modes++, omega, 0.5 * d.loss_factor, phi, omega * omega / (m * n), 0.0);
        }
    } else {
        const double fg = std::min(spec_.soil_cutoff_median_hz * std::exp(spec_.soil_cutoff_sigma_ln * normal(rng_)),
                                   nyquist_limit);
        set_mode(h.modes++, 2.0 * constants::pi * fg, spec_.soil_damping_ratio, 1.0, 1.0 / dt_, -1.0 / dt_);
    }

    // The hit's energy before the gain: the pulse through the resonators, sample by sample (the same law and
    // arithmetic as at run time, on a scratch pool), then the free decay in closed form.
    const double mass = density * constants::pi * diameter * diameter * diameter / 6.0;
    const double impulse = mass * speed, duration = diameter / speed;
    scratch_->clear();
    scratch_->add(CanopyHit{0, 0}, impulse, duration, dt_);
    double y1[max_modes]{}, y2[max_modes]{};
    double energy = 0.0;
    std::int64_t pulse_samples = 0;
    while (scratch_->active() > 0) {
        double j = 0.0;
        scratch_->emit(dt_, [&](CanopyHit, double force) { j = force * dt_; });
        double p = 0.0;
        for (int k = 0; k < h.modes; ++k) {
            const double y = h.a1[k] * y1[k] - h.a2[k] * y2[k] + h.g[k] * j;
            p += h.c0[k] * y + h.c1[k] * y1[k];
            y2[k] = y1[k];
            y1[k] = y;
        }
        energy += p * p;
        ++pulse_samples;
    }
    // Free decay: y_k[n0 + j] = 2 Re(beta_k z_k^j), z_k = r e^{i w_d T}; output 2 Re(gamma_k z_k^j) with
    // gamma_k = beta_k (c0 + c1 / z_k); sum_{j >= 1} of its square = 2 sum_{a,b} Re[g_a g_b S(z_a z_b) +
    // g_a conj(g_b) S(z_a conj(z_b))], S(w) = w / (1 - w).
    using cd = std::complex<double>;
    cd z[max_modes], gamma[max_modes];
    double r_max = 0.0;
    for (int k = 0; k < h.modes; ++k) {
        const double r = std::sqrt(h.a2[k]);
        const double cos_t = std::cos(theta[k]), sin_t = std::sin(theta[k]);
        z[k] = cd(r * cos_t, r * sin_t);
        const double br = 0.5 * y1[k];
        const double bi = (0.5 * r * y2[k] - br * cos_t) / sin_t;
        gamma[k] = cd(br, bi) * (h.c0[k] + h.c1[k] / z[k]);
        r_max = std::max(r_max, r);
    }
    auto tail_sum = [](cd w) { return w / (1.0 - w); };
    double tail = 0.0;
    for (int a = 0; a < h.modes; ++a)
        for (int b = 0; b < h.modes; ++b)
            tail += 2.0 * (gamma[a] * gamma[b] * tail_sum(z[a] * z[b]) +
                           gamma[a] * std::conj(gamma[b]) * tail_sum(z[a] * std::conj(z[b])))
                              .real();
    energy += std::max(0.0, tail);

    // Target sum of p^2 over the hit: E = (2 pi / (rho0 c)) T sum p^2 at 1 m.
    const double target = radiated_energy_j(diameter, speed, density) * constants::air_density *
                          constants::speed_of_sound_air / (2.0 * constants::pi * dt_);
    const bool splash = spec_.splash_share > 0.0 && splashes(diameter, speed, density);
    const double share = splash ? spec_.splash_share : 0.0;
    h.gain = energy > 0.0 ? std::sqrt((1.0 - share) * target / energy) : 0.0;
    const double max_samples = kMaxLifetimeS / dt_;
    if (share > 0.0) {
        // Uniform noise in [-1, 1) has variance 1/3: E[sum (A d^n u_n)^2] = A^2 / 3 (1 - d^2L) / (1 - d^2).
        const double d = std::exp(-dt_ / spec_.splash_time_constant_s);
        const double length = std::min(std::ceil(std::log(1e3) * spec_.splash_time_constant_s / dt_), max_samples);
        h.noise_decay = d;
        h.noise_end = static_cast<std::int64_t>(length);
        const double sum = (1.0 - std::pow(d, 2.0 * length)) / (1.0 - d * d) / 3.0;
        h.noise = std::sqrt(share * target / sum);
        ++stats_.splashes;
    }
    const double ring = r_max > 0.0 && r_max < 1.0 ? std::ceil(std::log(1e-6) / std::log(r_max)) : max_samples;
    h.end = std::max<std::int64_t>(h.noise_end, static_cast<std::int64_t>(std::min(
                                                    static_cast<double>(pulse_samples) + ring, max_samples)));

    if (!pulses_->add(CanopyHit{slot, 0}, impulse, duration, dt_)) {   // cannot happen: capacity >= max_hits
        ++stats_.refused_full;
        return false;
    }
    free_.pop_back();
    active_.push_back(slot);
    ++stats_.strikes;
    return true;
}

double SoftGround::sample() {
    if (active_.empty()) return 0.0;
    for (const std::int32_t s : active_) hits_[static_cast<std::size_t>(s)].impulse = 0.0;
    if (pulses_->active() > 0)
        pulses_->emit(dt_, [&](CanopyHit hit, double force) { hits_[static_cast<std::size_t>(hit.panel)].impulse = force * dt_; });
    double out = 0.0;
    for (std::size_t i = 0; i < active_.size();) {
        Hit& h = hits_[static_cast<std::size_t>(active_[i])];
        double p = 0.0;
        for (int k = 0; k < h.modes; ++k) {
            const double y = h.a1[k] * h.y1[k] - h.a2[k] * h.y2[k] + h.g[k] * h.impulse;
            p += h.c0[k] * y + h.c1[k] * h.y1[k];
            h.y2[k] = h.y1[k];
            h.y1[k] = y;
        }
        p *= h.gain;
        if (h.age < h.noise_end) {
            p += h.noise * rng_.uniform(-1.0, 1.0);
            h.noise *= h.noise_decay;
        }
        out += p;
        if (++h.age >= h.end) {
            free_.push_back(active_[i]);
            active_[i] = active_.back();
            active_.pop_back();
        } else {
            ++i;
        }
    }
    return out;
}

void SoftGround::process(double* out, std::size_t frames) {
    for (std::size_t i = 0; i < frames; ++i) out[i] = sample();
}

void SoftGround::reset(std::uint64_t seed) {
    rng_.reseed(seed);
    pulses_->clear();
    for (const std::int32_t s : active_) free_.push_back(s);
    active_.clear();
}

SoftGroundStats SoftGround::stats() const {
    SoftGroundStats s = stats_;
    s.active = static_cast<int>(active_.size());
    return s;
}

}  // namespace ameoto
