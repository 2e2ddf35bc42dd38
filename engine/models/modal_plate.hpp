// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Hard surfaces under rain: a thin rectangular plate (tin roof, glass pane, car roof) as a bank of exact
// two-pole modes, struck by drops, heard as the pressure it radiates at 1 m on its axis.
//
// Interface:
//   PlateSpec spec = PlateSpec::glass_pane();          // presets: tin_roof(), glass_pane(), car_roof()
//   PlateSpec mine = PlateSpec::custom("zinc", E, rho, nu, h, Lx, Ly, loss_factor);
//   validate_plate_spec(mine);                         // throws std::invalid_argument naming value, range, why
//   ModalPlate plate(spec, 48000.0);                   // allocates everything; throws std::invalid_argument
//   ModalPlate plate(spec, fs, PlateOptions{...});     // frequency limit, mode cap, strike pool, radiation loss
//   ---- audio-safe from here: no allocation, no locks, no blocking, no logging ----
//   bool ok = plate.strike(x_m, y_m, diameter_m, speed_m_per_s, liquid_density_kg_m3);
//                                                      // a drop lands at (x, y) from the corner (0, 0);
//                                                      // false: refused and counted (full pool, bad value)
//   double p = plate.sample();                         // Pa at 1 m on the plate's axis, one sample
//   plate.process(out, frames);                        // the same for a block: out[i] = sample()
//   plate.reset();                                     // silence, pending strikes dropped
//   ---- read (any time) ----
//   plate.mode_count(); plate.mode(k)                  // PlateMode: m, n, Hz, loss factor, decay, volume
//   plate.mode_energy(k)                               // J in mode k now
//   plate.momentum()                                   // kg m/s: the plate's momentum, rho h sum V_k q_k'
//   plate.stats()                                      // strikes, refusals, impulse delivered (N s)
//   plate.dropped_modes(), plate.frequency_limit_hz()  // what the caps left out
//
// Model (Kirchhoff thin plate; Graff, Wave Motion in Elastic Solids, 1975, section 4.3; Leissa, Vibration
// of Plates, NASA SP-160, 1969, section 4.1): D lap^2 w + rho h w_tt = f(x, y, t), D = E h^3 / (12 (1 - nu^2)).
// Boundary assumption: SIMPLY SUPPORTED on all four edges (w = 0 and no bending moment): a sheet screwed
// to purlins, a pane in a glazing bead, a roof skin on its rails are neither clamped nor free; simple
// support is the one case with closed-form modes, and clamping would raise the lowest modes (by about
// 1.8x for a square) and hardly move the high ones. Modes phi_mn = sin(m pi x / Lx) sin(n pi y / Ly),
//   f_mn = (pi / 2) sqrt(D / (rho h)) ((m / Lx)^2 + (n / Ly)^2),
// modal mass rho h Lx Ly / 4 = M / 4. A point force F at (x0, y0) drives mode k as
//   q_k'' + 2 a_k q_k' + w_k^2 q_k = (4 / M) phi_k(x0, y0) F(t),   a_k = eta_k w_k / 2.
// Radiation (Rayleigh's first integral, baffled plate; Kinsler et al., Fundamentals of Acoustics, 4th ed.,
// section 7.4): far away on the axis every point of the plate is at the same distance to first order, so
//   p(R, t) = rho0 / (2 pi R) sum_k q_k''(t - R / c) V_k,   V_k = integral phi_k dA = 4 Lx Ly / (pi^2 m n)
// for m and n both odd, 0 otherwise (even modes cancel on the axis). sample() returns R p(R) at R = 1 m
// without the delay: the pressure referred to 1 m, to which a scene applies its own 1/r, delay and panning.
// Valid in the far field (R much larger than the plate and than Lx Ly / wavelength) and for a baffled
// plate (a roof among roof panels, a pane in a wall, a roof in the car's body); off the axis the even
// modes radiate too and the odd ones have directivity: neither is modelled, so only odd-odd modes are run
// (the others never reach this output). Air loading (added mass) is neglected.
// Damping: eta_k = eta_s + eta_rad(f_k). eta_s is the structural loss factor of the mounted panel (the
// preset's figure, constant in frequency). eta_rad = 2 rho0 c sigma / (omega rho h) is the loss to sound on
// both faces (Cremer, Heckl & Petersson, Structure-Borne Sound, 3rd ed. 2005, ch. 7; Fahy & Gardonio,
// Sound and Structural Vibration, 2nd ed. 2007, ch. 3) with the radiation efficiency sigma of the mode:
//   below coincidence (f < f_c = c^2 / (2 pi) sqrt(rho h / D)): the odd-odd mode as a baffled monopole of
//   volume velocity V_k q_k', sigma = 32 k^2 Lx Ly / (pi^5 m^2 n^2) (derived from the same far field as the
//   output; Wallace 1972, JASA 51:946, leading term), at most 1 (it overestimates when k Lx > 1, where the
//   four corners radiate incoherently, by up to 4x: these modes' eta_rad is then far below eta_s anyway);
//   above: sigma = 1 / sqrt(1 - f_c / f) (infinite plate), at most Maidanik's (1962, JASA 34:809) value at
//   coincidence, sqrt(Lx / lambda_c) + sqrt(Ly / lambda_c). The rise just below f_c (edge modes) is left out.
// Discretisation: exact (impulse invariance). Each sample of the force is the exact integral of the drop's
// pulse over that sample (impact_force.hpp), applied as an impulse at the sample instant
// (q_k' += (4 / M) phi_k J_n); between instants the state (q_k, q_k') follows the exact 2x2 transition A of
// the damped mode (the modal integrator's, core/integrators/modal.cpp), so frequencies and decay rates are
// exact at any sample rate. What runs is that transition eliminated to a two-pole resonator on the
// velocity (Cayley-Hamilton): u[n+1] = 2 e^-aT cos(w_d T) u[n] - e^-2aT u[n-1] + k[n+1] - A_11 k[n],
// u = V_k q_k', k the kicks. The output is the mean acceleration over the sample,
// sum_k V_k (q_k'[n] - q_k'[n-1]) / T, so the integral of the pressure is exact too.
// Modes kept: all odd-odd (m, n) with f_mn <= frequency_limit_hz() = min(max_frequency_hz (20 kHz),
// 0.45 fs, the thin-plate limit), the lowest max_modes of them (dropped_modes() counts the rest). Thin-plate
// limit: Kirchhoff ignores shear and rotary inertia; Mindlin's (1951) theory is lower by about
// 0.19 (k_b h)^2 (computed here from Mindlin's dispersion relation, nu = 0.3): 1.8 % at a bending wavelength
// of 20 h, 6.5 % at 10 h, so modes shorter than min_wavelength_thicknesses (10) h are dropped.
// Drops: a drop of diameter D, speed V and density rho_l brings J = m V, m = rho_l pi D^3 / 6, over
// tau = D / V with the rigid-surface pulse law of impact_force.hpp (Soto et al. 2014; Gordillo et al. 2018:
// rise like t^1/2, no rebound). The plate is taken as rigid for the drop (its admittance is far below the
// drop's: the pulse is unchanged).
// Cost: per sample, one two-pole update per kept mode (structure of arrays, two modes per SSE2 vector);
// while a pulse lasts, one multiply-add per mode per strike under way (the kick is separable in m and n,
// and the modes run grouped by m so it is contiguous). Bounded by max_modes. Measured (docs/surfaces.md,
// "Hard: the modal plate"): about 0.5 ns per mode and sample ringing; tin roof 1.0 us, glass 0.08 us, car
// roof 1.2 us per sample; in 4800 drops/s about 2.5 us.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ameoto {

