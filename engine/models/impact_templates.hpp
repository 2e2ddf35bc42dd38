// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The template level of detail: the force a drop puts on the membrane, recorded once from the full model
// (a lattice drop on the canopy, drop_on_canopy.hpp) for a grid of diameters, then replayed into the
// nearest membrane node for every drop of the rain: the full model's impact at a fraction of its cost.
//
// Interface:
//   ImpactTemplateTable t = record_impact_templates(scene_config);   // off the audio thread (~0.15 s of
//                                                                    // CPU): one full-model run per grid
//                                                                    // size, on up to 4 threads (one per
//                                                                    // CPU); the same table on any number
//   record_impact_templates(scene_config, grid, 1)                   // on the calling thread only
//   record_impact_templates(scene_config, grid, 0, CanopyBuild::per_size)   // a canopy built per size
//                                                                    // (the same table, slower: tests)
//   record_impact_templates(scene_config, prototype)                 // from the caller's canopy, never
//                                                                    // stepped (UmbrellaScene's own)
//   t.diameters_m[k], t.speeds_m_per_s[k], t.force(k, n)             // the recording, N along the normal
//   ---- audio thread: no allocation ----
//   TemplatePool pool;                                               // fixed capacity
//   bool ok = pool.add(hit, t, D, V, density);                       // false: full (count it) or no table
//   pool.emit(t, [&](CanopyHit hit, double newtons) { canopy.apply_force(hit, newtons); });   // each sample
//   pool.active()
//
// Recording: for each grid diameter d_k (log-spaced, 0.5 to 6 mm: the rain's range, physics.md s.2),
// a fresh scene (its canopy copied from one built once per call: the same scene, bit for bit) of the caller's material, liquid, geometry and sample rate receives one drop at its
// arrival speed V_k, half way out along panel 0's centre line, and the contact force the membrane
// takes (DropOnCanopy::contact_force, along the surface normal there) is recorded for `seconds`
// (20 ms: the first impact and its splash; pieces thrown up fall back much later, and the template
// leaves those later strikes out).
// Replay: a drop (D, V, rho) plays the nearest grid size's recording scaled by the impact law
// F ~ rho V^2 D^2 over a duration ~ D / V (Soto et al. 2014; Gordillo et al. 2018: the peak force
// 0.8 rho V^2 D^2 and the time D / V, both from the same inertial scaling): amplitude
// (rho / rho_k) (V / V_k)^2 (D / d_k)^2 and playback rate (V / V_k) (d_k / D), read by linear
// interpolation, so the impulse scales as rho V D^3, the drop's momentum. The grid is fine (5 % steps
// in D), so the scaling corrects only small differences; the lattice's own behaviour at each size
// (its mass count, its breakup) is what was recorded.
// Accuracy against the full model: tests/engine/models/impact_templates_test.cpp compares the sound of
// the same drops, template against full, by log-spectral distance (within 3 dB).

#include <cstdint>
#include <vector>

#include "engine/models/canopy.hpp"
#include "engine/models/drop_on_canopy.hpp"

namespace ameoto {

struct ImpactTemplateTable {
    double sample_rate = 0.0;                // Hz: the recording's
    double density = 0.0;                    // kg/m^3: the recorded liquid's
    std::vector<double> diameters_m;         // grid, ascending
    std::vector<double> speeds_m_per_s;      // arrival speed of each
    int length = 0;                          // samples per recording (the stride of `forces`)
    std::vector<int> used;                   // per size: samples up to the last non-zero force (playback ends there)
    std::vector<double> forces;              // [k * length + n], N on the membrane along +n (negative: down)
    // What each recording cost on this machine: its run's thread CPU time, cumulative at every cpu_chunk
    // samples, [k * (cpu_chunks + 1) + c] after c chunks. Measured, so it differs from run to run: only
    // the governor's first price of a lattice drop reads it (worst_cpu_s; lod_governor.hpp).
    static constexpr int cpu_chunk = 16;
    int cpu_chunks = 0;
    std::vector<double> cpu_s;

    bool empty() const { return diameters_m.empty(); }
    double force(int k, int n) const { return forces[static_cast<std::size_t>(k * length + n)]; }
    int nearest(double diameter_m) const;    // grid index nearest in log D
    // The most CPU time (s) recording k took in `frames` consecutive samples (windows starting on a
    // chunk): what a lattice drop of that size's spawn and breakup may add to a block of that length;
    // without k, the most of any size. Audio-safe.
    double worst_cpu_s(int frames, int k) const;
    double worst_cpu_s(int frames) const;
};

struct TemplateGrid {
    double min_diameter_m = 0.5e-3, max_diameter_m = 6e-3;
    double step_ratio = 1.05;                // successive diameters
    double seconds = 0.02;                   // recorded per size
};

// How each recording run gets its canopy: shared (built once per call, each run starting from a copy:
// DropOnCanopy(config, prototype)) or per_size (each run builds its own, as before; kept to test that
// the two give the same table bit for bit). texture_grains.hpp's calibration takes the same choice.
enum class CanopyBuild { shared, per_size };

// Throws what DropOnCanopy throws for a bad configuration. threads <= 0: one per CPU, at most 4 (the
// sizes are independent runs, so the table is identical whatever the count; the start-up of ameotod
// waits for it, and that wait halves on two CPUs).
ImpactTemplateTable record_impact_templates(const DropOnCanopyConfig& scene, const TemplateGrid& grid = {}, int threads = 0,
                                            CanopyBuild build = CanopyBuild::shared);
// The same table from the caller's canopy instead of one built here: DropOnCanopy::fresh_canopy(scene) or
// a copy of one never stepped (its geometry is checked; its material, rate, integrator and air are the
// caller's promise, as for DropOnCanopy(config, prototype)). UmbrellaScene builds one canopy for the
// scene, its templates and its texture: in air each build is the air-loaded modes' (~0.6 s).
ImpactTemplateTable record_impact_templates(const DropOnCanopyConfig& scene, const Canopy& prototype, const TemplateGrid& grid = {},
                                            int threads = 0);

class TemplatePool {
public:
    static constexpr int capacity = 2048;

    bool add(CanopyHit target, const ImpactTemplateTable& table, double diameter_m, double speed_m_per_s, double density);

    template <typename Sink>
    void emit(const ImpactTemplateTable& table, Sink&& sink) {
        for (int i = 0; i < count_;) {
            Playing& p = playing_[static_cast<std::size_t>(i)];
            const auto n = static_cast<int>(p.position);
            const double frac = p.position - n;
            const double f0 = table.force(p.index, n);
            const int used = table.used[static_cast<std::size_t>(p.index)];
            const double f1 = n + 1 < used ? table.force(p.index, n + 1) : 0.0;
            sink(p.target, p.gain * (f0 + frac * (f1 - f0)));
            p.position += p.rate;
            if (p.position >= used) {
                playing_[static_cast<std::size_t>(i)] = playing_[static_cast<std::size_t>(--count_)];
            } else {
                ++i;
            }
        }
    }

    int active() const { return count_; }
    void clear() { count_ = 0; }

private:
    struct Playing {
        CanopyHit target;
        int index = 0;
        double position = 0.0, rate = 1.0, gain = 1.0;
    };
    Playing playing_[capacity];
    int count_ = 0;
};

}  // namespace ameoto
