// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/radiation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ameoto {

MassPickup::MassPickup(const Canopy& canopy, int panel, int node, double full_scale_m)
    : panel_(panel), node_(node), full_scale_m_(full_scale_m) {
    if (panel < 0 || panel >= canopy.panel_count()) throw std::invalid_argument("pickup panel out of range");
    if (node < 0 || node >= canopy.nodes_per_panel()) throw std::invalid_argument("pickup node out of range");
    if (!std::isfinite(full_scale_m)) throw std::invalid_argument("pickup full scale must be a finite displacement");
    if (full_scale_m <= 0.0) {
        // K_ii: the node's anchors plus every link that touches it.
        const NetworkArrays& a = canopy.panel(panel).network.arrays();   // the panel's arrays (not its state)
        double k = a.anchor_stiffness[static_cast<std::size_t>(node)];
        for (std::size_t l = 0; l < a.link_count(); ++l)
            if (a.link_a[l] == node || a.link_b[l] == node) k += a.link_stiffness[l];
        full_scale_m_ = reference_force_n / k;
    }
}

MassPickup MassPickup::at(const Canopy& canopy, double x, double y, double full_scale_m) {
    const CanopyHit hit = canopy.locate(x, y);
    if (hit.panel < 0) throw std::invalid_argument("pickup point is not on the canopy");
    return MassPickup(canopy, hit.panel, hit.node, full_scale_m);
}

RayleighRadiator::RayleighRadiator(std::vector<RadiatingElement> elements, std::vector<Vec3> points, int groups,
                                   double time_step_s, const AirMedium& air)
    : points_(std::move(points)), elements_(static_cast<int>(elements.size())), groups_(groups) {
    if (!(time_step_s > 0.0)) throw std::invalid_argument("time step must be positive");
    if (!(air.density > 0.0) || !(air.speed_of_sound > 0.0)) throw std::invalid_argument("air needs density and c");
    if (groups < 1) throw std::invalid_argument("at least one group");
    if (points_.empty()) throw std::invalid_argument("at least one listening point");
    for (const RadiatingElement& el : elements) {
        if (el.group < 0 || el.group >= groups) throw std::invalid_argument("element group out of range");
        if (!(el.area > 0.0)) throw std::invalid_argument("element area must be positive");
    }
    const std::size_t n = elements.size(), points_n = points_.size(), g = static_cast<std::size_t>(groups);
    // Scatter order: the groups taken in turn (the first element of each group, then the second, ...),
    // so consecutive taps add into different rows. In the caller's order a panel's neighbouring nodes
    // often share a delay or are one sample apart, and each add would wait for the previous one's store
    // (measured on the canopy: about 3 times slower).
    std::vector<int> rank(n), seen(g, 0);
    for (std::size_t e = 0; e < n; ++e) rank[e] = seen[static_cast<std::size_t>(elements[e].group)]++;
    source_.resize(n);
    for (std::size_t e = 0; e < n; ++e) source_[e] = static_cast<std::int32_t>(e);
    std::stable_sort(source_.begin(), source_.end(), [&](std::int32_t x, std::int32_t y) {
        const auto i = static_cast<std::size_t>(x), j = static_cast<std::size_t>(y);
        return rank[i] != rank[j] ? rank[i] < rank[j] : elements[i].group < elements[j].group;
    });
    distance_.resize(points_n * n);
    delay_.resize(points_n * n);
    gain_.resize(points_n * n);
    std::vector<int> whole_samples(points_n * n);
    std::vector<double> w0(points_n * n), w1(points_n * n);
    int longest = 0;
    for (std::size_t p = 0; p < points_n; ++p) {
        for (std::size_t e = 0; e < n; ++e) {
            const RadiatingElement& el = elements[e];
            const Vec3 d = points_[p] - el.position;
            // Floor a_eq / 2: the Rayleigh integral over a disc of area A from its centre (header).
            const double floor = 0.5 * std::sqrt(el.area / constants::pi);
            const double r = std::max(norm(d), floor);
            const double side = dot(d, el.normal) < 0.0 ? -1.0 : 1.0;   // the face that looks at the point
            const double gain = side * air.density * el.area / (2.0 * constants::pi * r);
            const double delay = r / (air.speed_of_sound * time_step_s);
            const double whole = std::floor(delay), frac = delay - whole;
            const std::size_t i = p * n + e;
            whole_samples[i] = static_cast<int>(whole);
            w0[i] = (1.0 - frac) * gain;
            w1[i] = frac * gain;
            distance_[i] = r;
            delay_[i] = delay;
            gain_[i] = w0[i] + w1[i];
            longest = std::max(longest, whole_samples[i] + 1);
        }
    }
    run_ = 1;
    while (run_ < longest + 1) run_ *= 2;   // header: span_ < run_
    span_ = longest;
    row_ = 2 * run_ + 8;   // header: not a power of two
    target_.resize(points_n * n);
    weights_.resize(2 * points_n * n);
    for (std::size_t p = 0; p < points_n; ++p) {
        for (std::size_t t = 0; t < n; ++t) {
            const std::size_t e = static_cast<std::size_t>(source_[t]), from = p * n + e, to = p * n + t;
            const std::size_t row = p * g + static_cast<std::size_t>(elements[e].group);
            target_[to] = static_cast<std::int32_t>(row * static_cast<std::size_t>(row_) + static_cast<std::size_t>(whole_samples[from]));
            weights_[2 * to] = w0[from];
            weights_[2 * to + 1] = w1[from];
        }
    }
    input_.assign(n, 0.0);
    pending_.assign(points_n * g * static_cast<std::size_t>(row_), 0.0);
}

