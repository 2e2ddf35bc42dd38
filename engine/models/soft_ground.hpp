// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Soft surfaces under rain: leaves (a tick per drop, 1-6 kHz) and soil (a dull thud with a little splash),
// as phenomenological models whose radiated energy follows the drop's kinetic energy. Heard as the
// pressure referred to 1 m, like the plates (modal_plate.hpp).
//
// Interface:
//   SoftGroundSpec spec = SoftGroundSpec::leaves();   // or soil(); fields below, all documented
//   validate_soft_ground_spec(spec);                  // throws std::invalid_argument naming value, range, why
//   SoftGround ground(spec, 48000.0, seed);           // allocates the hit pool (max_hits, default 256); throws
//                                                     // std::invalid_argument
//   ---- audio-safe from here: no allocation, no locks, no blocking, no logging ----
//   bool ok = ground.strike(diameter_m, speed_m_per_s, liquid_density_kg_m3);
//                                                     // false: refused and counted (pool full, bad value)
//   double p = ground.sample();                       // Pa at 1 m, one sample
//   ground.process(out, frames);                      // the same for a block
//   ground.reset(seed);                               // silence, and the generator reseeded
//   ---- read ----
//   ground.stats()                                    // strikes, refusals, splashes, hits sounding
//   ground.radiated_energy_j(D, V, rho)               // efficiency x 1/2 m V^2: what one hit radiates
//   SoftGround::draw_leaf(rng, spec)                  // the per-hit leaf distribution (tests, docs)
//   SoftGround::splashes(D, V)                        // Mundo's criterion for water (below)
//
// What is physical and what is not. PHENOMENOLOGICAL: no published model predicts the sound of one drop
// on a leaf or on soil from first principles, so the shapes below are stand-ins chosen to sound like the
// descriptions (leaves: short, bright ticks; soil: a dull thud), in the spirit of Cook's physically
// informed stochastic synthesis (PhISM, Computer Music Journal 21(3), 1997: random events exciting
// damped resonances). What physics sets: (1) the drive is the drop's own impact force (impact_force.hpp:
// impulse m V over tau = D / V, rising like t^1/2; Soto et al. 2014, Gordillo et al. 2018), so bigger and
// slower drops sound duller; (2) every hit radiates exactly E = efficiency * 1/2 m V^2 (exact to rounding,
// bar the splash noise's random share), the energy referred to a hemisphere at 1 m:
//   E = (2 pi (1 m)^2 / (rho0 c)) integral p^2 dt,
// so a scene's levels follow the rain's kinetic energy flux; (3) splash noise only when the drop splashes
// (Mundo et al. 1995: K = We^1/2 Re^1/4 > 57.7, with water's sigma 0.0728 N/m and mu 1.0e-3 Pa s).
// The efficiencies are tuning constants, not measurements: leaves 3e-6, half what the glass pane radiates
// for the same drop measured the same way (5.9e-6; tin roof 1.8e-5, car roof 2.4e-6: modal_plate_test),
// soil 3e-7, 10 dB below leaves (docs/surfaces.md has the table).
//
// Leaves. A whole leaf bends at tens of Hz (computed: a 6 cm square lamina, 0.25 mm thick, E 0.1-1 GPa,
// 700 kg/m^3, simply supported: 25-80 Hz), so the 1-6 kHz rustle is not its flexure; we take each hit to
// ring a small, heavily damped plate-like patch: four simply supported modes (1,1), (2,1), (1,2), (2,2) of a
// patch with aspect ratio alpha, f_mn = f1 (m^2 + n^2 / alpha^2) / (1 + 1 / alpha^2). Per hit (draw_leaf):
//   patch size  L / L_med ~ lognormal(0, size_sigma_ln = 0.2), stiffness s ~ lognormal(0, stiffness_sigma_ln
//   = 0.2), so f1 = f1_median s / (L / L_med)^2 (plate scaling: f ~ sqrt(D / rho h) / L^2), i.e. ln f1 is
//   normal with sd sqrt(4 * 0.04 + 0.04) = 0.447 about ln 2500 Hz; redrawn (up to 16 times, then clamped)
//   until f1 lies in [1 kHz, 6 kHz];
//   alpha ~ uniform [1, 1.6]; loss factor eta ~ uniform [0.08, 0.25] (T60 = 2.2 / (eta f): 2-25 ms);
//   struck at (u, v) ~ uniform [0.15, 0.85]^2 of the patch, mode k driven by phi_k(u, v) = sin(m pi u) sin(n pi v)
//   and heard through its acceleration weighted 1 / (m n) (higher orders radiate less; phenomenological).
// Soil. The ground under the drop as a damped mass-spring (the lumped analogue of a footing on an elastic
// half-space, Lysmer & Richart 1966, J. Soil Mech. Found. Div. 92(SM1):65): its displacement is the impact
// force through a second-order low-pass (ground compliance) at f_g ~ lognormal(median 400 Hz, sd_ln 0.25),
// damping ratio 0.6; the pressure is its time derivative (a band-pass about f_g falling as 1/f above: dull;
// and a radiated pressure with no net impulse). Plus a tiny splash: white noise under an exponential
// envelope (time constant 2 ms), 2 % of the hit's energy, only when Mundo's criterion says the drop splashes.
// Modes are exact two-pole resonators (impulse invariance: y[n] = 2 r cos(w_d T) y[n-1] - r^2 y[n-2] + g J_n,
// r = e^-aT, the continuous mode's impulse response sampled); a mode above 0.45 fs is dropped (the leaf's
// fundamental is kept, clamped to 0.45 fs). A hit's energy is computed when it lands: its pulse is run
// through its resonators (the same arithmetic as at run time), and the free decay after the pulse is summed
// in closed form (geometric series of the poles, cross terms included), so the gain that makes it radiate E
// is exact. A hit sounds until its resonators are 120 dB down and its noise 60 dB down, at most 2 s.
// One SoftGround is one patch heard as one source: a scene that spreads hits in space uses several.
// Determinism: all randomness comes from the ground's own Random (engine/core/random.hpp): the same seed
// and the same strikes at the same samples give the same output, sample for sample.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/random.hpp"

