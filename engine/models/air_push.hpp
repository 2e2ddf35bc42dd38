// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A contact force's push, heard through the crossover's two halves: below, the part of the force the
// air takes at once (the instantaneous push) through the double layer, exact; above the canopy's modes,
// the force on a limp screen in compressible air, leaving from the node's tile. The modes' own sound,
// less that instantaneous part, goes through the low half (dipole_radiation.hpp).
//
// Interface (build phase: allocates; DipoleRadiation builds them when asked):
//   PushCrossover x = push_crossover(modes);          // x.hz == 0: no room above the modes at this rate
//   PushPoint p;                                      // the point as the dipoles see it: per node r, cos(theta)
//   PushScreen screen;                                // per node: areal density, tile radius
//   PushFilters f = design_push_filters(modes, x, screen, p, air);
//   f.offset[node], f.fir[node * f.taps + j]: a force F (N) applied to node for step n adds F * fir[j]
//   (Pa) to the pressure the point hears at sample n + offset + j. A node that cannot move has an
//   all-zero filter. offset is lead samples (0.5 ms) before the node's own delay r / c.
//   LowPassState s; s.process(x, y)                   // audio-safe: the modes' sound through the low half
//
// Why (docs/canopy-air.md, "The compressible push in the server"). A mode's acceleration is
// phi_k' f - w_k^2 q_k - 2 s_k q_k'. Summed over the modes, the first term puts the instantaneous push M_a (M + M_a)^-1 f on the air
// (AirCanopyModes::instantaneous_push: for a newton on the default canopy's panel centroid, 38 % on the
// node and 54 % on the nodes round it). Each mode's taps are fitted at its pole, where that term is
// heard at the wrong gain away from it; so the taps hear each mode's acceleration less its kick, and
// each node's column of M_a (M + M_a)^-1 is heard here, every node of it as a point force (the dipole of
// dipole_radiation.hpp) at its own delay. Against the 5 mm reference the server's modes heard through
// the exact double layer miss nothing from 63 Hz to 1 kHz (docs/canopy-air.md).
// Above the lattice's highest mode in air (963 Hz on the default canopy) what is heard of a drop is its
// push. Incompressible air carries it as that instantaneous column; real air can be compressed: on an
// infinite limp screen of areal density s, the jump a point force f sends towards theta from the
// normal is
//   f / (1 + i beta |cos(theta)|),  beta = omega s / (2 rho0 c)
// (the fabric's impedance i omega s against both faces' radiation impedance rho0 c / cos(theta) at the
// trace wavenumber k sin(theta); with incompressible air the faces' impedance is a mass, 2 rho0 /
// (k sin(theta)), whence 1 / (1 + beta sin(theta))). Heard as the node's point force, it came within 3 dB
// of the 10 mm reference in 56 of 63 band-listener pairs from 1 to 4 kHz (docs/canopy-air.md).
// The crossover: Linkwitz-Riley of order 8 (two fourth-order Butterworths in series, bilinear with the
// corner prewarped), at 1.2 x the highest mode: its halves are in phase and sum to an all-pass, so the
// two join without a notch. Linkwitz, "Active crossover networks for noncoincident drivers", JAES 24
// (1976). Why 1.2: the modes' own sound is cut by the low half, and the nearer the corner, the more of
// their highest it costs (1.8 dB at 1.2 x).
// Each node's compressible push leaves from its tile, not a point: the lattice's node is the fabric of its cell
// (about 5 cm across on the default canopy), which moves with it in the added mass (air_loading.hpp)
// and in the reference alike, so its pressure jump spreads over the cell. Heard as a disc of the
// node's area (radius a = sqrt(A / pi)) with a uniform jump, its far field carries the disc's
// directivity 2 J1(k a sin(theta)) / (k a sin(theta)) (Kinsler et al., Fundamentals of Acoustics,
// 4th ed., 2000, s. 7.4): -2.8 dB at 4 kHz 63 degrees off the normal, under 0.2 dB below 1 kHz.
// A continuous fabric struck by a drop would have no tile (tile_radius 0: a point force).
// Each filter, node e, is
//   H(omega) = 1 / (4 pi) (e^{i omega T} - 1) / (i omega T) x [ L(omega) sum_i P_ie G_i(omega)
//              + Hi(omega) G_e(omega) / (1 + i beta |cos(theta_e)|) x 2 J1(k a sin(theta_e)) / (k a sin(theta_e)) ],
//   G_i(omega) = cos(theta_i) (1 / r_i^2 + i omega / (c r_i)) e^{-i omega r_i / c},
// P = M_a (M + M_a)^-1, L and Hi the halves, the force held over the step (heard at the step's end);
// rolled off over 0.35-0.45 of the rate so that it rings for a few samples only before r_e / c; from
// 0.5 ms before r_e / c, 5.2 ms long (250 taps at 48 kHz), both ends tapered. The column's sum is taken
// to 4 x the corner only, where L is 96 dB down (two real matrix products, P' G, over those bins).
// The delay is each node's own: the taps no longer carry the push, so nothing the filter could cancel
// arrives at the modes' bulk delay. (While the taps carried it, at gains tuned to their poles, a push at
// r / c cancelled theirs where the halves overlap and the filters ran at the modes' bulk delay instead.)

#include <vector>

#include "engine/core/biquad.hpp"
#include "engine/models/air_canopy.hpp"
#include "engine/models/radiation.hpp"

namespace ameoto {

struct PushCrossover {
    double hz = 0.0;          // the corner (0: none)
    Biquad low[4], high[4];   // each half: four sections in series
};

struct PushPoint {
    std::vector<double> r, cos_theta;   // per node (panel-major): distance (m, floored as the dipoles'), cos(theta)
};

struct PushScreen {
    std::vector<double> areal_density;   // per node (panel-major), kg/m^2; 0: the node cannot move
    std::vector<double> tile_radius;     // per node, m: the disc of the node's area its push leaves from (0: a point)
};

struct PushFilters {
    int taps = 0;
    std::vector<int> offset;    // per node, samples from the step
    std::vector<double> fir;    // [node * taps + j], Pa/N
};

// At 1.2 x the highest kept mode; none (hz 0) where that is above 0.3 of the rate or no mode is kept.
PushCrossover push_crossover(const AirCanopyModes& modes);

PushFilters design_push_filters(const AirCanopyModes& modes, const PushCrossover& crossover, const PushScreen& screen, const PushPoint& point,
                                const AirMedium& air);

// A uniform disc's far-field directivity, 2 J1(x) / x at x = k a sin(theta) (1 at x = 0).
double tile_directivity(double k_a_sin_theta);

// The low half, run on a channel's modal sound. Audio-safe.
struct LowPassState {
    BiquadState section[4];
    double process(const PushCrossover& crossover, double x) {
        for (int i = 0; i < 4; ++i) x = section[i].process(crossover.low[i], x);
        return x;
    }
    void reset() { *this = LowPassState{}; }
};

}  // namespace ameoto
