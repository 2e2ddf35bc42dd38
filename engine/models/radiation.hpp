// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Sound from the canopy: the seed's single-mass pickup, and the far-field pressure at listening points
// by the Rayleigh integral over the membrane, with each element's own distance and delay.
//
// Interface:
//   MassPickup pick(canopy, panel, node);             // the seed's output (section 5.2): u / full scale
//   MassPickup pick(canopy, panel, node, 1e-3);       // full scale given (m)
//   MassPickup pick = MassPickup::at(canopy, x, y);   // the node under a plan point
//   double s = pick.sample(canopy);                   // after canopy.step()
//   pick.full_scale_m()                               // default: the node's static deflection under 10 N,
//                                                     // 10 N / K_ii (its anchors and links): 2.9 mm for
//                                                     // nylon, 14 mm vinyl, 1.4 nm seed-nylon, so each
//                                                     // material's output has a comparable level
//
//   ListenerLayout mono = ListenerLayout::mono({0, 0, -0.3});
//   ListenerLayout ears = ListenerLayout::ears({0, 0, -0.3}, facing_azimuth_rad, 0.18);   // ch 0 left, 1 right
//   ListenerLayout ring = ListenerLayout::panned({0, 0, -0.3}, gains);   // gains[channel][panel]
//   FarFieldRadiation ff(canopy, ears, time_step_s);  // allocates the taps and pending pressures
//   ff.process(canopy, pressures_pa);                 // after canopy.step(): one pressure per channel;
//                                                     // never allocates
//
//   RayleighRadiator r(elements, points, groups, T);  // the sum itself, for any set of elements
//   r.process(accelerations, out);                    // out[point * groups + group], Pa
//   r.read_inputs_at(index, length);                  // build phase: process() then reads element e's
//                                                     // acceleration at accelerations[index[e]] of
//                                                     // length (the canopy's node-major lanes)
//   r.inputs(), r.process_inputs(out)                 // the same, the caller writing the (finite)
//                                                     // inputs in place: no copy
//
// Far field (the seed's future work, section 6): the Rayleigh integral (Rayleigh's first integral;
// Kinsler et al., Fundamentals of Acoustics, 4th ed., section 7.4) gives the pressure radiated into the
// half-space in front of a plane baffled surface by its normal acceleration a_n:
//   p(x, t) = (rho0 / 2 pi) integral a_n(y, t - |x - y| / c) / |x - y| dS(y),
// which the membrane's nodes discretise (node i: area A_i, distance r_i to the listening point):
//   p(t) = rho0 / (2 pi) sum_i A_i a_n,i(t - r_i / c) / r_i.
// a_n,i is node i's acceleration along the normal that faces the listening point (sign of
// (x - y_i) . n_i: a listener under the canopy hears -a), taken as the step's mean acceleration
// (v_i[n] - v_i[n-1]) / T; A_i is the node's plan area (the area its mass s A_i stands for). With those,
// sum_i A_i a_i = sum_i m_i a_i / s = F_net / s, the panel's net force over its areal density, so when
// every r_i is the same r this is exactly the renderer's baffled piston rho0 F_net / (2 pi r s)
// (engine/render/renderer.hpp; checked in tests/engine/models/radiation_test.cpp).
// Delays: each (point, node) pair has its own delay r_i / c, D = r_i / (c T) samples, applied by linear
// interpolation between samples floor(D) and floor(D) + 1 (Laakso et al., IEEE SP Magazine 13(1), 1996:
// a first-order fractional delay, exact at integer D; worst at a half-sample fraction, where its gain is
// cos(pi f T): -3 dB at fs / 4, 12 kHz at 48 kHz). With g_i the node's gain and f its fraction,
//   p[n] = sum_i w0_i a_i[n - floor D_i] + w1_i a_i[n - floor D_i - 1],   w0 = (1 - f) g, w1 = f g.
// The sum is linear in the a_i, so it is computed forwards (scattered) rather than read back
// (gathered): each sample, node i adds w0_i a_i[n] into its output's accumulator floor(D_i) samples
// ahead and w1_i a_i[n] into the one after, in a preallocated row of future pressures per (point,
// group); the row's entry for the current sample is this sample's output, cleared once read. Same sum,
// added in another order (rounding only: under 1e-15 of the peak against the per-node delay lines it
// replaced, tests/engine/models/radiation_test.cpp), and no per-node history: one two-wide
// multiply-add per (point, node) into rows small enough for L1 (points x groups x 264 doubles: 17 KB
// mono) instead of two reads per pair from one delay line per node (400 nodes x 128 samples: 400 KB)
// and a serial sum per group. Distances are from the rest positions: the displacements are
// micrometres against wavelengths of centimetres or more.
// Distance floor: a point closer to a node than a_eq / 2, a_eq = sqrt(A_i / pi), uses a_eq / 2: the
// Rayleigh integral over a disc of area A_i seen from its own centre is rho0 a_n a_eq, the same.
// What is approximated: the canopy is not baffled (air flows round the hem and the gaps between panels,
// so below the panel's coincidence the two faces partly cancel: the Rayleigh sum overestimates the low
// frequencies of a small unbaffled membrane, which radiates more like a dipole there), it is curved
// rather than plane (each element radiates along its own normal; shading by the canopy itself and
// reflections are ignored), the air does not load the membrane (no radiation damping or added mass),
// and the lattice's element size limits the sum to wavelengths longer than a few spacings.
// Channels: each output channel hears one listening point (mono: one point; stereo: two ears 0.18 m
// apart on the listener's left-right axis, so the inter-aural delay and level differences come from the
// geometry), optionally weighted per panel (a ring of speakers: one point, panned gains per panel).

