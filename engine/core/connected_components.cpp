// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/connected_components.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "engine/core/body3d.hpp"

namespace ameoto {

void ConnectedComponents::init(int mass_count, int link_count) {
    if (mass_count < 0) throw std::invalid_argument("mass count must be >= 0");
    if (link_count < 0) throw std::invalid_argument("link count must be >= 0");
    const auto masses = static_cast<std::size_t>(mass_count), entries = 2 * static_cast<std::size_t>(link_count);
    parent_.assign(masses, 0);
    size_.assign(masses, 0);
    label_.assign(masses, 0);
    row_.assign(masses + 1, 0);
    neighbour_.assign(entries, 0);
    via_link_.assign(entries, 0);
    queue_a_.assign(masses, 0);
    queue_b_.assign(masses, 0);
    changed_.assign(masses, 0);
    stamp_.assign(masses, 0);
    pending_.assign(static_cast<std::size_t>(link_count), 0);
    next_stamp_ = 0;
    link_capacity_ = link_count;
    adjacency_ready_ = false;
    changed_count_ = 0;
    mass_count_ = 0;
    count_ = 0;
}

void ConnectedComponents::start(int mass_count) {
    adjacency_ready_ = false;   // a new body, or the same one reset: its adjacency is built again if needed
    changed_count_ = 0;
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
    for (int c = 0; c < count_; ++c) changed_[static_cast<std::size_t>(c)] = c;
    changed_count_ = count_;
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

namespace {

// The two kinds of graph update() works on, seen the same way: which links may bind (they go in the
// adjacency), whether a link binds now, and its ends.
struct BodyLinks {
    const Body3D& body;
    int link_count() const { return body.link_count(); }
    bool bindable(int l) const { return body.link_kind(l) != LinkKind::contact; }
    bool bonds(int l) const { return body.link_bonds(l); }
    int a(int l) const { return body.link_a(l); }
    int b(int l) const { return body.link_b(l); }
};

struct GenericLinks {
    int mass_count;
    std::span<const std::int32_t> link_a, link_b;
    std::span<const std::uint8_t> bond;
    int link_count() const { return static_cast<int>(std::min({link_a.size(), link_b.size(), bond.size()})); }
    bool bindable(int l) const {
        const int p = a(l), q = b(l);
        return p >= 0 && q >= 0 && p < mass_count && q < mass_count;
    }
    bool bonds(int l) const { return bond[static_cast<std::size_t>(l)] != 0; }
    int a(int l) const { return link_a[static_cast<std::size_t>(l)]; }
    int b(int l) const { return link_b[static_cast<std::size_t>(l)]; }
};

// One broken link's ends, or a = -1 for one update() ignores (out of range).
struct BrokenLink {
    int a = -1, b = -1, link = -1;
};

}  // namespace

void ConnectedComponents::mark_changed(int component) {
    for (int i = 0; i < changed_count_; ++i)
        if (changed_[static_cast<std::size_t>(i)] == component) return;
    changed_[static_cast<std::size_t>(changed_count_++)] = component;
}

template <typename Links>
bool ConnectedComponents::build_adjacency(const Links& links) {
    // Compressed rows: count each mass's bindable links, prefix-sum, fill (queue_a_ as the cursor).
    const int n = links.link_count();
    if (n > link_capacity_) return false;
    const auto row = [this](int m) -> int& { return row_[static_cast<std::size_t>(m)]; };
    for (int m = 0; m <= mass_count_; ++m) row(m) = 0;
    for (int l = 0; l < n; ++l)
        if (links.bindable(l)) {
            ++row(links.a(l) + 1);
            ++row(links.b(l) + 1);
        }
    for (int m = 0; m < mass_count_; ++m) row(m + 1) += row(m);
    for (int m = 0; m < mass_count_; ++m) queue_a_[static_cast<std::size_t>(m)] = row(m);
    for (int l = 0; l < n; ++l) {
        if (!links.bindable(l)) continue;
        const int p = links.a(l), q = links.b(l);
        const auto at_p = static_cast<std::size_t>(queue_a_[static_cast<std::size_t>(p)]++);
        const auto at_q = static_cast<std::size_t>(queue_a_[static_cast<std::size_t>(q)]++);
        neighbour_[at_p] = q;
        via_link_[at_p] = l;
        neighbour_[at_q] = p;
        via_link_[at_q] = l;
    }
    adjacency_ready_ = true;
    return true;
}

template <typename Links>
bool ConnectedComponents::split_if_severed(const Links& links, int a, int b) {
    // Two breadth-first searches, from a and from b, over bonded links, each expanding one mass in turn.
    // Meeting: still one piece. One running out first: its masses are a piece of their own.
    if (next_stamp_ > 0xFFFFFFF0u) {   // after four billion searches: start the stamps again
        for (int m = 0; m < mass_count_; ++m) stamp_[static_cast<std::size_t>(m)] = 0;
        next_stamp_ = 0;
    }
    const std::uint32_t mark_a = ++next_stamp_, mark_b = ++next_stamp_;
    int head_a = 0, tail_a = 0, head_b = 0, tail_b = 0;
    queue_a_[static_cast<std::size_t>(tail_a++)] = a;
    queue_b_[static_cast<std::size_t>(tail_b++)] = b;
    stamp_[static_cast<std::size_t>(a)] = mark_a;
    stamp_[static_cast<std::size_t>(b)] = mark_b;
    // Expands one mass of one side; true if it reached the other side.
    const auto expand = [&](std::vector<int>& queue, int& head, int& tail, std::uint32_t own, std::uint32_t other) {
        const int m = queue[static_cast<std::size_t>(head++)];
        for (int e = row_[static_cast<std::size_t>(m)]; e < row_[static_cast<std::size_t>(m) + 1]; ++e) {
            const auto l = static_cast<std::size_t>(via_link_[static_cast<std::size_t>(e)]);
            if (!links.bonds(static_cast<int>(l)) && !pending_[l]) continue;
            const int n = neighbour_[static_cast<std::size_t>(e)];
            std::uint32_t& s = stamp_[static_cast<std::size_t>(n)];
            if (s == other) return true;
            if (s == own) continue;
            s = own;
            queue[static_cast<std::size_t>(tail++)] = n;
        }
        return false;
    };
    for (;;) {
        if (head_a == tail_a || head_b == tail_b) break;
        if (expand(queue_a_, head_a, tail_a, mark_a, mark_b)) return false;
        if (head_a == tail_a) break;
        if (expand(queue_b_, head_b, tail_b, mark_b, mark_a)) return false;
    }
    // The side that ran out is closed: every mass bonded to it is in it.
    const bool a_closed = head_a == tail_a;
    const std::vector<int>& piece = a_closed ? queue_a_ : queue_b_;
    const int piece_size = a_closed ? tail_a : tail_b;
    const int old = label_[static_cast<std::size_t>(a)];
    const int fresh = count_++;
    for (int i = 0; i < piece_size; ++i) label_[static_cast<std::size_t>(piece[static_cast<std::size_t>(i)])] = fresh;
    size_[static_cast<std::size_t>(fresh)] = piece_size;
    size_[static_cast<std::size_t>(old)] -= piece_size;
    mark_changed(old);
    mark_changed(fresh);
    return true;
}

template <typename Links, typename Ends>
int ConnectedComponents::update_with(const Links& links, int broken_count, const Ends& ends) {
    // The breaks are taken one at a time, as if the links had broken in that order: a link not yet taken
    // still binds (pending_), so after each one the labels are the components of the graph so far, and a
    // search never has to look beyond the one piece that held both ends (Even & Shiloach's invariant).
    changed_count_ = 0;
    if (mass_count_ == 0) return count_;
    int searches = 0;
    for (int i = 0; i < broken_count; ++i) {
        const auto e = ends(i);
        if (e.a >= 0 && e.a != e.b && label_[static_cast<std::size_t>(e.a)] == label_[static_cast<std::size_t>(e.b)]) ++searches;
    }
    if (searches == 0) return count_;
    if (searches > max_searches_per_update || (!adjacency_ready_ && !build_adjacency(links))) return -1;
    for (int i = 0; i < broken_count; ++i)
        if (const auto e = ends(i); e.a >= 0) pending_[static_cast<std::size_t>(e.link)] = 1;
    for (int i = 0; i < broken_count; ++i) {
        const auto e = ends(i);
        if (e.a < 0) continue;
        pending_[static_cast<std::size_t>(e.link)] = 0;
        if (e.a != e.b && label_[static_cast<std::size_t>(e.a)] == label_[static_cast<std::size_t>(e.b)])
            split_if_severed(links, e.a, e.b);
    }
    return count_;
}

int ConnectedComponents::update(const Body3D& body, std::span<const LinkBreak> breaks) {
    if (mass_count_ != body.mass_count()) return compute(body);
    const BodyLinks links{body};
    const int link_count = links.link_count();
    const int n = update_with(links, static_cast<int>(breaks.size()), [&](int i) {
        const LinkBreak& e = breaks[static_cast<std::size_t>(i)];
        return e.link >= 0 && e.link < link_count ? BrokenLink{links.a(e.link), links.b(e.link), e.link} : BrokenLink{};
    });
    return n >= 0 ? n : compute(body);
}

int ConnectedComponents::update(int mass_count, std::span<const std::int32_t> link_a, std::span<const std::int32_t> link_b,
                                std::span<const std::uint8_t> bonds, std::span<const std::int32_t> broken_links) {
    if (mass_count_ != mass_count) return compute(mass_count, link_a, link_b, bonds);
    const GenericLinks links{mass_count, link_a, link_b, bonds};
    const int link_count = links.link_count();
    const int n = update_with(links, static_cast<int>(broken_links.size()), [&](int i) {
        const int l = broken_links[static_cast<std::size_t>(i)];
        return l >= 0 && l < link_count && links.bindable(l) ? BrokenLink{links.a(l), links.b(l), l} : BrokenLink{};
    });
    return n >= 0 ? n : compute(mass_count, link_a, link_b, bonds);
}

}  // namespace ameoto