class ImpactPool;

struct PlateSpec {
    std::string name;
    double youngs_modulus_pa = 2.1e11;   // E
    double density_kg_m3 = 7850.0;       // rho
    double poisson_ratio = 0.3;          // nu
    double thickness_m = 0.5e-3;         // h
    double length_x_m = 1.0;             // Lx
    double length_y_m = 0.6;             // Ly
    double loss_factor = 0.01;           // eta_s, structural (mounted panel), constant in frequency

    double bending_stiffness() const;    // D = E h^3 / (12 (1 - nu^2)), N m
    double areal_density() const;        // rho h, kg/m^2
    double coincidence_hz() const;       // f_c = c^2 / (2 pi) sqrt(rho h / D), c = 343 m/s
    double mode_frequency_hz(int m, int n) const;   // f_mn above

    // Galvanised steel roofing sheet, 0.5 mm, a 1.0 x 0.6 m panel between purlins; E 210 GPa, nu 0.3
    // (EN 1993-1-1, 3.2.6), rho 7850 kg/m^3 (EN 1991-1-1, Table A.4), eta_s 0.01 (assumed: the sheet
    // itself loses ~1e-4, Cremer & Heckl; screws and laps add most; docs/surfaces.md). f_11 = 4.6 Hz, f_c = 24 kHz;
    // 1921 odd-odd modes to 20 kHz.
    static PlateSpec tin_roof();
    // Float glass, 4 mm, 0.8 x 0.6 m: E 70 GPa, nu 0.2, rho 2500 kg/m^3 (EN 572-1), eta_s 0.01 (assumed:
    // glass loses 0.6e-3 .. 2e-3, Cremer & Heckl; the bead or putty adds). f_11 = 42.5 Hz, f_c = 3.0 kHz;
    // 193 odd-odd modes to 20 kHz.
    static PlateSpec glass_pane();
    // Car roof skin, steel 0.8 mm, 1.2 x 1.0 m, flat (the crown is ignored), eta_s 0.05 (assumed: the
    // headliner, anti-flutter foam and mastic on the bows damp it well above the bare sheet). f_11 = 3.3 Hz,
    // f_c = 15 kHz; 2393 odd-odd modes to 20 kHz.
    static PlateSpec car_roof();
    static PlateSpec custom(std::string name, double youngs_modulus_pa, double density_kg_m3, double poisson_ratio,
                            double thickness_m, double length_x_m, double length_y_m, double loss_factor);
};

