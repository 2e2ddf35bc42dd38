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

DipoleRadiation::DipoleRadiation(const Canopy& canopy, const ListenerLayout& layout, double time_step_s, const AirMedium& air,
                                 const DipoleOptions& options) {
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
    a_.assign(static_cast<std::size_t>(channels_) * static_cast<std::size_t>(modes_), 0.0);
    b_.assign(a_.size(), 0.0);
    delay_.assign(static_cast<std::size_t>(channels_), 0);
    const std::complex<double> i1(0.0, 1.0);
    std::vector<double> r(static_cast<std::size_t>(panels * nodes)), cos_theta(r.size()), gain(r.size());
    // One point's taps: r, cos(theta) per element, its delay D, and each mode's {A, B} (and C, with the
    // push) for the element weights w (a panel gain per element; 0 skips the element).
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
    // With the push, the crossover first: the taps hear each mode's acceleration less its kick, three a
    // mode (header), where there is room for it above the modes.
    if (options.compressible_push) crossover_ = push_crossover(*m);
    three_ = crossover_.hz > 0.0;
    if (three_) c_.assign(a_.size(), 0.0);
    auto taps = [&](int delay, double* a, double* b, double* third) {
        for (int q = 0; q < modes_; ++q) {
            const double w = m->omega[q], s = m->rate[q];
            const std::complex<double> lambda = -s + i1 * std::sqrt(std::complex<double>(w * w - s * s));
            std::complex<double> h = 0.0;
            double h0 = 0.0;   // the gain at DC: the near field alone
            for (std::size_t e = 0; e < r.size(); ++e) {
                const double force = m->air_force(static_cast<Eigen::Index>(e), q);
                if (force == 0.0 || gain[e] == 0.0) continue;
                const double shift = r[e] / c - delay * t;
                const double near = gain[e] * cos_theta[e] * force / (4.0 * constants::pi);
                h += near * std::exp(-lambda * shift) * (1.0 / (r[e] * r[e]) + lambda / (c * r[e]));
                h0 += near / (r[e] * r[e]);
            }
            // From the mean acceleration over the step to q'' at its end (header).
            const std::complex<double> z1 = std::exp(-lambda * t);
            const std::complex<double> lt = lambda * t;
            const std::complex<double> mean_to_end = std::abs(lt) < 1e-9 ? std::complex<double>(1.0) : lt / (1.0 - z1);
            const DipoleTaps d = three_ ? dipole_taps_three(h * mean_to_end, s * t, std::imag(lambda) * t, h0)
                                        : dipole_taps_two(h * mean_to_end, z1);
            a[q] = d.a;
            b[q] = d.b;
            if (third != nullptr) third[q] = d.c;
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
        const std::size_t at = static_cast<std::size_t>(ch) * static_cast<std::size_t>(modes_);
        taps(delay, a_.data() + at, b_.data() + at, c_.empty() ? nullptr : c_.data() + at);
    }
    // One point heard through panel gains (the panned formats): each panel's own taps at unit gain, so a
    // head's turn re-mixes them (set_panel_gains) as the Rayleigh path re-mixes its panel sums. The
    // taps are linear in the weights: the channels' own are these mixed by their gains (to rounding).
    const bool one_point = std::all_of(layout.channel_point.begin(), layout.channel_point.end(), [](int p) { return p == 0; });
    if (!layout.panel_gain.empty() && one_point && channels_ > 1) {
        panel_a_.assign(static_cast<std::size_t>(panels) * static_cast<std::size_t>(modes_), 0.0);
        panel_b_.assign(panel_a_.size(), 0.0);
        if (!c_.empty()) panel_c_.assign(panel_a_.size(), 0.0);
        int delay = 0;
        distances(layout.points[0], delay);
        for (int k = 0; k < panels; ++k) {
            std::fill(gain.begin(), gain.end(), 0.0);
            for (int i = 0; i < nodes; ++i) gain[static_cast<std::size_t>(k * nodes + i)] = 1.0;
            const std::size_t at = static_cast<std::size_t>(k) * static_cast<std::size_t>(modes_);
            taps(delay, panel_a_.data() + at, panel_b_.data() + at, panel_c_.empty() ? nullptr : panel_c_.data() + at);
        }
        panels_ = panels;
        rest_a_ = a_;
        rest_b_ = b_;
        rest_c_ = c_;
        target_a_ = a_;
        target_b_ = b_;
        target_c_ = c_;
        step_a_.assign(a_.size(), 0.0);
        step_b_.assign(b_.size(), 0.0);
        step_c_.assign(c_.size(), 0.0);
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
            push_.push_back(design_push_filters(*m, crossover_, screen, at, air));
            const PushFilters& f = push_.back();
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
    previous_.assign(static_cast<std::size_t>(modes_), 0.0);
    if (three_) history_.assign(3 * static_cast<std::size_t>(modes_), 0.0);
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
    const double* acc = canopy.air_state().accelerations();
    const auto modes = static_cast<std::size_t>(modes_);
    if (glide_left_ > 0) {   // a head's turn: the taps glide to their new mix (set_panel_gains)
        if (--glide_left_ == 0) {
            a_ = target_a_;   // same sizes: copies, no allocation
            b_ = target_b_;
            c_ = target_c_;
        } else {
            for (std::size_t i = 0; i < a_.size(); ++i) {
                a_[i] += step_a_[i];
                b_[i] += step_b_[i];
            }
            for (std::size_t i = 0; i < c_.size(); ++i) c_[i] += step_c_[i];
        }
    }
    if (!push_.empty()) play_push(canopy.air_state());
    // With the push: x[n] = abar[n] - kick[n], into the oldest of the three rows (x[n - 1] and x[n - 2]
    // are the other two).
    const double* x[3] = {nullptr, nullptr, nullptr};
    if (three_) {
        newest_ = newest_ == 2 ? 0 : newest_ + 1;
        double* const row = history_.data() + static_cast<std::size_t>(newest_) * modes;
        const double* kick = canopy.air_state().kicks();
        for (std::size_t k = 0; k < modes; ++k) row[k] = acc[k] - kick[k];
        for (int j = 0; j < 3; ++j) x[j] = history_.data() + static_cast<std::size_t>((newest_ + 3 - j) % 3) * modes;
    }
    for (int ch = 0; ch < channels_; ++ch) {
        const std::size_t base = static_cast<std::size_t>(ch) * modes;
        double* const row = ring_.data() + static_cast<std::size_t>(ch) * static_cast<std::size_t>(length_);
        // sum_k A_k abar_k[n] + B_k abar_k[n-1], in eight running sums (lane_sums.hpp: one would be a chain
        // of 800 dependent additions a sample), AVX2 where the CPU has it (the same bits).
        const double y = three_ ? kernels_->taps3(a_.data() + base, x[0], b_.data() + base, x[1], c_.data() + base, x[2], modes)
                                : kernels_->taps(a_.data() + base, acc, b_.data() + base, previous_.data(), modes);
        const double heard = std::isfinite(y) ? y : 0.0;
        // With the push, the modes are heard through the crossover's low half (air_push.hpp).
        row[(now_ + delay_[static_cast<std::size_t>(ch)]) & mask_] += push_.empty() ? heard : low_[static_cast<std::size_t>(ch)].process(crossover_, heard);
        pressures_pa[ch] = row[now_];
        row[now_] = 0.0;
    }
    if (!three_) std::copy(acc, acc + modes, previous_.begin());
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
            const PushFilters& filters = push_[static_cast<std::size_t>(push_point_[static_cast<std::size_t>(ch)])];
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
    std::fill(history_.begin(), history_.end(), 0.0);
    std::fill(ring_.begin(), ring_.end(), 0.0);
    for (LowPassState& l : low_) l.reset();
}

bool DipoleRadiation::set_panel_gains(const double* gains, int glide_frames) {
    if (panels_ == 0) return false;
    if (!push_gain_.empty()) std::copy(gains, gains + push_gain_.size(), push_gain_.begin());
    const auto modes = static_cast<std::size_t>(modes_);
    for (int ch = 0; ch < channels_; ++ch)
        for (std::size_t q = 0; q < modes; ++q) {
            double a = 0.0, b = 0.0, third = 0.0;
            for (int k = 0; k < panels_; ++k) {
                const double g = gains[ch * panels_ + k];
                a += g * panel_a_[static_cast<std::size_t>(k) * modes + q];
                b += g * panel_b_[static_cast<std::size_t>(k) * modes + q];
                if (!panel_c_.empty()) third += g * panel_c_[static_cast<std::size_t>(k) * modes + q];
            }
            target_a_[static_cast<std::size_t>(ch) * modes + q] = a;
            target_b_[static_cast<std::size_t>(ch) * modes + q] = b;
            if (!target_c_.empty()) target_c_[static_cast<std::size_t>(ch) * modes + q] = third;
        }
    start_glide(glide_frames);
    return true;
}

bool DipoleRadiation::set_rest_gains(int glide_frames) {
    if (panels_ == 0) return false;
    push_gain_ = push_rest_gain_;   // same size: a copy, no allocation
    target_a_ = rest_a_;
    target_b_ = rest_b_;
    target_c_ = rest_c_;
    start_glide(glide_frames);
    return true;
}

void DipoleRadiation::start_glide(int glide_frames) {
    if (glide_frames <= 0) {
        a_ = target_a_;
        b_ = target_b_;
        c_ = target_c_;
        glide_left_ = 0;
        return;
    }
    for (std::size_t i = 0; i < a_.size(); ++i) {   // from where the taps are now (mid-glide too)
        step_a_[i] = (target_a_[i] - a_[i]) / glide_frames;
        step_b_[i] = (target_b_[i] - b_[i]) / glide_frames;
    }
    for (std::size_t i = 0; i < c_.size(); ++i) step_c_[i] = (target_c_[i] - c_[i]) / glide_frames;
    glide_left_ = glide_frames;
}

}  // namespace ameoto
