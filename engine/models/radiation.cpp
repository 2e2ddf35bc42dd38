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
        const NetworkArrays& a = canopy.panel(panel).network.arrays();
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
    : elements_(std::move(elements)), points_(std::move(points)), groups_(groups) {
    if (!(time_step_s > 0.0)) throw std::invalid_argument("time step must be positive");
    if (!(air.density > 0.0) || !(air.speed_of_sound > 0.0)) throw std::invalid_argument("air needs density and c");
    if (groups < 1) throw std::invalid_argument("at least one group");
    if (points_.empty()) throw std::invalid_argument("at least one listening point");
    const std::size_t n = elements_.size();
    taps_.resize(points_.size() * n);
    int longest = 0;
    for (std::size_t p = 0; p < points_.size(); ++p) {
        for (std::size_t e = 0; e < n; ++e) {
            const RadiatingElement& el = elements_[e];
            if (el.group < 0 || el.group >= groups) throw std::invalid_argument("element group out of range");
            if (!(el.area > 0.0)) throw std::invalid_argument("element area must be positive");
            const Vec3 d = points_[p] - el.position;
            // Floor a_eq / 2: the Rayleigh integral over a disc of area A from its centre (header).
            const double floor = 0.5 * std::sqrt(el.area / constants::pi);
            const double r = std::max(norm(d), floor);
            const double side = dot(d, el.normal) < 0.0 ? -1.0 : 1.0;   // the face that looks at the point
            const double g = side * air.density * el.area / (2.0 * constants::pi * r);
            const double delay = r / (air.speed_of_sound * time_step_s);
            const double whole = std::floor(delay), frac = delay - whole;
            Tap& t = taps_[p * n + e];
            t.element = static_cast<int>(e);
            t.offset = static_cast<int>(whole);
            t.w0 = (1.0 - frac) * g;
            t.w1 = frac * g;
            t.distance = r;
            t.delay = delay;
            longest = std::max(longest, t.offset + 1);
        }
    }
    int length = 1;
    while (length < longest + 1) length *= 2;   // a power of two: the ring index is a mask
    mask_ = length - 1;
    history_.assign(n * static_cast<std::size_t>(length), 0.0);
}

void RayleighRadiator::process(const double* accelerations, double* out) {
    const std::size_t n = elements_.size(), length = static_cast<std::size_t>(mask_) + 1;
    write_ = (write_ + 1) & mask_;
    for (std::size_t e = 0; e < n; ++e)
        history_[e * length + static_cast<std::size_t>(write_)] = std::isfinite(accelerations[e]) ? accelerations[e] : 0.0;
    const std::size_t outputs = points_.size() * static_cast<std::size_t>(groups_);
    for (std::size_t o = 0; o < outputs; ++o) out[o] = 0.0;
    for (std::size_t p = 0; p < points_.size(); ++p) {
        double* row = out + p * static_cast<std::size_t>(groups_);
        const Tap* taps = taps_.data() + p * n;
        for (std::size_t e = 0; e < n; ++e) {
            const Tap& t = taps[e];
            const double* ring = history_.data() + e * length;
            const double now = ring[static_cast<std::size_t>((write_ - t.offset) & mask_)];
            const double before = ring[static_cast<std::size_t>((write_ - t.offset - 1) & mask_)];
            row[elements_[e].group] += t.w0 * now + t.w1 * before;
        }
    }
}

void RayleighRadiator::reset() {
    std::fill(history_.begin(), history_.end(), 0.0);
    write_ = 0;
}

double RayleighRadiator::distance(int point, int element) const {
    return taps_[static_cast<std::size_t>(point) * elements_.size() + static_cast<std::size_t>(element)].distance;
}

double RayleighRadiator::delay_samples(int point, int element) const {
    return taps_[static_cast<std::size_t>(point) * elements_.size() + static_cast<std::size_t>(element)].delay;
}

double RayleighRadiator::gain(int point, int element) const {
    const Tap& t = taps_[static_cast<std::size_t>(point) * elements_.size() + static_cast<std::size_t>(element)];
    return t.w0 + t.w1;
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
    const std::size_t n = static_cast<std::size_t>(panels_ * nodes_);
    previous_velocity_.assign(n, 0.0);
    acceleration_.assign(n, 0.0);
    sums_.assign(layout.points.size() * static_cast<std::size_t>(panels_), 0.0);
    resets_seen_.assign(static_cast<std::size_t>(panels_), 0);
    for (int k = 0; k < panels_; ++k) {
        resets_seen_[static_cast<std::size_t>(k)] = canopy.panel(k).network.guard_resets();
        for (int i = 0; i < nodes_; ++i)
            previous_velocity_[static_cast<std::size_t>(k * nodes_ + i)] = canopy.normal_velocity(k, i);
    }
}

void FarFieldRadiation::process(const Canopy& canopy, double* pressures_pa) {
    if (canopy.panel_count() != panels_ || canopy.nodes_per_panel() != nodes_) {
        for (int c = 0; c < layout_.channels(); ++c) pressures_pa[c] = 0.0;
        return;
    }
    for (int k = 0; k < panels_; ++k) {
        // A panel the runtime guard reset since the last sample restarted from rest (zero velocity).
        const std::uint64_t resets = canopy.panel(k).network.guard_resets();
        const bool restarted = resets != resets_seen_[static_cast<std::size_t>(k)];
        resets_seen_[static_cast<std::size_t>(k)] = resets;
        double* previous = previous_velocity_.data() + static_cast<std::size_t>(k * nodes_);
        double* a = acceleration_.data() + static_cast<std::size_t>(k * nodes_);
        for (int i = 0; i < nodes_; ++i) {
            const double v = canopy.normal_velocity(k, i);
            a[i] = (v - (restarted ? 0.0 : previous[i])) * inverse_dt_;
            previous[i] = v;
        }
    }
    radiator_.process(acceleration_.data(), sums_.data());
    const int channels = layout_.channels();
    for (int c = 0; c < channels; ++c) {
        const double* row = sums_.data() + static_cast<std::size_t>(layout_.channel_point[static_cast<std::size_t>(c)] * panels_);
        const double* gain = flat_gain_.data() + static_cast<std::size_t>(c * panels_);
        double p = 0.0;
        for (int k = 0; k < panels_; ++k) p += gain[k] * row[k];
        pressures_pa[c] = p;
    }
}

}  // namespace ameoto