// Names the value, its range and why, for each value out of range; throws std::invalid_argument.
// E 1e8 .. 1.2e12 Pa, rho 100 .. 25 000 kg/m^3, nu -0.99 .. 0.499, h 1e-5 .. 0.05 m and at most
// min(Lx, Ly) / 20, Lx and Ly 0.01 .. 20 m, eta_s 1e-5 .. 0.5, a name.
void validate_plate_spec(const PlateSpec& spec);

struct PlateOptions {
    double max_frequency_hz = 20000.0;       // further limited to 0.45 fs and the thin-plate limit
    int max_modes = 4096;                    // the lowest ones; 1 .. 65536
    int max_strikes = 64;                    // strikes whose pulse is under way at once; 1 .. 2048
    double min_wavelength_thicknesses = 10.0;   // thin-plate limit (above); 0 disables it
    bool radiation_damping = true;           // eta_rad as above; false: eta_s only
};

struct PlateMode {
    int m = 1, n = 1;                // half-waves along x and y (both odd)
    double frequency_hz = 0.0;       // f_mn (undamped; the damped frequency is f sqrt(1 - eta^2 / 4))
    double loss_factor = 0.0;        // eta_s + eta_rad
    double radiation_efficiency = 0.0;   // sigma (per face)
    double decay_per_s = 0.0;        // a = eta omega / 2: amplitude ~ e^{-a t}; T60 = 3 ln 10 / a
    double volume_m3 = 0.0;          // V = integral of phi over the plate
};