#include <cstdint>
#include <vector>

#include "engine/core/body3d_vec3.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/models/canopy.hpp"

namespace ameoto {

class MassPickup {
public:
    static constexpr double reference_force_n = 10.0;   // for the default full scale

    // full_scale_m <= 0: the default (header).
    MassPickup(const Canopy& canopy, int panel, int node, double full_scale_m = 0.0);
    static MassPickup at(const Canopy& canopy, double x, double y, double full_scale_m = 0.0);
    double sample(const Canopy& canopy) const { return canopy.displacement(panel_, node_) / full_scale_m_; }
    int panel() const { return panel_; }
    int node() const { return node_; }
    double full_scale_m() const { return full_scale_m_; }

private:
    int panel_ = 0, node_ = 0;
    double full_scale_m_ = 1e-3;
};

struct AirMedium {
    double density = constants::air_density;            // rho0, kg/m^3
    double speed_of_sound = constants::speed_of_sound_air;   // c, m/s
};

struct RadiatingElement {
    Vec3 position;    // m
    Vec3 normal;      // unit
    double area = 0.0;   // m^2
    int group = 0;    // elements summed together (a panel)
};

class RayleighRadiator {
public:
    RayleighRadiator() = default;
    RayleighRadiator(std::vector<RadiatingElement> elements, std::vector<Vec3> points, int groups, double time_step_s,
                     const AirMedium& air = AirMedium{});

    // One sample: accelerations[e] (m/s^2, along element e's normal); out[point * groups + group] (Pa)
    // is overwritten. Non-finite accelerations count as 0.
    void process(const double* accelerations, double* out);
    // Build phase (allocates): element e's input is accelerations[index[e]], 0 <= index[e] < length, the
    // entries no element reads being ignored; the taps, their order and the sums are unchanged.
    void read_inputs_at(const std::vector<std::int32_t>& index, int length);
    // process() without its copy: the caller has written this sample's accelerations, every one finite
    // (non-finite ones as 0), into inputs()[0 .. input_count()) in the input layout. Never allocates.
    double* inputs() { return input_.data(); }
    int input_count() const { return static_cast<int>(input_.size()); }
    void process_inputs(double* out);
    void reset();   // clears the pending pressures: silence until the next non-zero input

