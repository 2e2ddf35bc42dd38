// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The sound of the canopy in air (air_canopy.hpp) at each listening point: no baffle, so each face of
// the membrane pushes the air with the opposite sign and every node is a dipole (a point force on the
// air along its normal), not the baffled monopole of the Rayleigh integral (radiation.hpp).
//
// Interface:
//   DipoleRadiation d(canopy, layout, T);       // build phase (allocates): canopy.in_air() required,
//                                               // else std::invalid_argument
//   d.process(canopy, pressures_pa);            // after canopy.step(): one pressure per channel, Pa;
//                                               // never allocates
//   d.delay_samples(channel)                    // D: the bulk delay (the nearest node's, whole samples)
//   d.coefficients(channel, mode)               // {A, B}: the mode's two taps (below)
//   d.tap(channel, index, set), d.state_taps()  // with the push: its four sets (below)
//   d.push_filters(point)                       // with options.compressible_push: the point's filters
//   DipoleRadiation e(canopy, layout, T, air, options, &d);   // the same, sharing d's push filters for
//                                               // every point designed alike (build phase; below)
//
// Source. A thin screen in free air is a double layer: the pressure at x is
//   p(x) = integral over the screen of Delta p(y) dG/dn_y dS(y),  G = e^{-ikr} / (4 pi r)
// (the Kirchhoff-Helmholtz integral of a surface of zero thickness, whose single-layer terms cancel
// between the faces; Pierce, Acoustics, 1989, section 4.3; Morse & Ingard, Theoretical Acoustics, 1968,
// section 7.1). Node i's share, its pressure jump times its area, is the force F_i it puts on the air
// along its normal n_i; in the time domain each is a point force (a dipole, Lighthill's analogy:
// Dowling & Ffowcs Williams, Sound and Sources of Sound, 1983, section 2.6):
//   p(x, t) = sum_i cos(theta_i) / (4 pi) [ F_i'(t - r_i / c) / (c r_i) + F_i(t - r_i / c) / r_i^2 ],
// r_i = |x - y_i|, cos(theta_i) = (x - y_i) . n_i / r_i (a listener under the canopy hears -F). With the
// potential's jump mu (Delta p = -rho0 d mu / dt, linearised Bernoulli) this is the brief's form
// p = rho0 sum_i A_i d/dt [ mu_i d/dn G(x, y_i) ] with the far (F') and near (F / r^2) terms.
// The force: the air's incompressible near field (air_loading.hpp), F = M_a u'' = sum_k (M_a phi_k) q_k'',
// the same pressure jump that loads the modes (and whose far field is radiation_damping's source).
// It holds the instantaneous part of a drop's force as well: the kick a contact gives the modes
// carries through q'' at once, (M_a (M + M_a)^-1) f.
// Per mode and listener. Mode k's free motion is q_k = Re(C e^{lambda t}), lambda = -s_k + i w_d, so
// F_i' = lambda F_i and a shift by Delta multiplies by e^{-lambda Delta}: the node sum is one complex gain
//   H_k = sum_i g_i cos(theta_i) (M_a phi_k)_i / (4 pi) e^{-lambda Delta_i} (1 / r_i^2 + lambda / (c r_i)),
// with Delta_i = r_i / c - D T >= 0 (D: the nearest node's delay in whole samples) and g_i the panel's
// pan gain (1 for a point). The modes deliver their mean acceleration over each step,
// abar[n] = (q'[n] - q'[n-1]) / T = (1 - e^{-lambda T}) / (lambda T) q''(t_n) for that motion, and two
// real taps reproduce any complex gain on a real damped sinusoid exactly:
//   p(t_n + D T) = sum_k A_k abar_k[n] + B_k abar_k[n-1],   A + B e^{-lambda T} = H_k lambda T / (1 - e^{-lambda T}),
// so the pressure is computed now and played D samples later (a ring per channel). Exact for each mode's
// free ring-down (any distance, delay spread and near field); while a force acts (a drop's contact, a
// fraction of a millisecond) the taps filter its kick as the mode's own frequency response would, an
// approximation for the spectrum far from the mode (the broadband part of an impact).
// Cost per sample: 2 x modes x channels multiply-adds (the default canopy: 400 modes; mono 800).
// Distance floor: r_i >= a_eq / 2, a_eq = sqrt(A_i / pi), as the Rayleigh path (radiation.hpp).
// The compressible push (DipoleOptions::compressible_push; air_push.hpp): the taps hear each mode's
// acceleration less its kick, x_k = abar_k - phi_k' f (the step's projected force), and each force the canopy
// took in the step (summed per node: AirCanopyState::forced_*) is heard through its node's filter: its
// share of the instantaneous push M_a (M + M_a)^-1 f through the double layer below a crossover above the
// highest mode, the force on a limp screen in compressible air above it. The modes' sound goes through
// the crossover's low half. x has no instantaneous part, but at DC it is -phi_k' f where the true q'' is
// 0, and the filters carry the DC the kicks put on the air: so each mode has three taps,
//   p(t_n + D T) = sum_k A_k x_k[n] + B_k x_k[n-1] + C_k x_k[n-2],
//   A + B z1 + C z1^2 = H_k lambda T / (1 - e^{-lambda T}) (z1 = e^{-lambda T}),  A + B + C = H_k(0),
// exact at the pole (the free ring, as above) and at DC (where the kicks' and the filters' near fields
// cancel; with two taps the 63 Hz band was 6-8 dB off). x[n-1] and x[n-2] are the mode's state after
// the step, (q, q'), taken back through its transition, less its kicks: the three taps are
//   p = a q[n] + b q'[n] + c kick[n] + d kick[n-1]   (dipole_state_taps),
// and as kick_k = sum_e phi_k(e) f_e, the kicks' terms are the step's forces through per-node taps,
// sum_e f_e[n] sum_k c_k phi_k(e) + f_e[n-1] sum_k d_k phi_k(e): 2 multiply-adds a mode and channel (the
// two taps on abar cost the same) and 2 a forced node (a second pass over the modes while a kick is under
// two steps old cost heavy rain's render 1.24 x the model without the push, against 1.14 x before the
// instantaneous push). Per forced node and channel, the filter's length (250 at 48 kHz) multiply-adds;
// per channel, four biquad sections. With panel gains the filter is the point's at unit gain times the
// node's panel's gain (a turn changes it at once).
// Approximated: without the push, the force is the incompressible near field's; the canopy shades
// nothing and nothing reflects; a curved canopy's pressure jump is its plan's (air_loading.hpp) along
// each node's own normal.

