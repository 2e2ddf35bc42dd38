// SPDX-License-Identifier: GPL-3.0-or-later
// The air-loaded canopy's unbaffled (dipole) radiation: see dipole_radiation.hpp for the equations.
#include "engine/models/dipole_radiation.hpp"

#include "engine/models/air_canopy_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

namespace ameoto {

DipoleTaps dipole_taps_two(std::complex<double> total, std::complex<double> z1) {
    // A + B z1 = total: two real unknowns for the complex equation (z1 is not real below Nyquist).
    if (std::abs(z1.imag()) > 1e-12 * std::abs(z1)) {
        const double b = total.imag() / z1.imag();
        return {total.real() - b * z1.real(), b, 0.0};
    }
    return {total.real(), 0.0, 0.0};   // at 0 or Nyquist (or overdamped): the real part alone
}

DipoleTaps dipole_taps_three(std::complex<double> total, double s_t, double w_t, double dc) {
    // z1 = e^{-lambda T} = e^{sT} e^{-i wd T}, z2 = z1^2. Unknowns A, B, C:
    //   A + B Re z1 + C Re z2 = Re total,  B Im z1 + C Im z2 = Im total,  A + B + C = dc;
    // the first from the third: B (1 - Re z1) + C (1 - Re z2) = dc - Re total. 1 - Re z is taken as
    // -expm1(a) cos(b) + 2 sin^2(b / 2) for z = e^a e^{-ib}: at 85 Hz and 48 kHz it is 1.6e-5, where
    // 1 - cos would lose 5 of the 16 digits.
    if (!(w_t > 0.0)) return dipole_taps_two(total, std::exp(std::complex<double>(s_t, 0.0)));   // overdamped: z1 real
    auto one_less_real = [](double a, double b) { return -std::expm1(a) * std::cos(b) + 2.0 * std::sin(0.5 * b) * std::sin(0.5 * b); };
    const double i1 = -std::exp(s_t) * std::sin(w_t), i2 = -std::exp(2.0 * s_t) * std::sin(2.0 * w_t);
    const double r1 = one_less_real(s_t, w_t), r2 = one_less_real(2.0 * s_t, 2.0 * w_t);
    const double det = i1 * r2 - i2 * r1;
    if (!(std::abs(det) > 1e-300)) return dipole_taps_two(total, std::polar(std::exp(s_t), -w_t));
    const double u = total.imag(), v = dc - total.real();
    const double b = (u * r2 - i2 * v) / det;
    const double c = (i1 * v - r1 * u) / det;
    return {dc - b - c, b, c};
}

StateTaps dipole_state_taps(const DipoleTaps& x, double t11, double t12, double t21, double t22, double t) {
    // With s[n] = (q[n], q'[n]) after step n and Phi the transition: s[n] = Phi (s[n-1] + (0, T p[n])), so
    // s[n-1] = Phi^-1 s[n] - (0, T p[n]); and x[n] = (q'[n] - q'[n-1]) / T - p[n] = L s[n] with
    // L = (e2' - e2' Phi^-1) / T (p[n] cancels). Then x[n-1] = L Phi^-1 s[n] - T L_2 p[n] and
    // x[n-2] = L Phi^-2 s[n] - T (L Phi^-1)_2 p[n] - T L_2 p[n-1]: the three taps are
    //   (A L + B L Phi^-1 + C L Phi^-2) s[n] - T (B L_2 + C (L Phi^-1)_2) p[n] - T C L_2 p[n-1].
    const double det = t11 * t22 - t12 * t21;   // e^{-2 s T}
    const double i11 = t22 / det, i12 = -t12 / det, i21 = -t21 / det, i22 = t11 / det;   // Phi^-1
    auto times_inverse = [&](const double (&row)[2], double (&out)[2]) {
        out[0] = row[0] * i11 + row[1] * i21;
        out[1] = row[0] * i12 + row[1] * i22;
    };
    const double l0[2] = {-i21 / t, (1.0 - i22) / t};
    double l1[2], l2[2];
    times_inverse(l0, l1);
    times_inverse(l1, l2);
    StateTaps out;
    out.q = x.a * l0[0] + x.b * l1[0] + x.c * l2[0];
    out.qd = x.a * l0[1] + x.b * l1[1] + x.c * l2[1];
    out.kick = -t * (x.b * l0[1] + x.c * l1[1]);
    out.kick_before = -t * x.c * l0[1];
    return out;
}

DipoleRadiation::DipoleRadiation(const Canopy& canopy, const ListenerLayout& layout, double time_step_s, const AirMedium& air,
                                 const DipoleOptions& options)
    : DipoleRadiation(canopy, layout, time_step_s, air, options, nullptr) {}

DipoleRadiation::DipoleRadiation(const Canopy& canopy, const ListenerLayout& layout, double time_step_s, const AirMedium& air,
                                 const DipoleOptions& options, const DipoleRadiation* sibling) {
    const AirCanopyModes* m = canopy.air_modes();
    if (m == nullptr) throw std::invalid_argument("dipole radiation: the canopy is not in air");
    if (!(time_step_s > 0.0)) throw std::invalid_argument("dipole radiation: the time step must be positive");
    channels_ = layout.channels();
    if (channels_ < 1) throw std::invalid_argument("a layout needs at least one channel");
    for (int p : layout.channel_point)
        if (p < 0 || p >= static_cast<int>(layout.points.size())) throw std::invalid_argument("channel hears no point");
    if (!layout.panel_gain.empty() && static_cast<int>(layout.panel_gain.size()) != channels_)
        throw std::invalid_argument("panel gains: one row per channel");
    const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel();
    modes_ = m->modes;
    const double c = air.speed_of_sound, t = time_step_s;
    // With the push, the crossover first: where there is room for it above the modes, the taps hear each
    // mode's acceleration less its kick, as a dot with its state (header).
    if (options.compressible_push) crossover_ = push_crossover(*m);
    state_taps_ = crossover_.hz > 0.0;
    tap_sets_ = state_taps_ ? 4 : 2;
    nodes_ = panels * nodes;
    for (int j = 0; j < tap_sets_; ++j) taps_[j].assign(static_cast<std::size_t>(channels_) * static_cast<std::size_t>(tap_width(j)), 0.0);
    delay_.assign(static_cast<std::size_t>(channels_), 0);
    const std::complex<double> i1(0.0, 1.0);
    std::vector<double> r(static_cast<std::size_t>(panels * nodes)), cos_theta(r.size()), gain(r.size());
    // One point's taps: r, cos(theta) per element, its delay D, and each mode's taps for the element
    // weights w (a panel gain per element; 0 skips the element).
    auto distances = [&](const Vec3& x, int& delay) {
        double nearest = 1e300;
        for (int k = 0; k < panels; ++k)
            for (int i = 0; i < nodes; ++i) {
                const std::size_t e = static_cast<std::size_t>(k * nodes + i);
                const Vec3 y = canopy.rest_position(k, i), n = canopy.normal(k, i);
                const Vec3 d = x - y;
                const double floor = 0.5 * std::sqrt(m->node_area[e] / constants::pi);
                const double dist = norm(d);
                r[e] = std::max(dist, floor);
                cos_theta[e] = dist > 0.0 ? dot(d, n) / dist : 0.0;
                nearest = std::min(nearest, r[e]);
            }
        delay = static_cast<int>(std::floor(nearest / (c * t)));
    };
    // Writes the taps of one channel (or panel) `index`: sets 0 and 1 per mode at out[j][index * modes + q];
    // with the push, sets 2 and 3 per node at out[j][index * nodes + e] (header: the kicks' taps taken
    // through the shapes, sum_k c_k phi_k(e), so a step costs what its forced nodes number).
    const auto all_nodes = static_cast<std::size_t>(panels * nodes);
    std::vector<double> kick_now(static_cast<std::size_t>(modes_)), kick_before(kick_now.size());
    auto taps = [&](int delay, std::vector<double>* out, std::size_t index) {
        const std::size_t at = index * static_cast<std::size_t>(modes_);
        for (int q = 0; q < modes_; ++q) {
            const double w = m->omega[q], s = m->rate[q];
            const std::complex<double> lambda = -s + i1 * std::sqrt(std::complex<double>(w * w - s * s));
            std::complex<double> h = 0.0;
            double h0 = 0.0;   // the gain at DC: the near field alone
            for (std::size_t e = 0; e < r.size(); ++e) {
                const double force = m->air_force(static_cast<Eigen::Index>(e), q);
                if (force == 0.0 || gain[e] == 0.0) continue;
                const double shift = r[e] / c - delay * t;
                const double weight = gain[e] * cos_theta[e] * force / (4.0 * constants::pi);
                h += weight * std::exp(-lambda * shift) * (1.0 / (r[e] * r[e]) + lambda / (c * r[e]));
                h0 += weight / (r[e] * r[e]);
            }
            // From the mean acceleration over the step to q'' at its end (header).
            const std::complex<double> z1 = std::exp(-lambda * t);
            const std::complex<double> lt = lambda * t;
            const std::complex<double> mean_to_end = std::abs(lt) < 1e-9 ? std::complex<double>(1.0) : lt / (1.0 - z1);
            const auto k = at + static_cast<std::size_t>(q);
            if (!state_taps_) {
                const DipoleTaps d = dipole_taps_two(h * mean_to_end, z1);
                out[0][k] = d.a;
                out[1][k] = d.b;
                continue;
            }
            const StateTaps d = dipole_state_taps(dipole_taps_three(h * mean_to_end, s * t, std::imag(lambda) * t, h0), m->t11[q], m->t12[q],
                                                  m->t21[q], m->t22[q], t);
            out[0][k] = d.q;
            out[1][k] = d.qd;
            kick_now[static_cast<std::size_t>(q)] = d.kick;
            kick_before[static_cast<std::size_t>(q)] = d.kick_before;
        }
        if (!state_taps_) return;
        for (std::size_t e = 0; e < all_nodes; ++e) {
            const double* phi = m->shape.data() + e * static_cast<std::size_t>(modes_);
            double now = 0.0, before = 0.0;
            for (int q = 0; q < modes_; ++q) {
                now += kick_now[static_cast<std::size_t>(q)] * phi[q];
                before += kick_before[static_cast<std::size_t>(q)] * phi[q];
            }
            out[2][index * all_nodes + e] = now;
            out[3][index * all_nodes + e] = before;
        }
    };
    for (int ch = 0; ch < channels_; ++ch) {
        const Vec3 x = layout.points[static_cast<std::size_t>(layout.channel_point[static_cast<std::size_t>(ch)])];
        for (int k = 0; k < panels; ++k) {
            const double g = layout.panel_gain.empty() ? 1.0
                                                       : layout.panel_gain[static_cast<std::size_t>(ch)].at(static_cast<std::size_t>(k));
            if (!layout.panel_gain.empty() && layout.panel_gain[static_cast<std::size_t>(ch)].size() != static_cast<std::size_t>(panels))
                throw std::invalid_argument("panel gains: one per panel");
            for (int i = 0; i < nodes; ++i) gain[static_cast<std::size_t>(k * nodes + i)] = g;
        }
        int delay = 0;
        distances(x, delay);
        delay_[static_cast<std::size_t>(ch)] = delay;
        taps(delay, taps_, static_cast<std::size_t>(ch));
    }
    // One point heard through panel gains (the panned formats): each panel's own taps at unit gain, so a
    // head's turn re-mixes them (set_panel_gains) as the Rayleigh path re-mixes its panel sums. The
    // taps are linear in the weights: the channels' own are these mixed by their gains (to rounding).
    const bool one_point = std::all_of(layout.channel_point.begin(), layout.channel_point.end(), [](int p) { return p == 0; });
    if (!layout.panel_gain.empty() && one_point && channels_ > 1) {
        for (int j = 0; j < tap_sets_; ++j) panel_[j].assign(static_cast<std::size_t>(panels) * static_cast<std::size_t>(tap_width(j)), 0.0);
        int delay = 0;
        distances(layout.points[0], delay);
        for (int k = 0; k < panels; ++k) {
            std::fill(gain.begin(), gain.end(), 0.0);
            for (int i = 0; i < nodes; ++i) gain[static_cast<std::size_t>(k * nodes + i)] = 1.0;
            taps(delay, panel_, static_cast<std::size_t>(k));
        }
        panels_ = panels;
        for (int j = 0; j < tap_sets_; ++j) {
            rest_[j] = taps_[j];
            target_[j] = taps_[j];
            step_[j].assign(taps_[j].size(), 0.0);
        }
    }
    int longest = 0;
    for (int d : delay_) longest = std::max(longest, d + 1);
    if (options.compressible_push) {
        // Each point's filters at unit gain (air_push.hpp); a channel scales them by its panel gains.
        PushScreen screen;
        screen.areal_density.assign(r.size(), 0.0);
        screen.tile_radius.assign(r.size(), 0.0);
        for (int k = 0; k < panels; ++k)
            for (int i = 0; i < nodes; ++i) {
                const auto e = static_cast<std::size_t>(k * nodes + i);
                screen.areal_density[e] = canopy.panel(k).network.mass(i) > 0.0 ? canopy.panel(k).material.areal_density : 0.0;
                screen.tile_radius[e] = std::sqrt(m->node_area[e] / constants::pi);
            }
        for (std::size_t point = 0; point < layout.points.size() && crossover_.hz > 0.0; ++point) {
            PushPoint at;
            int delay = 0;   // each node's filter starts from its own delay (air_push.hpp)
            distances(layout.points[point], delay);
            at.r = r;
            at.cos_theta = cos_theta;
            PushDesignKey key{canopy.shared_air_modes(), air.density, air.speed_of_sound, r, cos_theta, screen.areal_density, screen.tile_radius};
            std::shared_ptr<const PushFilters> shared;
            for (std::size_t j = 0; sibling != nullptr && j < sibling->push_keys_.size() && !shared; ++j)
                if (sibling->push_keys_[j] == key) shared = sibling->push_[j];
            push_.push_back(shared ? shared : std::make_shared<const PushFilters>(design_push_filters(*m, crossover_, screen, at, air)));
            push_keys_.push_back(std::move(key));
            const PushFilters& f = *push_.back();
            for (int e = 0; e < panels * nodes && f.taps > 0; ++e)
                longest = std::max(longest, f.offset[static_cast<std::size_t>(e)] + f.taps);
        }
        push_panels_ = panels;
        push_nodes_per_panel_ = nodes;
        push_point_ = layout.channel_point;
        push_gain_.assign(static_cast<std::size_t>(channels_) * static_cast<std::size_t>(panels), 1.0);
        for (int ch = 0; ch < channels_ && !layout.panel_gain.empty(); ++ch)
            for (int k = 0; k < panels; ++k)
                push_gain_[static_cast<std::size_t>(ch * panels + k)] = layout.panel_gain[static_cast<std::size_t>(ch)][static_cast<std::size_t>(k)];
        push_rest_gain_ = push_gain_;
        low_.assign(static_cast<std::size_t>(channels_), LowPassState{});
    }
    if (state_taps_) {
        before_node_.assign(static_cast<std::size_t>(nodes_), 0);
        before_newtons_.assign(static_cast<std::size_t>(nodes_), 0.0);
    } else {
        previous_.assign(static_cast<std::size_t>(modes_), 0.0);   // abar[n - 1] (two taps only)
    }
    kernels_ = &air_kernels();   // here, in the build phase (the first call initialises a static)
    length_ = 1;
    while (length_ <= longest) length_ *= 2;
    mask_ = length_ - 1;
    ring_.assign(static_cast<std::size_t>(channels_) * static_cast<std::size_t>(length_), 0.0);
    now_ = 0;
}

void DipoleRadiation::process(const Canopy& canopy, double* pressures_pa) {
    const AirCanopyModes* m = canopy.air_modes();
    if (m == nullptr || m->modes != modes_ || kernels_ == nullptr) {   // not the canopy it was built for: silence
        for (int ch = 0; ch < channels_; ++ch) pressures_pa[ch] = 0.0;
        return;
    }
    const AirCanopyState& state = canopy.air_state();
    const auto modes = static_cast<std::size_t>(modes_);
    if (glide_left_ > 0) {   // a head's turn: the taps glide to their new mix (set_panel_gains)
        if (--glide_left_ == 0) {
            for (int j = 0; j < tap_sets_; ++j) taps_[j] = target_[j];   // same sizes: copies, no allocation
        } else {
            for (int j = 0; j < tap_sets_; ++j)
                for (std::size_t i = 0; i < taps_[j].size(); ++i) taps_[j][i] += step_[j][i];
        }
    }
    if (!push_.empty()) play_push(state);
    // Two taps on abar[n], abar[n - 1]; or, with the push, the state after the step and the forces of this
    // step and the one before, each through its node's taps (header).
    const double* x = state_taps_ ? state.modal_q() : state.accelerations();
    const double* y = state_taps_ ? state.modal_qd() : previous_.data();
    for (int ch = 0; ch < channels_; ++ch) {
        const std::size_t base = static_cast<std::size_t>(ch) * modes;
        double* const row = ring_.data() + static_cast<std::size_t>(ch) * static_cast<std::size_t>(length_);
        // sum_k A_k x_k + B_k y_k, in eight running sums (lane_sums.hpp: one would be a chain of 800 dependent
        // additions a sample), AVX2 where the CPU has it (the same bits).
        double p = kernels_->taps(taps_[0].data() + base, x, taps_[1].data() + base, y, modes);
        if (state_taps_) {
            const double* now = taps_[2].data() + static_cast<std::size_t>(ch) * static_cast<std::size_t>(nodes_);
            const double* before = taps_[3].data() + static_cast<std::size_t>(ch) * static_cast<std::size_t>(nodes_);
            for (int j = 0; j < state.forced_nodes(); ++j) p += now[state.forced_node(j)] * state.forced_newtons(j);
            for (int j = 0; j < before_count_; ++j)
                p += before[before_node_[static_cast<std::size_t>(j)]] * before_newtons_[static_cast<std::size_t>(j)];
        }
        const double heard = std::isfinite(p) ? p : 0.0;
        // With the push, the modes are heard through the crossover's low half (air_push.hpp).
        row[(now_ + delay_[static_cast<std::size_t>(ch)]) & mask_] += push_.empty() ? heard : low_[static_cast<std::size_t>(ch)].process(crossover_, heard);
        pressures_pa[ch] = row[now_];
        row[now_] = 0.0;
    }
    if (!state_taps_) {
        const double* acc = state.accelerations();
        std::copy(acc, acc + modes, previous_.begin());
    } else {   // this step's forces, for the next (a list no longer than the nodes: sized in the build)
        before_count_ = state.forced_nodes();
        for (int j = 0; j < before_count_; ++j) {
            before_node_[static_cast<std::size_t>(j)] = state.forced_node(j);
            before_newtons_[static_cast<std::size_t>(j)] = state.forced_newtons(j);
        }
    }
    now_ = (now_ + 1) & mask_;
}

// Each node the step's forces touched, through its filter into every channel's ring (air_push.hpp).
void DipoleRadiation::play_push(const AirCanopyState& state) {
    for (int j = 0; j < state.forced_nodes(); ++j) {
        const int e = state.forced_node(j);
        const double f = state.forced_newtons(j);
        if (!std::isfinite(f) || f == 0.0) continue;
        const int panel = e / push_nodes_per_panel_;
        for (int ch = 0; ch < channels_; ++ch) {
            const PushFilters& filters = *push_[static_cast<std::size_t>(push_point_[static_cast<std::size_t>(ch)])];
            const double g = f * push_gain_[static_cast<std::size_t>(ch * push_panels_ + panel)];
            if (filters.taps == 0 || g == 0.0) continue;
            const double* fir = filters.fir.data() + static_cast<std::size_t>(e) * static_cast<std::size_t>(filters.taps);
            double* const row = ring_.data() + static_cast<std::size_t>(ch) * static_cast<std::size_t>(length_);
            // Two runs of the ring, each contiguous (so the loops vectorise): to its end, then from its start.
            const int start = (now_ + filters.offset[static_cast<std::size_t>(e)]) & mask_;
            const int first = std::min(filters.taps, length_ - start);
            double* const head = row + start;
            for (int tap = 0; tap < first; ++tap) head[tap] += g * fir[tap];
            for (int tap = first; tap < filters.taps; ++tap) row[tap - first] += g * fir[tap];
        }
    }
}

void DipoleRadiation::reset() {
    std::fill(previous_.begin(), previous_.end(), 0.0);
    before_count_ = 0;
    std::fill(ring_.begin(), ring_.end(), 0.0);
    for (LowPassState& l : low_) l.reset();
}

bool DipoleRadiation::set_panel_gains(const double* gains, int glide_frames) {
    if (panels_ == 0) return false;
    if (!push_gain_.empty()) std::copy(gains, gains + push_gain_.size(), push_gain_.begin());
    for (int j = 0; j < tap_sets_; ++j) {
        const auto width = static_cast<std::size_t>(tap_width(j));
        for (int ch = 0; ch < channels_; ++ch)
            for (std::size_t q = 0; q < width; ++q) {
                double sum = 0.0;
                for (int k = 0; k < panels_; ++k) sum += gains[ch * panels_ + k] * panel_[j][static_cast<std::size_t>(k) * width + q];
                target_[j][static_cast<std::size_t>(ch) * width + q] = sum;
            }
    }
    start_glide(glide_frames);
    return true;
}

bool DipoleRadiation::set_rest_gains(int glide_frames) {
    if (panels_ == 0) return false;
    push_gain_ = push_rest_gain_;   // same size: a copy, no allocation
    for (int j = 0; j < tap_sets_; ++j) target_[j] = rest_[j];
    start_glide(glide_frames);
    return true;
}

void DipoleRadiation::start_glide(int glide_frames) {
    if (glide_frames <= 0) {
        for (int j = 0; j < tap_sets_; ++j) taps_[j] = target_[j];
        glide_left_ = 0;
        return;
    }
    for (int j = 0; j < tap_sets_; ++j)   // from where the taps are now (mid-glide too)
        for (std::size_t i = 0; i < taps_[j].size(); ++i) step_[j][i] = (target_[j][i] - taps_[j][i]) / glide_frames;
    glide_left_ = glide_frames;
}

}  // namespace ameoto
