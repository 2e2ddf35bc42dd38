// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Chooses the level of detail of each drop, so the engine models no more than the scene needs and sheds
// detail before it misses a deadline.
//
// Interface:
//   LodGovernor g(LodSettings{.budget = 0.4, .max_full = 4});
//   g.set_settings(s);                                   // /lod: budget (fraction of the block period), max full
//   ---- audio thread: no allocation ----
//   LodTier t = g.choose(D_m, V_m_per_s, distance_m, full_active);   // per drop (V: impact speed)
//   g.end_block(measured_load, drops_this_block, block_seconds);  // after each block: load in 0..1+
//   g.observe_load(load, LatticeActivity{...}, block_seconds);    // live only: each callback's load and what
//                                                        // the lattice drops did in it (prices them)
//   g.set_lattice_prior(diameters, events, n)            // live only: a spawn and breakup's cost per drop
//                                                        // size, measured before the stream (fractions of
//                                                        // the period): the event price's floor
//   g.set_lattice_prior(event)                           // the same, one figure for every size
//   g.detail()                                           // 0..1: how much detail the load allows now
//   g.masking_db()                                       // the density's masking level now
//
// Tiers: full (a lattice drop on the physical membrane, drop_on_canopy.hpp), template (its recorded
// impact replayed into the membrane, impact_templates.hpp), texture (a noise grain of the same size's
// energy and colour, texture_grains.hpp).
//
// Audibility. A drop's level at the listener is taken from its impact: the radiated pressure grows as the
// force, ~ rho V^2 D^2 (the impact law; Gordillo et al. 2018), over the distance r, so its level relative
// to a 2 mm drop at terminal speed 1 m away is
//   L = 20 log10((V / V_2)^2 (D / 2 mm)^2 / (r / 1 m))  dB.
// Masking by density: N incoherent drops per second of similar level raise the background by
// 10 log10(N / N_0) dB (powers add); one drop stands out of that background when its level exceeds it by
// a margin. masking_db() = 10 log10(max(1, rate / 100 per s)) follows the measured drop rate (smoothed
// over about 0.5 s), so below 100 drops per second nothing is masked.
// Rules, in order:
//   - full: L >= full_level_db (default +6 dB: a large or near drop, 3 mm and up at terminal speed
//     within 1 m) + masking, while fewer than max_full lattice drops are active and detail() allows it;
//   - template: L >= masking - texture_margin_db (default 20 dB below the background: still heard);
//   - texture: the rest (far or buried in the hiss of many).
// Load shedding: after every block the measured load (callback time over block period) is compared with
// the budget. Over it, detail() falls by (load / budget - 1) at once (fast attack: the next block is
// already cheaper), raising the full threshold by (1 - detail) * 40 dB and the template threshold by
// (1 - detail) * 30 dB; under it, detail() recovers at 0.5 per second (slow release, so it does not
// oscillate). Offline renders pass no measured load (end_block with load 0): the choice then depends only
// on the drops and the rate, so an offline render is reproducible to the sample.
// Pricing a lattice drop (live only: after the first observe_load). A lattice drop costs the audio thread
// far more than a template, and unevenly: about 10 % of a 64-frame block each block while it is awake,
// and in the blocks where it is spawned and shatters on the membrane (hundreds of links breaking, its
// pieces colliding) several times that. From each callback's measured load the governor learns:
//   base    the load of blocks with no lattice drop awake (one-pole, 0.5 s);
//   mean    one awake drop's share of the load above base, in blocks without a spawn or a break
//           ((load - base) / awake, one-pole, 0.25 s): its expected cost per block;
//   event   the worst block a spawn or a breakup gave: load - base - (awake - 1) mean, the excess one drop
//           caused, a running maximum that decays with a 120 s time constant (so drops are tried again
//           when the machine has become quieter);
//   recent  the load now (one-pole, 0.1 s).
// A drop is then admitted to the full tier only if, besides the rules above, its price fits:
//   recent + mean <= budget  (its expected cost keeps the mean under the budget), and
//   recent + event <= max(peak_budget, budget)  (its spawn and breakup block fits under the peak limit);
// otherwise it becomes a template (counted in counts().priced_out). Offline (no prior and nothing
// measured) every drop that the rules above choose is admitted.
// The prior (live): the first lattice drop would otherwise teach its event price by the block it
// overruns: a lattice drop's breakup on the canopy in air (775 links) took one 64-frame block to
// 230-260 % of the period (ameoto bench scene, 2026-12-06). The renderer gives set_lattice_prior, before
// its first block and after each scene change, what the impact templates' recordings of the same lattice
// drops on the same canopy cost this machine in a block's length, per recorded size
// (ImpactTemplateTable::worst_cpu_s, measured while the scene was built: a 1 mm drop's 4 % of a
// 64-frame period, a 3.5 mm drop's 33 %, the largest's (5.7 mm) 132 % on the 2-CPU VM). A drop's event price
// is never taken below its size's prior (the nearest recorded size in log D): unlike a measured block,
// which may hold the machine's noise and so fades, the prior is the drop's own work. Until the first load
// is measured (live: the stream's first callback, which also bears the stream's cold start, its page
// faults and cold caches) no lattice drop is admitted; lattice_affordable() then says whether the prior
// alone fits under the peak limit. (The only lattice block over the period in a 5-minute soak, 104 %, was
// a drop whose prior fitted, spawned in the first callback: docs/bench-realtime.md.) lattice_affordable()
// without a size, and lattice_price().prior, use the largest size's.
// Spacing (live only), because each price is one drop's and the worst blocks of two drops must not land
// together: a lattice drop is admitted
//   - at least full_spacing_s (default 0.1 s, the length of a 5 mm drop's spawn, impact and breakup:
//     docs/bench.md, "ameoto bench drop") after the previous one, and
//   - while the price is still being learned (until lattice drops have been awake for learning_s = 0.1 s
//     of measured blocks in all), only when no other lattice drop is in the scene: the first drop teaches
//     the price alone. Without this a scene that starts in heavy rain let four drops in before any was
//     priced, and their breakups in the same blocks took a 64-frame callback to 79 % (ameoto bench scene).
// Drops turned away by the spacing are counted with the priced-out ones.