#include <complex>
#include <memory>
#include <utility>
#include <vector>

#include "engine/models/air_push.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/radiation.hpp"

namespace ameoto {

struct AirKernels;

// One mode's taps on a channel: p = A x[n] + B x[n-1] + C x[n-2] (C = 0 with two).
struct DipoleTaps {
    double a = 0.0, b = 0.0, c = 0.0;
};
// Two taps, exact at the pole: A + B z1 = total, z1 = e^{-lambda T}.
DipoleTaps dipole_taps_two(std::complex<double> total, std::complex<double> z1);
// Three taps, exact at the pole (z1 = e^{sT} e^{-i wd T}: s_t = sT, w_t = wd T) and at DC (A + B + C = dc).
DipoleTaps dipole_taps_three(std::complex<double> total, double s_t, double w_t, double dc);
// The same three taps on x = abar - kick as what the push path runs: a dot with the mode's state after
// the step and its last two kicks, p = q q[n] + qd q'[n] + kick p[n] + kick_before p[n-1] (the mode's
// transition t11..t22 over T; the header's algebra in dipole_radiation.cpp).
struct StateTaps {
    double q = 0.0, qd = 0.0, kick = 0.0, kick_before = 0.0;
};
StateTaps dipole_state_taps(const DipoleTaps& taps, double t11, double t12, double t21, double t22, double t);

struct DipoleOptions {
    bool compressible_push = false;   // each force's push: instantaneous below a crossover, through compressible air above (air_push.hpp)
};

// What one point's push filters are designed from (design_push_filters' inputs): two points with equal
// keys have the same filters, bit for bit.
struct PushDesignKey {
    // The same object: the canopy's copies share it. Held, so that no other modes can take its address
    // while a key names it. The crossover is the modes' own (push_crossover), so they name it too.
    std::shared_ptr<const AirCanopyModes> modes;
    double air_density = 0.0, speed_of_sound = 0.0;
    std::vector<double> r, cos_theta, areal_density, tile_radius;   // per node
    bool operator==(const PushDesignKey&) const = default;
};

class DipoleRadiation {
public:
    DipoleRadiation() = default;
    DipoleRadiation(const Canopy& canopy, const ListenerLayout& layout, double time_step_s, const AirMedium& air = AirMedium{},
                    const DipoleOptions& options = DipoleOptions{});
    // The same, taking `sibling`'s push filters for each point whose design key is its (the same modes
    // object, screen, air and point): filters never change once designed, so they are shared, not
    // copied. A scene built many times from one canopy (the texture's calibration builds one a drop
    // size) designs them once: 400 nodes' filters a point cost about 30 ms. A sibling built for anything
    // else shares nothing; the result is the same either way, bit for bit (tested).
    DipoleRadiation(const Canopy& canopy, const ListenerLayout& layout, double time_step_s, const AirMedium& air,
                    const DipoleOptions& options, const DipoleRadiation* sibling);

