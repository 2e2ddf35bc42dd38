// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A contact force's push above the canopy's modes, heard through compressible air. A crossover above
// the highest mode splits the sound: below it the modes and their taps (dipole_radiation.hpp), above it
// each force the canopy takes, played through its node's short filter: a force on a limp screen in
// compressible air, leaving from the node's tile.
//
// Interface (build phase: allocates; DipoleRadiation builds them when asked):
//   PushCrossover x = push_crossover(modes);          // x.hz == 0: no room above the modes at this rate
//   PushPoint p;                                      // the point as the dipoles see it: per node r,
//                                                     // cos(theta); the modes' bulk delay D
//   PushScreen screen;                                // per node: areal density, tile radius
//   PushFilters f = design_push_filters(modes, x, screen, p, air);
//   f.offset[node], f.fir[node * f.taps + j]: a force F (N) applied to node for step n adds F * fir[j]
//   (Pa) to the pressure the point hears at sample n + offset + j (the sample at which the modes' taps
//   put p(t_n)). A node that cannot move has an all-zero filter.
//   LowPassState s; s.process(x, y)                   // audio-safe: the modes' sound through the low half
//
// Why (docs/canopy-air.md, "The air compressible"). Above the lattice's highest mode in air (963 Hz on
// the default canopy) what is heard of a drop is its push: the force the struck node and the air next
// to it put on the air. The modes carry it as the incompressible jump M_a (M + M_a)^-1 f, heard through
// taps fitted at the modes' poles: up to 8 dB off the reference from 1.26 to 4 kHz. Real air can be
// compressed: on an infinite limp screen of areal density s, the jump a point force f sends towards
// theta from the normal is
//   f / (1 + i beta |cos(theta)|),  beta = omega s / (2 rho0 c)
// (the fabric's impedance i omega s against both faces' radiation impedance rho0 c / cos(theta) at the
// trace wavenumber k sin(theta); with incompressible air the faces' impedance is a mass, 2 rho0 /
// (k sin(theta)), whence 1 / (1 + beta sin(theta))). Heard as the node's point force (the dipole of
// dipole_radiation.hpp), it came within 3 dB of the 10 mm reference in 56 of 63 band-listener pairs
// from 1 to 4 kHz (docs/canopy-air.md).
// The crossover: Linkwitz-Riley of order 8 (two fourth-order Butterworths in series, bilinear with the
// corner prewarped), at 1.2 x the highest mode: its halves are in phase and sum to an all-pass, so the
// modes below and the push above join without a notch, and the highest mode loses 1.8 dB to it.
// Linkwitz, "Active crossover networks for noncoincident drivers", JAES 24 (1976). Why 1.2: above the
// highest mode the modes' taps carry the push at gains tuned to their poles, so the less of the band
// above the modes they carry, the better; a corner nearer the modes costs their highest more. Against
// the 5, 7.5 and 10 mm references (171 band-listener pairs each) 1.1 / 1.2 / 1.3 / 1.4 x the highest
// mode miss 3 dB in 21 / 22 / 24 / 25 pairs in all, with the highest mode 3.3 / 1.8 / 1.0 / 0.57 dB down
// (docs/canopy-air.md).
// Each node's push leaves from its tile, not a point: the lattice's node is the fabric of its cell
// (about 5 cm across on the default canopy), which moves with it in the added mass (air_loading.hpp)
// and in the reference alike, so its pressure jump spreads over the cell. Heard as a disc of the
// node's area (radius a = sqrt(A / pi)) with a uniform jump, its far field carries the disc's
// directivity 2 J1(k a sin(theta)) / (k a sin(theta)) (Kinsler et al., Fundamentals of Acoustics,
// 4th ed., 2000, s. 7.4): -2.8 dB at 4 kHz 63 degrees off the normal, under 0.2 dB below 1 kHz, so the
// modes' taps keep their points. Against the 5 mm reference the side's 2.5-4 kHz bands are within
// +2.1 dB from the tile, up to +4.2 from a point (docs/canopy-air.md). A continuous fabric struck by a drop would have
// no tile (tile_radius 0: a point force).
// Each filter is the high half times
//   H(omega) = cos(theta) / (4 pi) (1 / r^2 + i omega / (c r)) e^{-i omega D T} / (1 + i beta |cos(theta)|)
//              x 2 J1(k a sin(theta)) / (k a sin(theta)) x (e^{i omega T} - 1) / (i omega T)
// (the force held over the step, heard at the step's end), rolled off over 0.35-0.45 of the rate so
// that it rings for a few samples only before D; from 0.5 ms before D, 5.2 ms long (250 taps at 48 kHz),
// both ends tapered: 90 dB down below 500 Hz.
// The delay is the modes' bulk delay D (the nearest node's), not the struck node's own r / c: the
// modes' taps hear a contact's push at D (each mode's taps are exact at its pole only; 0.4 ms early for
// the default canopy's centroid heard 0.3 m under the shaft), and where the crossover's halves overlap
// a push at r / c cancels theirs: 6-7 dB holes in the 1.26 kHz band against the reference. A delay
// gliding from D at the crossover to r / c above it was tried: its filters rang 1.5 ms ahead of D and
// were 60 dB down at DC at best, at twice the length (docs/canopy-air.md).

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
    int delay = 0;                      // D: the modes' bulk delay for the point, samples (dipole_radiation.hpp)
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