void RayleighRadiator::read_inputs_at(const std::vector<std::int32_t>& index, int length) {
    if (index.size() != static_cast<std::size_t>(elements_)) throw std::invalid_argument("one input index per element");
    for (std::int32_t i : index)
        if (i < 0 || i >= length) throw std::invalid_argument("input index out of range");
    for (std::int32_t& s : source_) s = index[static_cast<std::size_t>(s)];
    input_.assign(static_cast<std::size_t>(length), 0.0);
}

void RayleighRadiator::process(const double* accelerations, double* out) {
    const std::size_t inputs = input_.size();
    double* const input = input_.data();
    for (std::size_t e = 0; e < inputs; ++e) input[e] = std::isfinite(accelerations[e]) ? accelerations[e] : 0.0;
    process_inputs(out);
}

void RayleighRadiator::process_inputs(double* out) {
    const std::size_t n = static_cast<std::size_t>(elements_);
    const double* const input = input_.data();
    // Scatter (header, "Delays"): this sample's a_i reaches its output floor(D) and floor(D) + 1
    // samples ahead; a tap with floor(D) = 0 adds into the current sample, which is read below.
    double* const current = pending_.data() + now_;
    const std::int32_t* const source = source_.data();
    for (std::size_t p = 0; p < points_.size(); ++p) {
        const std::int32_t* const target = target_.data() + p * n;
        const double* const weights = weights_.data() + 2 * p * n;
        for (std::size_t t = 0; t < n; ++t) {
            const double a = input[source[t]];
            double* const cell = current + target[t];
            // All four loads before either store (a store to cell[0] could alias weights[2t + 1] as far
            // as the compiler knows): it then pairs them into one two-wide load, multiply, add and
            // store (SSE2 on x86-64), cell[0..1] being the adjacent samples floor(D) and floor(D) + 1.
            const double w0 = weights[2 * t], w1 = weights[2 * t + 1], c0 = cell[0], c1 = cell[1];
            cell[0] = c0 + w0 * a;
            cell[1] = c1 + w1 * a;
        }
    }
    const std::size_t outputs = points_.size() * static_cast<std::size_t>(groups_), row = static_cast<std::size_t>(row_);
    for (std::size_t o = 0; o < outputs; ++o) {
        out[o] = current[o * row];
        current[o * row] = 0.0;
    }
    if (++now_ == run_) {
        for (std::size_t o = 0; o < outputs; ++o) {
            double* const front = pending_.data() + o * row;
            double* const ahead = front + run_;
            std::copy(ahead, ahead + span_, front);
            std::fill(ahead, ahead + span_, 0.0);
        }
        now_ = 0;
    }
}

void RayleighRadiator::reset() {
    std::fill(pending_.begin(), pending_.end(), 0.0);
    now_ = 0;
}

double RayleighRadiator::distance(int point, int element) const {
    return distance_[static_cast<std::size_t>(point) * static_cast<std::size_t>(elements_) + static_cast<std::size_t>(element)];
}

double RayleighRadiator::delay_samples(int point, int element) const {
    return delay_[static_cast<std::size_t>(point) * static_cast<std::size_t>(elements_) + static_cast<std::size_t>(element)];
}

double RayleighRadiator::gain(int point, int element) const {
    return gain_[static_cast<std::size_t>(point) * static_cast<std::size_t>(elements_) + static_cast<std::size_t>(element)];
}