    void process(const Canopy& canopy, double* pressures_pa);
    void reset();
    // One point heard through panel gains (the panned formats) only, else false: the taps glide over
    // glide_frames samples (0: at once) to the mix of each panel's own taps by gains[channel * panels +
    // panel] (a head's turn, DropOnCanopy::turn_head), or back to the layout's own taps, bit for bit.
    // Audio thread: no allocation (channels x modes x panels products, once per turn).
    bool set_panel_gains(const double* gains, int glide_frames);
    bool set_rest_gains(int glide_frames);

    int channels() const { return channels_; }
    int modes() const { return modes_; }
    int delay_samples(int channel) const { return delay_[static_cast<std::size_t>(channel)]; }
    const PushFilters* push_filters(int point) const {
        return point >= 0 && point < static_cast<int>(push_.size()) && push_[static_cast<std::size_t>(point)]->taps > 0
                   ? push_[static_cast<std::size_t>(point)].get()
                   : nullptr;
    }
    std::pair<double, double> coefficients(int channel, int mode) const { return {tap(channel, mode, 0), tap(channel, mode, 1)}; }
    // A channel's taps: without the push A (set 0, on abar[n]) and B (set 1, on abar[n-1]) per mode; with
    // it (state_taps()) StateTaps' q and qd per mode (sets 0, 1), and per node (index: panel * nodes +
    // node) sum_k phi_k(node) kick_k (set 2, on this step's force there) and sum_k phi_k(node) kick_before_k
    // (set 3, on the step before's); 0 for a set not used.
    double tap(int channel, int index, int set) const {
        if (set < 0 || set >= tap_sets_) return 0.0;
        return taps_[set][static_cast<std::size_t>(channel) * static_cast<std::size_t>(tap_width(set)) + static_cast<std::size_t>(index)];
    }
    bool state_taps() const { return state_taps_; }

private:
    const AirKernels* kernels_ = nullptr;   // air_canopy_kernels.hpp, chosen when built
    int channels_ = 0, modes_ = 0;
    // The taps, [set][channel * width + index]: two sets per mode (A, B on abar), or with the push two per
    // mode (q, q') and two per node (the forces now and a step before): tap().
    std::vector<double> taps_[4];
    int tap_sets_ = 2, nodes_ = 0;
    bool state_taps_ = false;
    int tap_width(int set) const { return set < 2 ? modes_ : nodes_; }
    std::vector<double> previous_;   // each mode's abar[n - 1] (two taps; empty with the state taps)
    // With the push: the forces the step before took, as AirCanopyState lists them (sized to the nodes).
    std::vector<int> before_node_;
    std::vector<double> before_newtons_;
    int before_count_ = 0;
    std::vector<int> delay_;         // per channel
    std::vector<double> ring_;       // [channel * length_ + slot]
    int length_ = 1, mask_ = 0, now_ = 0;
    // set_panel_gains: each panel's taps at unit gain [set][panel * modes + mode], the layout's own taps,
    // the glide's targets and steps [set][channel * modes + mode].
    int panels_ = 0, glide_left_ = 0;
    std::vector<double> panel_[4], rest_[4], target_[4], step_[4];
    void start_glide(int glide_frames);
    // The compressible push: each point's filters, each channel's point, and each channel's gain per
    // panel ([channel * panels + panel]; the layout's, or a turn's).
    PushCrossover crossover_;
    std::vector<LowPassState> low_;   // per channel
    std::vector<std::shared_ptr<const PushFilters>> push_;   // per point, never null once built
    std::vector<PushDesignKey> push_keys_;                    // per point: what its filters were designed from
    std::vector<int> push_point_;
    std::vector<double> push_gain_, push_rest_gain_;
    int push_panels_ = 0, push_nodes_per_panel_ = 0;
    void play_push(const AirCanopyState& state);
};

}  // namespace ameoto
