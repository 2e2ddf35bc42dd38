#include "engine/core/connected_components.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "engine/core/body3d.hpp"

namespace ameoto {

void ConnectedComponents::init(int mass_count) {
    if (mass_count < 0) throw std::invalid_argument("mass count must be >= 0");
    parent_.assign(static_cast<std::size_t>(mass_count), 0);
    size_.assign(static_cast<std::size_t>(mass_count), 0);
    label_.assign(static_cast<std::size_t>(mass_count), 0);
    mass_count_ = 0;
    count_ = 0;
}

void ConnectedComponents::start(int mass_count) {
    // Never grows here (the audio thread must not allocate): a body larger than init() is refused by
    // an empty result, which the caller sees as count() == 0 for a non-empty body.
    mass_count_ = static_cast<std::size_t>(mass_count) <= parent_.size() ? mass_count : 0;
    for (int m = 0; m < mass_count_; ++m) {
        parent_[static_cast<std::size_t>(m)] = m;
        size_[static_cast<std::size_t>(m)] = 1;
    }
}

int ConnectedComponents::find(int m) {
    // Path halving: every other node on the way points to its grandparent.
    while (parent_[static_cast<std::size_t>(m)] != m) {
        auto& p = parent_[static_cast<std::size_t>(m)];
        p = parent_[static_cast<std::size_t>(p)];
        m = p;
    }
    return m;
}

void ConnectedComponents::unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (size_[static_cast<std::size_t>(a)] < size_[static_cast<std::size_t>(b)]) std::swap(a, b);
    parent_[static_cast<std::size_t>(b)] = a;
    size_[static_cast<std::size_t>(a)] += size_[static_cast<std::size_t>(b)];
}

int ConnectedComponents::finish() {
    // Label in order of each component's lowest mass. A root's slot may be labelled before the loop
    // reaches it (when a lower mass points to it); it then labels itself with the same value.
    count_ = 0;
    for (int m = 0; m < mass_count_; ++m) label_[static_cast<std::size_t>(m)] = -1;
    for (int m = 0; m < mass_count_; ++m) {
        const auto root = static_cast<std::size_t>(find(m));
        if (label_[root] < 0) label_[root] = count_++;
        label_[static_cast<std::size_t>(m)] = label_[root];
    }
    // The union sizes are no longer needed: size_ now counts the masses of each labelled component.
    for (int c = 0; c < count_; ++c) size_[static_cast<std::size_t>(c)] = 0;
    for (int m = 0; m < mass_count_; ++m) ++size_[static_cast<std::size_t>(label_[static_cast<std::size_t>(m)])];
    return count_;
}

int ConnectedComponents::compute(int mass_count, std::span<const std::int32_t> link_a,
                                 std::span<const std::int32_t> link_b, std::span<const std::uint8_t> bonds) {
    start(mass_count);
    if (mass_count_ != mass_count) return count_ = 0;
    const std::size_t links = std::min({link_a.size(), link_b.size(), bonds.size()});
    for (std::size_t l = 0; l < links; ++l) {
        const int a = link_a[l], b = link_b[l];
        if (bonds[l] && a >= 0 && b >= 0 && a < mass_count && b < mass_count) unite(a, b);
    }
    return finish();
}

int ConnectedComponents::compute(const Body3D& body) {
    start(body.mass_count());
    if (mass_count_ != body.mass_count()) return count_ = 0;
    for (int l = 0; l < body.link_count(); ++l)
        if (body.link_bonds(l)) unite(body.link_a(l), body.link_b(l));
    return finish();
}

}  // namespace ameoto
