// SPDX-License-Identifier: GPL-3.0-or-later
// The air-loaded canopy's unbaffled (dipole) radiation: see dipole_radiation.hpp for the equations.
#include "engine/models/dipole_radiation.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

namespace ameoto {

DipoleRadiation::DipoleRadiation(const Canopy& canopy, const ListenerLayout& layout, double time_step_s, const AirMedium& air) {
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
    for (int ch = 0; ch < channels_; ++ch) {
        const Vec3 x = layout.points[static_cast<std::size_t>(layout.channel_point[static_cast<std::size_t>(ch)])];
        double nearest = 1e300;
        for (int k = 0; k < panels; ++k) {
            const double g = layout.panel_gain.empty() ? 1.0
                                                       : layout.panel_gain[static_cast<std::size_t>(ch)].at(static_cast<std::size_t>(k));
            if (!layout.panel_gain.empty() && layout.panel_gain[static_cast<std::size_t>(ch)].size() != static_cast<std::size_t>(panels))
                throw std::invalid_argument("panel gains: one per panel");
            for (int i = 0; i < nodes; ++i) {
                const std::size_t e = static_cast<std::size_t>(k * nodes + i);
                const Vec3 y = canopy.rest_position(k, i), n = canopy.normal(k, i);
                const Vec3 d = x - y;
                const double floor = 0.5 * std::sqrt(m->node_area[e] / constants::pi);
                const double dist = norm(d);
                r[e] = std::max(dist, floor);
                cos_theta[e] = dist > 0.0 ? dot(d, n) / dist : 0.0;
                gain[e] = g;
                nearest = std::min(nearest, r[e]);
            }
        }
        const int delay = static_cast<int>(std::floor(nearest / (c * t)));
        delay_[static_cast<std::size_t>(ch)] = delay;
        for (int q = 0; q < modes_; ++q) {
            const double w = m->omega[q], s = m->rate[q];
            const std::complex<double> lambda = -s + i1 * std::sqrt(std::complex<double>(w * w - s * s));
            std::complex<double> h = 0.0;
            for (std::size_t e = 0; e < r.size(); ++e) {
                const double force = m->air_force(static_cast<Eigen::Index>(e), q);
                if (force == 0.0 || gain[e] == 0.0) continue;
                const double shift = r[e] / c - delay * t;
                h += gain[e] * cos_theta[e] * force / (4.0 * constants::pi) * std::exp(-lambda * shift) *
                     (1.0 / (r[e] * r[e]) + lambda / (c * r[e]));
            }
            // From the mean acceleration over the step to q'' at its end (header).
            const std::complex<double> z1 = std::exp(-lambda * t);
            const std::complex<double> lt = lambda * t;
            const std::complex<double> mean_to_end = std::abs(lt) < 1e-9 ? std::complex<double>(1.0) : lt / (1.0 - z1);
            const std::complex<double> total = h * mean_to_end;
            const std::size_t at = static_cast<std::size_t>(ch) * static_cast<std::size_t>(modes_) + static_cast<std::size_t>(q);
            // A + B z1 = total: two real unknowns for the complex equation (z1 is not real below Nyquist).
            if (std::abs(z1.imag()) > 1e-12 * std::abs(z1)) {
                b_[at] = total.imag() / z1.imag();
                a_[at] = total.real() - b_[at] * z1.real();
            } else {   // at 0 or Nyquist (or overdamped): the real part alone
                a_[at] = total.real();
                b_[at] = 0.0;
            }
        }
    }
    previous_.assign(static_cast<std::size_t>(modes_), 0.0);
    int longest = 0;
    for (int d : delay_) longest = std::max(longest, d);
    length_ = 1;
    while (length_ <= longest + 1) length_ *= 2;
    mask_ = length_ - 1;
    ring_.assign(static_cast<std::size_t>(channels_) * static_cast<std::size_t>(length_), 0.0);
    now_ = 0;
}

namespace {

double dipole_taps(std::size_t modes, const double* __restrict a, const double* __restrict b, const double* __restrict now,
                   const double* __restrict before) {
    double y = 0.0;
    for (std::size_t k = 0; k < modes; ++k) y += a[k] * now[k] + b[k] * before[k];
    return y;
}

}  // namespace

void DipoleRadiation::process(const Canopy& canopy, double* pressures_pa) {
    const AirCanopyModes* m = canopy.air_modes();
    if (m == nullptr || m->modes != modes_) {   // not the canopy it was built for: silence
        for (int ch = 0; ch < channels_; ++ch) pressures_pa[ch] = 0.0;
        return;
    }
    const double* acc = canopy.air_state().accelerations();
    const auto modes = static_cast<std::size_t>(modes_);
    for (int ch = 0; ch < channels_; ++ch) {
        const std::size_t base = static_cast<std::size_t>(ch) * modes;
        double* const row = ring_.data() + static_cast<std::size_t>(ch) * static_cast<std::size_t>(length_);
        const double y = dipole_taps(modes, a_.data() + base, b_.data() + base, acc, previous_.data());
        row[(now_ + delay_[static_cast<std::size_t>(ch)]) & mask_] = std::isfinite(y) ? y : 0.0;
        pressures_pa[ch] = row[now_];
        row[now_] = 0.0;
    }
    std::copy(acc, acc + modes, previous_.begin());
    now_ = (now_ + 1) & mask_;
}

void DipoleRadiation::reset() {
    std::fill(previous_.begin(), previous_.end(), 0.0);
    std::fill(ring_.begin(), ring_.end(), 0.0);
}

}  // namespace ameoto