ListenerLayout ListenerLayout::mono(Vec3 at) { return ListenerLayout{{at}, {0}, {}}; }

ListenerLayout ListenerLayout::ears(Vec3 head, double facing_azimuth_rad, double spacing_m) {
    if (!(spacing_m > 0.0)) throw std::invalid_argument("ear spacing must be positive");
    const Vec3 left{-std::sin(facing_azimuth_rad), std::cos(facing_azimuth_rad), 0.0};
    return ListenerLayout{{head + (0.5 * spacing_m) * left, head - (0.5 * spacing_m) * left}, {0, 1}, {}};
}

ListenerLayout ListenerLayout::panned(Vec3 at, std::vector<std::vector<double>> gains) {
    ListenerLayout l{{at}, std::vector<int>(gains.size(), 0), std::move(gains)};
    return l;
}

namespace {

std::vector<RadiatingElement> canopy_elements(const Canopy& canopy) {
    std::vector<RadiatingElement> elements;
    elements.reserve(static_cast<std::size_t>(canopy.panel_count() * canopy.nodes_per_panel()));
    for (int k = 0; k < canopy.panel_count(); ++k)
        for (int i = 0; i < canopy.nodes_per_panel(); ++i)
            elements.push_back({canopy.rest_position(k, i), canopy.normal(k, i), canopy.node_area(), k});
    return elements;
}

}  // namespace

FarFieldRadiation::FarFieldRadiation(const Canopy& canopy, const ListenerLayout& layout, double time_step_s,
                                     const AirMedium& air)
    : layout_(layout),
      radiator_(canopy_elements(canopy), layout.points, canopy.panel_count(), time_step_s, air),
      inverse_dt_(1.0 / time_step_s),
      panels_(canopy.panel_count()),
      nodes_(canopy.nodes_per_panel()) {
    const int channels = layout.channels();
    if (channels < 1) throw std::invalid_argument("a layout needs at least one channel");
    for (int p : layout.channel_point)
        if (p < 0 || p >= static_cast<int>(layout.points.size())) throw std::invalid_argument("channel hears no point");
    if (!layout.panel_gain.empty() && static_cast<int>(layout.panel_gain.size()) != channels)
        throw std::invalid_argument("panel gains: one row per channel");
    flat_gain_.assign(static_cast<std::size_t>(channels * panels_), 1.0);
    for (std::size_t c = 0; c < layout.panel_gain.size(); ++c) {
        if (static_cast<int>(layout.panel_gain[c].size()) != panels_)
            throw std::invalid_argument("panel gains: one per panel");
        std::copy(layout.panel_gain[c].begin(), layout.panel_gain[c].end(),
                  flat_gain_.begin() + static_cast<std::ptrdiff_t>(c) * panels_);
    }
    gain_target_ = flat_gain_;
    gain_step_.assign(flat_gain_.size(), 0.0);
    // The radiator reads the canopy's node-major velocities' layout directly (element k * nodes + i, the
    // order of canopy_elements, is input i * lanes + k): no per-panel copy each sample.
    lanes_ = canopy.lanes();
    std::vector<std::int32_t> index(static_cast<std::size_t>(panels_ * nodes_));
    for (int k = 0; k < panels_; ++k)
        for (int i = 0; i < nodes_; ++i) index[static_cast<std::size_t>(k * nodes_ + i)] = i * lanes_ + k;
    const std::size_t cells = static_cast<std::size_t>(nodes_ * lanes_);
    radiator_.read_inputs_at(index, static_cast<int>(cells));
    velocity_.assign(cells, 0.0);
    previous_velocity_.assign(cells, 0.0);
    sums_.assign(layout.points.size() * static_cast<std::size_t>(panels_), 0.0);
    resets_seen_.assign(static_cast<std::size_t>(panels_), 0);
    for (int k = 0; k < panels_; ++k) resets_seen_[static_cast<std::size_t>(k)] = canopy.panel_guard_resets(k);
    canopy.velocities(previous_velocity_.data());
}