struct PlateStats {
    std::uint64_t strikes = 0;
    std::uint64_t refused_full = 0;      // the strike pool was full
    std::uint64_t refused_invalid = 0;   // a value out of range or not finite (below)
    double impulse_delivered_n_s = 0.0;  // sum of the pulses' impulses delivered so far
    int active_strikes = 0;
};

class ModalPlate {
public:
    // sample_rate_hz 8000 .. 384000.
    ModalPlate(const PlateSpec& spec, double sample_rate_hz, const PlateOptions& options = PlateOptions{});
    ~ModalPlate();
    ModalPlate(ModalPlate&&) noexcept;
    ModalPlate& operator=(ModalPlate&&) noexcept;
    ModalPlate(const ModalPlate&) = delete;
    ModalPlate& operator=(const ModalPlate&) = delete;

    // Refused (false, counted) unless 0 <= x <= Lx, 0 <= y <= Ly, 0 < diameter <= 0.02 m,
    // 0 < speed <= 100 m/s, 100 <= density <= 25 000 kg/m^3, all finite. The pulse starts this sample.
    bool strike(double x_m, double y_m, double diameter_m, double speed_m_per_s,
                double liquid_density_kg_m3 = 998.0);
    double sample();
    void process(double* out, std::size_t frames);
    void reset();

    const PlateSpec& spec() const { return spec_; }
    double sample_rate_hz() const { return 1.0 / dt_; }
    int mode_count() const { return static_cast<int>(modes_.size()); }
    const PlateMode& mode(int k) const { return modes_[static_cast<std::size_t>(k)]; }
    double mode_energy(int k) const;
    double momentum() const;
    PlateStats stats() const;
    int dropped_modes() const { return dropped_modes_; }
    double frequency_limit_hz() const { return frequency_limit_hz_; }

private:
    void build(const PlateOptions& options);
    std::size_t internal(int k) const { return static_cast<std::size_t>(order_[static_cast<std::size_t>(k)]); }

    PlateSpec spec_;
    double dt_ = 1.0 / 48000.0;
    double frequency_limit_hz_ = 0.0;
    int dropped_modes_ = 0;
    std::vector<PlateMode> modes_;        // by frequency (public order)
    std::vector<std::int32_t> order_;     // public index -> internal index
    // Internally the modes run ordered by m, then n (so a strike's kick is contiguous in n), as structure
    // of arrays. State: u = V q' after this sample's kick (m^3/s), u1 the previous sample's; two-pole
    // coefficients a1 (trace of A), a2 (its determinant); t11 = A_11 for the kick's correction term.
    std::vector<double> a1_, a2_, t11_, u_, u1_, kick_, kick_prev_;
    std::vector<double> t12_, t21_, t22_;  // the rest of the transition, for mode_energy() only
    struct Group {
        std::int32_t start, length;        // internal modes (m, 1), (m, 3), ... (m, 2 length - 1)
    };
    std::vector<Group> groups_;           // one per odd m, in order
    int table_x_ = 0, table_y_ = 0;       // odd multiples per strike table: m = 1, 3, .. 2 table_x_ - 1
    // Strike slots: sin(m pi x0 / Lx) / m for odd m, likewise y; the impulse this sample.
    std::vector<double> slot_sx_, slot_sy_, slot_impulse_;
    std::vector<std::int32_t> slot_free_, slot_active_;
    std::vector<std::uint8_t> slot_seen_;
    std::unique_ptr<ImpactPool> pulses_;
    PlateStats stats_{};
    bool kicked_last_ = false;            // kick_prev_ holds a kick: one more corrected step
    int flush_countdown_ = 0;             // subnormal guard (modal_plate.cpp)
    double pressure_gain_ = 0.0;          // rho0 / (2 pi * 1 m * T)
    double kick_scale_ = 0.0;             // 16 / (pi^2 rho h)
};

}  // namespace ameoto
