// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The canopy in air, fast model against reference, in third-octave band levels (issue 19, part 2):
// a raised-cosine strike (or a given force) on one node, heard at listening points by the reference
// (engine/reference/canopy_in_air.hpp: the box's own pressure where a point lies inside it, the double
// layer of its nodes' forces on the air beyond, screen_far_field.hpp) and by the fast model (the
// canopy's air-loaded modes, engine/models/air_canopy.hpp, heard as dipoles, dipole_radiation.hpp, at
// 48 kHz). Offline; allocates.
//
// Interface:
//   CanopyBandsSetup s;  s.reference.dx = 0.01; s.reference.node = 12;   // the reference's setup
//   CanopyBandsResult r = compare_canopy_bands(s);   // r.fast[l], r.reference[l]: band levels per listener
//   r.difference(l, b)                               // dB, fast - reference
//   FastCanopyBands f = fast_canopy_bands(s, node);  // the fast model's levels alone (seconds, no reference)
//   fast_canopy_bands(s, canopy_in_air, node)        // the same on a canopy whose air is built

#include <vector>

#include "engine/core/body3d_vec3.hpp"
#include "engine/models/canopy.hpp"
#include "engine/reference/canopy_in_air.hpp"
#include "engine/reference/screen_far_field.hpp"

namespace ameoto::reference {

struct CanopyBandsSetup {
    CanopyInAirSetup reference;       // strike, grid, duration; its listeners are replaced by `listeners`
    std::vector<Vec3> listeners{{0.0, 0.0, -0.3}, {1.0, 0.0, -0.3}, {0.0, 0.0, -3.0}};
    double low_hz = 80.0, high_hz = 630.0;
    BandFilter bands = BandFilter::ideal;   // how the levels are read (screen_far_field.hpp)
    double fast_rate_hz = 48000.0;
};

struct CanopyBandsResult {
    std::vector<std::vector<BandLevel>> fast, reference;   // [listener][band]
    std::vector<std::vector<BandLevel>> fast_push;         // the fast model with the compressible push (air_push.hpp)
    // The signals the levels were read from (Pa; for other band filters, screen_far_field.hpp): the
    // reference's per listener every reference_interval_s, the fast model's every 1 / fast_rate_hz.
    std::vector<std::vector<double>> reference_pressure, fast_pressure, fast_push_pressure;
    double reference_interval_s = 0.0;
    std::vector<bool> inside_box;                          // per listener: the box's pressure (else the double layer)
    int struck_node = -1;
    double reference_seconds = 0.0;                        // the reference's run time (wall clock)
    double difference(int listener, int band) const {
        return fast[static_cast<std::size_t>(listener)][static_cast<std::size_t>(band)].level_db -
               reference[static_cast<std::size_t>(listener)][static_cast<std::size_t>(band)].level_db;
    }
};

CanopyBandsResult compare_canopy_bands(const CanopyBandsSetup& setup);

// The fast model's side alone (no reference run): the same strike on `node` of setup.reference.panel
// heard at setup.listeners by the canopy's air-loaded modes without (fast) and with (fast_push) the
// compressible push, as compare_canopy_bands plays it. For comparisons against cached reference levels.
struct FastCanopyBands {
    std::vector<std::vector<BandLevel>> fast, fast_push;               // [listener][band]
    std::vector<std::vector<double>> fast_pressure, fast_push_pressure;  // [listener][sample], Pa
};
FastCanopyBands fast_canopy_bands(const CanopyBandsSetup& setup, int node);
// The same with the canopy in air already built and never stepped (setup.reference's geometry and
// material, in air at setup.fast_rate_hz): several strikes share one build of its modes (about 0.3 s).
FastCanopyBands fast_canopy_bands(const CanopyBandsSetup& setup, const Canopy& in_air, int node);

// The reference's nodes as point forces on the air, for double_layer_pressure (screen_far_field.hpp):
// each node's rest position and normal, and the force it put on the air at each recorded sample (the
// air's recorded force on it, reversed). Needs a run with record_forces.
struct NodeForcesOnAir {
    std::vector<Vec3> positions, normals;
    std::vector<std::vector<double>> force;   // [node][sample], N
};
NodeForcesOnAir node_forces_on_air(const Canopy& canopy, const CanopyInAirResult& run);

}  // namespace ameoto::reference