namespace {

// a = (v - v_prev) / T, v_prev = v, over the whole node-major array, written straight into the
// radiator's inputs with its rule (non-finite: 0), which saves process()'s copy. Restrict parameters:
// vectorised.
void accelerations(std::size_t cells, const double* __restrict v, double* __restrict previous, double inverse_dt,
                   double* __restrict a) {
    for (std::size_t c = 0; c < cells; ++c) {
        const double acceleration = (v[c] - previous[c]) * inverse_dt;
        a[c] = std::isfinite(acceleration) ? acceleration : 0.0;
        previous[c] = v[c];
    }
}

// The two passes above in one: v = (x - x_prev) * inv_dt (LanedNetwork::velocities' backward
// difference), then accelerations()'s a = (v - v_prev) * inverse_dt, the same operations on the same
// values in the same order (so the same bits), without storing v in between. Compiled for AVX2 and the
// baseline, picked once by the loader (target_clones: an ifunc); no FMA can form (a product is
// never added to), so every clone gives the same bits.
__attribute__((target_clones("avx2", "default"))) void velocities_and_accelerations(
    std::size_t cells, const double* __restrict x, const double* __restrict xp, double lane_inv_dt,
    double* __restrict previous, double inverse_dt, double* __restrict a) {
    for (std::size_t c = 0; c < cells; ++c) {
        const double v = (x[c] - xp[c]) * lane_inv_dt;
        const double acceleration = (v - previous[c]) * inverse_dt;
        a[c] = std::isfinite(acceleration) ? acceleration : 0.0;
        previous[c] = v;
    }
}

}  // namespace

void FarFieldRadiation::process(const Canopy& canopy, double* pressures_pa) {
    if (canopy.panel_count() != panels_ || canopy.nodes_per_panel() != nodes_ || canopy.lanes() != lanes_) {
        for (int c = 0; c < layout_.channels(); ++c) pressures_pa[c] = 0.0;
        return;
    }
    const std::size_t stride = static_cast<std::size_t>(lanes_);
    for (int k = 0; k < panels_; ++k) {
        // A panel the runtime guard reset since the last sample restarted from rest (zero velocity):
        // its previous velocities read as 0 (v - 0.0, the bits the per-panel loop gave).
        const std::uint64_t resets = canopy.panel_guard_resets(k);
        if (resets != resets_seen_[static_cast<std::size_t>(k)])
            for (std::size_t i = 0; i < static_cast<std::size_t>(nodes_); ++i)
                previous_velocity_[i * stride + static_cast<std::size_t>(k)] = 0.0;
        resets_seen_[static_cast<std::size_t>(k)] = resets;
    }
    // Every panel's velocities and accelerations in one pass over the lanes' own layout (explicit Verlet,
    // laned: from the positions, as Canopy::velocities forms them), else the velocities, then the
    // accelerations.
    const LanedNetwork* lanes = canopy.lanes_state();
    if (lanes != nullptr && lanes->previous_positions() != nullptr &&
        static_cast<std::size_t>(lanes->mass_count() * lanes->lanes()) == velocity_.size()) {
        velocities_and_accelerations(velocity_.size(), lanes->positions(), lanes->previous_positions(), lanes->inverse_dt(),
                                     previous_velocity_.data(), inverse_dt_, radiator_.inputs());
    } else {
        canopy.velocities(velocity_.data());
        accelerations(velocity_.size(), velocity_.data(), previous_velocity_.data(), inverse_dt_, radiator_.inputs());
    }
    radiator_.process_inputs(sums_.data());
    if (glide_left_ > 0) {
        if (--glide_left_ == 0) {
            flat_gain_ = gain_target_;   // same size: a copy, no allocation; exactly the target at the end
        } else {
            for (std::size_t i = 0; i < flat_gain_.size(); ++i) flat_gain_[i] += gain_step_[i];
        }
    }
    const int channels = layout_.channels();
    for (int c = 0; c < channels; ++c) {
        const double* row = sums_.data() + static_cast<std::size_t>(layout_.channel_point[static_cast<std::size_t>(c)] * panels_);
        const double* gain = flat_gain_.data() + static_cast<std::size_t>(c * panels_);
        double p = 0.0;
        for (int k = 0; k < panels_; ++k) p += gain[k] * row[k];
        pressures_pa[c] = p;
    }
}

void FarFieldRadiation::set_panel_gains(const double* gains, int glide_frames) {
    if (layout_.panel_gain.empty()) return;
    for (std::size_t i = 0; i < gain_target_.size(); ++i) gain_target_[i] = gains[i];
    if (glide_frames <= 0) {
        flat_gain_ = gain_target_;
        glide_left_ = 0;
        return;
    }
    // From where the gains are now (mid-glide too): no jump.
    for (std::size_t i = 0; i < flat_gain_.size(); ++i) gain_step_[i] = (gain_target_[i] - flat_gain_[i]) / glide_frames;
    glide_left_ = glide_frames;
}

}  // namespace ameoto