#include <array>
#include <cstdint>

namespace ameoto {

enum class LodTier : std::uint8_t { full, template_, texture };

struct LodSettings {
    double budget = 0.4;               // fraction of the block period (/lod percent / 100), 0.01..0.95
    int max_full = 4;                  // lattice drops at once, 0..64
    double full_level_db = 6.0;        // relative to a 2 mm drop at 1 m
    double texture_margin_db = 20.0;   // below the masking level a drop becomes texture
    double peak_budget = 0.5;          // the most a lattice drop's worst block may reach (fraction of the
                                       // period): the 60 % target less a margin for the machine's own noise
    double full_spacing_s = 0.1;       // live: the least time between two lattice drops' admissions
};

// What the lattice drops did during one measured callback (for observe_load).
struct LatticeActivity {
    int awake = 0;         // lattice drops alive in the block (the most at once)
    bool event = false;    // one was spawned or links broke in it
};

// What the governor has learned a lattice drop costs, fractions of the block period (see the header).
struct LatticePrice {
    bool known = false;    // a load has been observed (live)
    double base = 0.0, mean = 0.0, event = 0.0, recent = 0.0;
    double prior = 0.0;    // the event price's floor for the costliest size (set_lattice_prior; 0 offline)
};

struct LodCounts {
    std::uint64_t full = 0, template_ = 0, texture = 0;
    std::uint64_t priced_out = 0;   // would have been full, but their price did not fit (live only)
};

class LodGovernor {
public:
    explicit LodGovernor(const LodSettings& settings = {}) : settings_(settings) {}

    void set_settings(const LodSettings& settings) { settings_ = settings; }
    const LodSettings& settings() const { return settings_; }

    LodTier choose(double diameter_m, double speed_m_per_s, double distance_m, int full_active);
    void end_block(double measured_load, int drops, double block_seconds);
    void observe_load(double measured_load, const LatticeActivity& activity, double block_seconds);
    // The event price's floor from now on (header): per size (diameters ascending, m; at most
    // max_prior_sizes of them, else their largest event for every size), or one for every size.
    static constexpr int max_prior_sizes = 64;
    void set_lattice_prior(const double* diameters_m, const double* events, int sizes);
    void set_lattice_prior(double event);
    bool lattice_affordable() const;                    // for the costliest size
    bool lattice_affordable(double diameter_m) const;   // for a drop of this size
    const LatticePrice& lattice_price() const { return price_; }

    double detail() const { return detail_; }
    double masking_db() const { return masking_db_; }
    const LodCounts& counts() const { return counts_; }   // drops given each tier so far

    static double level_db(double diameter_m, double speed_m_per_s, double distance_m);

private:
    LodSettings settings_;
    double detail_ = 1.0;
    double rate_per_s_ = 0.0;
    double masking_db_ = 0.0;
    LodCounts counts_;
    bool lattice_admissible(int full_active, double diameter_m) const;   // affordable, spaced, and not while learning alone
    double prior_for(double diameter_m) const;
    std::array<double, max_prior_sizes> prior_diameters_{}, prior_events_{};
    int prior_sizes_ = 0;   // 0: price_.prior for every size
    LatticePrice price_;
    bool base_seen_ = false;
    double since_full_s_ = 1e300;   // measured time since the last lattice drop was admitted (live)
    double measured_full_s_ = 0.0;  // measured blocks with a lattice drop awake, in all (live)
};

}  // namespace ameoto