namespace ameoto {

class ImpactPool;

enum class GroundKind { leaves, soil };

struct SoftGroundSpec {
    std::string name;
    GroundKind kind = GroundKind::leaves;
    double efficiency = 3e-6;               // radiated acoustic energy / drop kinetic energy
    // Leaves (above).
    double leaf_f1_median_hz = 2500.0;
    double leaf_f1_min_hz = 1000.0, leaf_f1_max_hz = 6000.0;
    double leaf_size_sigma_ln = 0.2, leaf_stiffness_sigma_ln = 0.2;
    double leaf_aspect_min = 1.0, leaf_aspect_max = 1.6;
    double leaf_loss_min = 0.08, leaf_loss_max = 0.25;
    // Soil (above).
    double soil_cutoff_median_hz = 400.0, soil_cutoff_sigma_ln = 0.25;
    double soil_damping_ratio = 0.6;
    // Splash noise (either kind), when the drop splashes.
    double splash_share = 0.0;              // of the hit's energy
    double splash_time_constant_s = 0.002;

    static SoftGroundSpec leaves();         // efficiency 3e-6, no splash noise
    static SoftGroundSpec soil();           // efficiency 3e-7, splash 2 %
};

// Ranges: efficiency 1e-9 .. 1e-2; leaf band 20 .. 20 000 Hz with min <= median <= max; sigmas 0 .. 1;
// aspect 1 .. 4 (min <= max); leaf loss 0.01 .. 1 (min <= max); soil cutoff 20 .. 5000 Hz; damping ratio
// 0.05 .. 0.95; splash share 0 .. 0.5; splash time constant 1e-4 .. 0.05 s; a name.
void validate_soft_ground_spec(const SoftGroundSpec& spec);

struct LeafDraw {
    double f1_hz = 0.0;        // fundamental
    double aspect = 1.0;       // alpha
    double loss_factor = 0.0;  // eta
    double u = 0.5, v = 0.5;   // struck point, fractions of the patch
    int redraws = 0;           // how many times f1 fell outside the band
};

struct SoftGroundStats {
    std::uint64_t strikes = 0;
    std::uint64_t refused_full = 0;
    std::uint64_t refused_invalid = 0;
    std::uint64_t splashes = 0;
    int active = 0;
};

class SoftGround {
public:
    // sample_rate_hz 8000 .. 384000; max_hits 1 .. 2048 (hits sounding at once; a full pool refuses).
    SoftGround(const SoftGroundSpec& spec, double sample_rate_hz, std::uint64_t seed, int max_hits = 256);
    ~SoftGround();
    SoftGround(SoftGround&&) noexcept;
    SoftGround& operator=(SoftGround&&) noexcept;
    SoftGround(const SoftGround&) = delete;
    SoftGround& operator=(const SoftGround&) = delete;

    // Refused unless 0 < diameter <= 0.02 m, 0.5 <= speed <= 100 m/s, 100 <= density <= 25 000 kg/m^3.
    bool strike(double diameter_m, double speed_m_per_s, double liquid_density_kg_m3 = 998.0);
    double sample();
    void process(double* out, std::size_t frames);
    void reset(std::uint64_t seed);

    const SoftGroundSpec& spec() const { return spec_; }
    SoftGroundStats stats() const;
    double radiated_energy_j(double diameter_m, double speed_m_per_s, double liquid_density_kg_m3 = 998.0) const;

    static LeafDraw draw_leaf(Random& rng, const SoftGroundSpec& spec);
    static bool splashes(double diameter_m, double speed_m_per_s, double liquid_density_kg_m3 = 998.0);

    static constexpr int max_modes = 4;

private:
    struct Hit {
        int modes = 0;
        double a1[max_modes]{}, a2[max_modes]{}, g[max_modes]{}, c0[max_modes]{}, c1[max_modes]{};
        double y1[max_modes]{}, y2[max_modes]{};
        double gain = 0.0;
        double noise = 0.0, noise_decay = 0.0;   // current noise amplitude, per-sample factor
        double impulse = 0.0;                    // this sample's share of the pulse
        std::int64_t age = 0, noise_end = 0, end = 0;
    };

    SoftGroundSpec spec_;
    double dt_ = 1.0 / 48000.0;
    Random rng_;
    std::vector<Hit> hits_;
    std::vector<std::int32_t> free_, active_;
    std::unique_ptr<ImpactPool> pulses_, scratch_;
    SoftGroundStats stats_{};
};

}  // namespace ameoto
