// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/modal_plate.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "engine/core/physical_constants.hpp"
#include "engine/core/range_message.hpp"
#include "engine/models/impact_force.hpp"

namespace ameoto {
namespace {

constexpr double kReferenceDistanceM = 1.0;

// Radiation efficiency (per face) of odd-odd mode (m, n) at frequency f; see the header.
double radiation_efficiency(const PlateSpec& s, int m, int n, double f) {
    const double c = constants::speed_of_sound_air;
    const double fc = s.coincidence_hz();
    if (f < fc) {
        const double k = 2.0 * constants::pi * f / c;
        const double sigma = 32.0 * k * k * s.length_x_m * s.length_y_m /
                             (std::pow(constants::pi, 5) * static_cast<double>(m * m) * static_cast<double>(n * n));
        return std::min(1.0, sigma);
    }
    const double lambda_c = c / fc;
    const double cap = std::sqrt(s.length_x_m / lambda_c) + std::sqrt(s.length_y_m / lambda_c);
    const double above = 1.0 - fc / f;
    return above <= 0.0 ? cap : std::min(cap, 1.0 / std::sqrt(above));
}

// sin((2i + 1) theta) for i = 0..count-1 (the odd multiples) by the Chebyshev recurrence
// s_{i+1} = 2 cos(2 theta) s_i - s_{i-1}, s_{-1} = -sin theta: two libm calls per table instead of one per
// entry (the error grows like i eps: < 1e-13 for i < 1000).
void odd_sine_table(double theta, int count, double* out) {
    const double c2 = 2.0 * std::cos(2.0 * theta);
    double prev = -std::sin(theta), cur = std::sin(theta);
    for (int i = 0; i < count; ++i) {
        out[i] = cur;
        const double next = c2 * cur - prev;
        prev = cur;
        cur = next;
    }
}

// The mode loops. Each returns sum (u[n+1] - u[n]), the change of the volume velocity over the sample
// (m^3/s). A plain loop with one running sum is latency-bound (the compiler may not reassociate a
// floating-point sum, so it adds one mode at a time: measured 1.7 ns per mode), and GCC 12's
// auto-vectoriser turned a four-way unrolled version into shuffles and spills; so these use GCC/Clang
// vector extensions explicitly: two modes per 16-byte vector (SSE2, the baseline of x86-64), two vectors
// per iteration with their own partial sums, a scalar tail. The rounding differs from a sequential sum but
// is the same on every run (deterministic).
using Pair = double __attribute__((vector_size(16), aligned(8), may_alias));

inline Pair load(const double* p) { return *reinterpret_cast<const Pair*>(p); }
inline void store(double* p, Pair v) { *reinterpret_cast<Pair*>(p) = v; }

// Free ringing: the two-pole recursion u[n+1] = a1 u[n] - a2 u[n-1].
double ring(std::size_t modes, const double* __restrict a1, const double* __restrict a2, double* __restrict u,
            double* __restrict u1) {
    Pair s0 = {0.0, 0.0}, s1 = {0.0, 0.0};
    std::size_t k = 0;
    for (; k + 4 <= modes; k += 4) {
        const Pair u0a = load(u + k), u0b = load(u + k + 2);
        const Pair una = load(a1 + k) * u0a - load(a2 + k) * load(u1 + k);
        const Pair unb = load(a1 + k + 2) * u0b - load(a2 + k + 2) * load(u1 + k + 2);
        store(u1 + k, u0a);
        store(u1 + k + 2, u0b);
        store(u + k, una);
        store(u + k + 2, unb);
        s0 += una - u0a;
        s1 += unb - u0b;
    }
    double tail = 0.0;
    for (; k < modes; ++k) {
        const double u0 = u[k];
        const double un = a1[k] * u0 - a2[k] * u1[k];
        u1[k] = u0;
        u[k] = un;
        tail += un - u0;
    }
    const Pair s = s0 + s1;
    return (s[0] + s[1]) + tail;
}

// With kicks: u[n+1] = a1 u[n] - a2 u[n-1] + kick[n+1] - t11 kick[n] (the state-space form with the kick
// applied after the transition, x[n+1] = A x[n] + (0, 1)' kick[n+1], eliminated by Cayley-Hamilton:
// C (A - a1 I) B = t22 - a1 = -t11).
double ring_kicked(std::size_t modes, const double* __restrict a1, const double* __restrict a2,
                   const double* __restrict t11, double* __restrict u, double* __restrict u1,
                   const double* __restrict kick, const double* __restrict kick_prev) {
    Pair s0 = {0.0, 0.0}, s1 = {0.0, 0.0};
    std::size_t k = 0;
    for (; k + 4 <= modes; k += 4) {
        const Pair u0a = load(u + k), u0b = load(u + k + 2);
        const Pair una = load(a1 + k) * u0a - load(a2 + k) * load(u1 + k) + load(kick + k) -
                         load(t11 + k) * load(kick_prev + k);
        const Pair unb = load(a1 + k + 2) * u0b - load(a2 + k + 2) * load(u1 + k + 2) + load(kick + k + 2) -
                         load(t11 + k + 2) * load(kick_prev + k + 2);
        store(u1 + k, u0a);
        store(u1 + k + 2, u0b);
        store(u + k, una);
        store(u + k + 2, unb);
        s0 += una - u0a;
        s1 += unb - u0b;
    }
    double tail = 0.0;
    for (; k < modes; ++k) {
        const double u0 = u[k];
        const double un = a1[k] * u0 - a2[k] * u1[k] + kick[k] - t11[k] * kick_prev[k];
        u1[k] = u0;
        u[k] = un;
        tail += un - u0;
    }
    const Pair s = s0 + s1;
    return (s[0] + s[1]) + tail;
}

// Subnormal guard: a mode left ringing decays through the subnormal range (below 2.2e-308), where every
// multiply costs some hundred cycles: measured, a struck car roof went from 1.2 us to 100 us per sample
// after 1.5 s. So every flush_interval samples, a mode whose u and u1 are both below 1e-150 m^3/s (a
// pressure of order 1e-146 Pa) is set to rest. Between flushes the fastest mode (eta 1 at 20 kHz) decays
// by at most e^-42, so nothing reaches the subnormal range. Branch-free, vectorised.
constexpr int kFlushInterval = 32;
constexpr double kFlushBelow = 1e-150;

void flush_tiny(std::size_t modes, double* __restrict u, double* __restrict u1) {
    for (std::size_t k = 0; k < modes; ++k) {
        const bool rest = std::abs(u[k]) < kFlushBelow && std::abs(u1[k]) < kFlushBelow;
        u[k] = rest ? 0.0 : u[k];
        u1[k] = rest ? 0.0 : u1[k];
    }
}

// One group (fixed odd m, n = 1, 3, ...), contiguous: kick[j] = c sy[j] for the first strike of the sample,
// kick[j] += c sy[j] for the others.
void kick_group_set(std::size_t length, double c, const double* __restrict sy, double* __restrict kick) {
    for (std::size_t j = 0; j < length; ++j) kick[j] = c * sy[j];
}
void kick_group_add(std::size_t length, double c, const double* __restrict sy, double* __restrict kick) {
    for (std::size_t j = 0; j < length; ++j) kick[j] += c * sy[j];
}

}  // namespace

double PlateSpec::bending_stiffness() const {
    return youngs_modulus_pa * thickness_m * thickness_m * thickness_m / (12.0 * (1.0 - poisson_ratio * poisson_ratio));
}

double PlateSpec::areal_density() const { return density_kg_m3 * thickness_m; }

double PlateSpec::coincidence_hz() const {
    const double c = constants::speed_of_sound_air;
    return c * c / (2.0 * constants::pi) * std::sqrt(areal_density() / bending_stiffness());
}

double PlateSpec::mode_frequency_hz(int m, int n) const {
    const double a = m / length_x_m, b = n / length_y_m;
    return 0.5 * constants::pi * std::sqrt(bending_stiffness() / areal_density()) * (a * a + b * b);
}

PlateSpec PlateSpec::tin_roof() { return custom("tin-roof", 2.1e11, 7850.0, 0.3, 0.5e-3, 1.0, 0.6, 0.01); }
PlateSpec PlateSpec::glass_pane() { return custom("glass-pane", 7.0e10, 2500.0, 0.2, 4e-3, 0.8, 0.6, 0.01); }
PlateSpec PlateSpec::car_roof() { return custom("car-roof", 2.1e11, 7850.0, 0.3, 0.8e-3, 1.2, 1.0, 0.05); }

PlateSpec PlateSpec::custom(std::string name, double youngs_modulus_pa, double density_kg_m3, double poisson_ratio,
                            double thickness_m, double length_x_m, double length_y_m, double loss_factor) {
    PlateSpec s;
    s.name = std::move(name);
    s.youngs_modulus_pa = youngs_modulus_pa;
    s.density_kg_m3 = density_kg_m3;
    s.poisson_ratio = poisson_ratio;
    s.thickness_m = thickness_m;
    s.length_x_m = length_x_m;
    s.length_y_m = length_y_m;
    s.loss_factor = loss_factor;
    return s;
}

void validate_plate_spec(const PlateSpec& s) {
    std::vector<std::string> reasons = {
        s.name.empty() ? std::string("a plate needs a name") : std::string(),
        out_of_range("Young's modulus", s.youngs_modulus_pa, 1e8, 1.2e12, "Pa",
                     "softer than any rigid plastic: a sheet that soft sags into a membrane, which bending alone does not describe",
                     "stiffer than diamond (1.05e12 Pa)"),
        out_of_range("density", s.density_kg_m3, 100.0, 25000.0, "kg/m^3",
                     "lighter than any solid sheet (balsa is about 150)", "denser than osmium (22 590)"),
        out_of_range("Poisson's ratio", s.poisson_ratio, -0.99, 0.499, "",
                     "an isotropic solid needs nu > -1 (positive shear modulus)",
                     "an isotropic solid needs nu < 1/2 (positive bulk modulus)"),
        out_of_range("thickness", s.thickness_m, 1e-5, 0.05, "m", "thinner than foil: a membrane, not a plate",
                     "a slab: thicker than any panel a drop could set ringing"),
        out_of_range("length x", s.length_x_m, 0.01, 20.0, "m", "smaller than a raindrop's splash",
                     "larger than any single panel"),
        out_of_range("length y", s.length_y_m, 0.01, 20.0, "m", "smaller than a raindrop's splash",
                     "larger than any single panel"),
        out_of_range("loss factor", s.loss_factor, 1e-5, 0.5, "",
                     "below any real material's internal loss (aluminium ~1e-5)",
                     "so damped that modes overlap into a thud: no longer a ringing plate (use soft_ground)"),
    };
    if (std::isfinite(s.thickness_m) && std::isfinite(s.length_x_m) && std::isfinite(s.length_y_m) &&
        s.thickness_m > std::min(s.length_x_m, s.length_y_m) / 20.0) {
        std::ostringstream r;
        r << "thickness " << s.thickness_m << " m is more than 1/20 of the shorter side ("
          << std::min(s.length_x_m, s.length_y_m) << " m): not a thin plate (Kirchhoff needs h much smaller than the span)";
        reasons.push_back(r.str());
    }
    std::string all;
    for (const auto& r : reasons) {
        if (r.empty()) continue;
        all += (all.empty() ? "" : "; ") + r;
    }
    if (!all.empty()) throw std::invalid_argument("plate '" + s.name + "': " + all);
}

ModalPlate::ModalPlate(const PlateSpec& spec, double sample_rate_hz, const PlateOptions& options) : spec_(spec) {
    validate_plate_spec(spec_);
    if (!std::isfinite(sample_rate_hz) || sample_rate_hz < 8000.0 || sample_rate_hz > 384000.0)
        throw std::invalid_argument("plate: sample rate must be 8000 .. 384000 Hz");
    if (!(options.max_frequency_hz > 0.0) || !std::isfinite(options.max_frequency_hz))
        throw std::invalid_argument("plate: max_frequency_hz must be positive");
    if (options.max_modes < 1 || options.max_modes > 65536)
        throw std::invalid_argument("plate: max_modes must be 1 .. 65536");
    if (options.max_strikes < 1 || options.max_strikes > ImpactPool::capacity)
        throw std::invalid_argument("plate: max_strikes must be 1 .. 2048 (the impulse pool's capacity)");
    if (!(options.min_wavelength_thicknesses >= 0.0) || !std::isfinite(options.min_wavelength_thicknesses))
        throw std::invalid_argument("plate: min_wavelength_thicknesses must be >= 0");
    dt_ = 1.0 / sample_rate_hz;
    build(options);
}

ModalPlate::~ModalPlate() = default;
ModalPlate::ModalPlate(ModalPlate&&) noexcept = default;
ModalPlate& ModalPlate::operator=(ModalPlate&&) noexcept = default;

void ModalPlate::build(const PlateOptions& options) {
    const double kappa = std::sqrt(spec_.bending_stiffness() / spec_.areal_density());   // omega = kappa k_b^2
    double limit = std::min(options.max_frequency_hz, 0.45 / dt_);
    if (options.min_wavelength_thicknesses > 0.0) {
        const double k_max = 2.0 * constants::pi / (options.min_wavelength_thicknesses * spec_.thickness_m);
        limit = std::min(limit, kappa * k_max * k_max / (2.0 * constants::pi));
    }
    frequency_limit_hz_ = limit;

    struct Candidate {
        int m, n;
        double f;
    };
    std::vector<Candidate> all;
    for (int m = 1; spec_.mode_frequency_hz(m, 1) <= limit; m += 2)
        for (int n = 1; spec_.mode_frequency_hz(m, n) <= limit; n += 2) all.push_back({m, n, spec_.mode_frequency_hz(m, n)});
    if (all.empty()) {
        std::ostringstream r;
        r << "plate '" << spec_.name << "': its lowest mode (" << spec_.mode_frequency_hz(1, 1)
          << " Hz) is above the frequency limit " << limit << " Hz (max_frequency_hz, 0.45 fs, thin-plate limit)";
        throw std::invalid_argument(r.str());
    }
    std::sort(all.begin(), all.end(), [](const Candidate& a, const Candidate& b) {
        return a.f != b.f ? a.f < b.f : (a.m != b.m ? a.m < b.m : a.n < b.n);
    });
    const std::size_t kept = std::min(all.size(), static_cast<std::size_t>(options.max_modes));
    dropped_modes_ = static_cast<int>(all.size() - kept);

    const double rho_h = spec_.areal_density();
    const double z0 = constants::air_density * constants::speed_of_sound_air;
    // Public order: by frequency. Internal order: by m, then n; within a group n runs 1, 3, ... without
    // gaps (f grows with n, and the kept modes are the lowest), and the groups are m = 1, 3, ... likewise.
    std::vector<std::int32_t> internal_of(kept);
    {
        std::vector<std::int32_t> by_mn(kept);
        for (std::size_t k = 0; k < kept; ++k) by_mn[k] = static_cast<std::int32_t>(k);
        std::sort(by_mn.begin(), by_mn.end(), [&](std::int32_t a, std::int32_t b) {
            const Candidate &ca = all[static_cast<std::size_t>(a)], &cb = all[static_cast<std::size_t>(b)];
            return ca.m != cb.m ? ca.m < cb.m : ca.n < cb.n;
        });
        for (std::size_t i = 0; i < kept; ++i) internal_of[static_cast<std::size_t>(by_mn[i])] = static_cast<std::int32_t>(i);
    }
    modes_.resize(kept);
    order_ = internal_of;
    for (auto* v : {&a1_, &a2_, &t11_, &t12_, &t21_, &t22_, &u_, &u1_, &kick_, &kick_prev_}) v->assign(kept, 0.0);
    groups_.clear();
    table_y_ = 0;
    for (std::size_t k = 0; k < kept; ++k) {
        const Candidate& c = all[k];
        PlateMode& pm = modes_[k];
        pm.m = c.m;
        pm.n = c.n;
        pm.frequency_hz = c.f;
        const double omega = 2.0 * constants::pi * c.f;
        pm.radiation_efficiency = radiation_efficiency(spec_, c.m, c.n, c.f);
        const double eta_rad = options.radiation_damping ? 2.0 * z0 * pm.radiation_efficiency / (omega * rho_h) : 0.0;
        // At most 1: a critically damped mode needs eta = 2; beyond 1 it would no longer ring.
        pm.loss_factor = std::min(1.0, spec_.loss_factor + eta_rad);
        pm.decay_per_s = 0.5 * pm.loss_factor * omega;
        pm.volume_m3 = 4.0 * spec_.length_x_m * spec_.length_y_m / (constants::pi * constants::pi * c.m * c.n);
        // Exact transition of (q, q') over T for q'' + 2 a q' + w^2 q = 0 (underdamped: a / w = eta / 2 <= 0.5);
        // its trace and determinant are the two-pole coefficients.
        const double a = pm.decay_per_s;
        const double wd = omega * std::sqrt(1.0 - 0.25 * pm.loss_factor * pm.loss_factor);
        const double e = std::exp(-a * dt_);
        const double ec = e * std::cos(wd * dt_), es = e * std::sin(wd * dt_) / wd;
        const auto i = static_cast<std::size_t>(internal_of[k]);
        t11_[i] = ec + a * es;
        t12_[i] = es;
        t21_[i] = -omega * omega * es;
        t22_[i] = ec - a * es;
        a1_[i] = 2.0 * ec;
        a2_[i] = e * e;
    }
    for (std::size_t k = 0; k < kept; ++k) {
        const Candidate& c = all[k];
        const auto g = static_cast<std::size_t>((c.m - 1) / 2);
        if (groups_.size() <= g) groups_.resize(g + 1, Group{0, 0});
        if (c.n == 1) groups_[g].start = internal_of[k];
        groups_[g].length = std::max(groups_[g].length, static_cast<std::int32_t>((c.n + 1) / 2));
        table_y_ = std::max(table_y_, (c.n + 1) / 2);
    }
    table_x_ = static_cast<int>(groups_.size());
    // u = V q' is kicked by V (4 / M) phi J = (16 / (pi^2 rho h)) (sin(m pi x0 / Lx) / m) (sin(n pi y0 / Ly) / n) J:
    // separable, so a strike stores its two tables already divided by m and n.
    kick_scale_ = 16.0 / (constants::pi * constants::pi * rho_h);
    const auto slots = static_cast<std::size_t>(options.max_strikes);
    slot_sx_.assign(slots * static_cast<std::size_t>(table_x_), 0.0);
    slot_sy_.assign(slots * static_cast<std::size_t>(table_y_), 0.0);
    slot_impulse_.assign(slots, 0.0);
    slot_seen_.assign(slots, 0);
    slot_active_.clear();
    slot_active_.reserve(slots);
    slot_free_.clear();
    slot_free_.reserve(slots);
    for (std::size_t s = slots; s-- > 0;) slot_free_.push_back(static_cast<std::int32_t>(s));
    pulses_ = std::make_unique<ImpactPool>();
    kicked_last_ = false;
    pressure_gain_ = constants::air_density / (2.0 * constants::pi * kReferenceDistanceM * dt_);
}

bool ModalPlate::strike(double x, double y, double diameter, double speed, double density) {
    const bool valid = std::isfinite(x) && std::isfinite(y) && x >= 0.0 && x <= spec_.length_x_m && y >= 0.0 &&
                       y <= spec_.length_y_m && diameter > 0.0 && diameter <= 0.02 && speed > 0.0 && speed <= 100.0 &&
                       density >= 100.0 && density <= 25000.0;
    if (!valid) {
        ++stats_.refused_invalid;
        return false;
    }
    if (slot_free_.empty()) {
        ++stats_.refused_full;
        return false;
    }
    const std::int32_t slot = slot_free_.back();
    const double mass = density * constants::pi * diameter * diameter * diameter / 6.0;
    if (!pulses_->add(CanopyHit{slot, 0}, mass * speed, diameter / speed, dt_)) {
        ++stats_.refused_full;
        return false;
    }
    slot_free_.pop_back();
    slot_active_.push_back(slot);
    const auto s = static_cast<std::size_t>(slot);
    double* sx = slot_sx_.data() + s * static_cast<std::size_t>(table_x_);
    double* sy = slot_sy_.data() + s * static_cast<std::size_t>(table_y_);
    odd_sine_table(constants::pi * x / spec_.length_x_m, table_x_, sx);
    odd_sine_table(constants::pi * y / spec_.length_y_m, table_y_, sy);
    for (int i = 0; i < table_x_; ++i) sx[i] /= 2 * i + 1;
    for (int j = 0; j < table_y_; ++j) sy[j] /= 2 * j + 1;
    slot_seen_[s] = 1;
    ++stats_.strikes;
    return true;
}

double ModalPlate::sample() {
    const std::size_t n = a1_.size();
    if (++flush_countdown_ >= kFlushInterval) {
        flush_countdown_ = 0;
        flush_tiny(n, u_.data(), u1_.data());
    }
    if (slot_active_.empty() && !kicked_last_)
        return pressure_gain_ * ring(n, a1_.data(), a2_.data(), u_.data(), u1_.data());
    // This sample's impulse from every pulse under way (impact_force.hpp's law, exact per sample).
    for (const std::int32_t s : slot_active_) {
        slot_impulse_[static_cast<std::size_t>(s)] = 0.0;
        slot_seen_[static_cast<std::size_t>(s)] = 0;
    }
    if (pulses_->active() > 0) {
        pulses_->emit(dt_, [&](CanopyHit hit, double force) {
            const auto s = static_cast<std::size_t>(hit.panel);
            slot_impulse_[s] = force * dt_;
            slot_seen_[s] = 1;
        });
    }
    bool kicked = false;
    for (std::size_t i = 0; i < slot_active_.size();) {
        const auto s = static_cast<std::size_t>(slot_active_[i]);
        if (!slot_seen_[s]) {   // its pulse ended last sample
            slot_free_.push_back(slot_active_[i]);
            slot_active_[i] = slot_active_.back();
            slot_active_.pop_back();
            continue;
        }
        const double impulse = slot_impulse_[s];
        stats_.impulse_delivered_n_s += impulse;
        const double* sx = slot_sx_.data() + s * static_cast<std::size_t>(table_x_);
        const double* sy = slot_sy_.data() + s * static_cast<std::size_t>(table_y_);
        const double scale = kick_scale_ * impulse;
        for (std::size_t g = 0; g < groups_.size(); ++g) {
            const auto start = static_cast<std::size_t>(groups_[g].start);
            const auto length = static_cast<std::size_t>(groups_[g].length);
            if (kicked) kick_group_add(length, scale * sx[g], sy, kick_.data() + start);
            else kick_group_set(length, scale * sx[g], sy, kick_.data() + start);
        }
        kicked = true;
        ++i;
    }
    if (!kicked) std::fill(kick_.begin(), kick_.end(), 0.0);   // the last corrected step after a pulse
    const double change =
        ring_kicked(n, a1_.data(), a2_.data(), t11_.data(), u_.data(), u1_.data(), kick_.data(), kick_prev_.data());
    // kick_prev_ now holds this sample's kicks (all zero when there were none, which is what the free
    // recursion assumes once kicked_last_ is false).
    kick_.swap(kick_prev_);
    kicked_last_ = kicked;
    return pressure_gain_ * change;
}

void ModalPlate::process(double* out, std::size_t frames) {
    for (std::size_t i = 0; i < frames; ++i) out[i] = sample();
}

void ModalPlate::reset() {
    for (auto* v : {&u_, &u1_, &kick_, &kick_prev_}) std::fill(v->begin(), v->end(), 0.0);
    kicked_last_ = false;
    pulses_->clear();
    for (const std::int32_t s : slot_active_) slot_free_.push_back(s);
    slot_active_.clear();
}

double ModalPlate::mode_energy(int k) const {
    // (M / 4) (q'^2 + w^2 q^2) / 2. The two-pole state is (u[n], u[n-1]) with u = V q'; w = V q follows from
    // the transition: u[n] = t21 w[n-1] + t22 u[n-1] + kick[n], w[n] = t11 w[n-1] + t12 u[n-1].
    const std::size_t i = internal(k);
    const double kick = kicked_last_ ? kick_prev_[i] : 0.0;
    const double w_prev = (u_[i] - kick - t22_[i] * u1_[i]) / t21_[i];
    const double w_now = t11_[i] * w_prev + t12_[i] * u1_[i];
    const PlateMode& m = modes_[static_cast<std::size_t>(k)];
    const double omega = 2.0 * constants::pi * m.frequency_hz;
    const double q = w_now / m.volume_m3, qd = u_[i] / m.volume_m3;
    const double modal_mass = 0.25 * spec_.areal_density() * spec_.length_x_m * spec_.length_y_m;
    return 0.5 * modal_mass * (qd * qd + omega * omega * q * q);
}

double ModalPlate::momentum() const {
    double volume_velocity = 0.0;
    for (const double u : u_) volume_velocity += u;
    return spec_.areal_density() * volume_velocity;
}

PlateStats ModalPlate::stats() const {
    PlateStats s = stats_;
    s.active_strikes = static_cast<int>(slot_active_.size());
    return s;
}

}  // namespace ameoto