    int element_count() const { return elements_; }
    int point_count() const { return static_cast<int>(points_.size()); }
    int group_count() const { return groups_; }
    int history_length() const { return run_; }   // samples of delay it holds: a power of two above
                                                  // the longest floor(D) + 1
    double distance(int point, int element) const;        // m, r_i (after the floor)
    double delay_samples(int point, int element) const;   // r_i / (c T)
    double gain(int point, int element) const;            // Pa per m/s^2: +-rho0 A / (2 pi r)

private:
    std::vector<Vec3> points_;
    int elements_ = 0, groups_ = 1;
    // The queries, point-major in the caller's element order: [point * elements + element].
    std::vector<double> distance_, delay_, gain_;
    // The taps, structure of arrays, point-major: [point * elements + t], t in scatter order (the same
    // for every point; source_[t] is the element tap t reads). target_: (point * groups + group) *
    // row_ + floor(D), the accumulator (relative to the current sample) that receives w0 a; w1 a goes
    // to the next one, so weights_ holds the pair (w0, w1) = ((1 - frac) g, frac g) side by side and
    // one tap is one two-wide multiply-add on two adjacent doubles.
    std::vector<std::int32_t> source_, target_;
    std::vector<double> weights_;       // [2 (point * elements + t)], [... + 1]
    std::vector<double> input_;         // this sample's accelerations, caller's order (or the layout
                                        // read_inputs_at() gave), non-finite: 0
    // Future pressures, one row of row_ = 2 run_ + 8 samples per (point, group); now_ runs from 0 to
    // run_ - 1 and taps reach at most span_ (the longest floor(D) + 1 < run_) samples ahead, so they
    // stay inside the row without a wrap-around mask; when now_ reaches run_, the span_ samples ahead
    // move back to the row's front (every earlier sample was read and cleared). The 8 (a cache line)
    // keep rows from lying a power of two apart: panels at the same distance add into the same column
    // one after the other, and a load 4 KiB from a pending store waits for it (4K aliasing; measured
    // 15 % slower without).
    std::vector<double> pending_;
    int run_ = 1, span_ = 0, row_ = 2, now_ = 0;
};

struct ListenerLayout {
    std::vector<Vec3> points;                        // listening points, canopy coordinates (m)
    std::vector<int> channel_point;                  // which point each output channel hears
    std::vector<std::vector<double>> panel_gain;     // [channel][panel]; empty: 1 for every panel

    static ListenerLayout mono(Vec3 at);
    // Two ears, spacing apart on the left-right axis of a head facing `facing_azimuth` (0: +x; the left
    // ear is counter-clockwise from the facing direction, as the renderer's azimuths).
    static ListenerLayout ears(Vec3 head, double facing_azimuth_rad = 0.0, double spacing_m = 0.18);
    static ListenerLayout panned(Vec3 at, std::vector<std::vector<double>> gains);
    int channels() const { return static_cast<int>(channel_point.size()); }
};

class FarFieldRadiation {
public:
    FarFieldRadiation(const Canopy& canopy, const ListenerLayout& layout, double time_step_s,
                      const AirMedium& air = AirMedium{});

    // Call once after every canopy.step(): pressures_pa[channel] for each channel of the layout. It
    // hears the canopy it was built for (one FarFieldRadiation per canopy: build a new one with a new
    // canopy, off the audio thread); a canopy of another shape (panels, nodes) is not read: silence.
    void process(const Canopy& canopy, double* pressures_pa);

    // Any thread that owns it (the audio thread), no allocation: the panel gains glide linearly from where
    // they are to gains[channel * panels + panel] over glide_frames samples (0: at once). The head's turn
    // on the panned formats (DropOnCanopy::turn_head): the pressures summed per panel are the same, only
    // their mix over the speakers moves. A layout without panel gains (ears, mono) keeps its own.
    void set_panel_gains(const double* gains, int glide_frames);
    bool gains_gliding() const { return glide_left_ > 0; }

    int channels() const { return layout_.channels(); }
    const RayleighRadiator& radiator() const { return radiator_; }
    const ListenerLayout& layout() const { return layout_; }

private:
    ListenerLayout layout_;
    RayleighRadiator radiator_;
    double inverse_dt_ = 0.0;
    int panels_ = 0, nodes_ = 0, lanes_ = 0;
    // The canopy's node-major layout (Canopy::velocities): [node * lanes_ + panel], padding lanes unread.
    std::vector<double> velocity_, previous_velocity_, sums_;
    std::vector<double> flat_gain_;                 // [channel * panels + panel]
    std::vector<double> gain_target_, gain_step_;   // the glide of set_panel_gains (same layout)
    int glide_left_ = 0;
    std::vector<std::uint64_t> resets_seen_;        // per panel: the guard's reset count at the last sample
};

}  // namespace ameoto
