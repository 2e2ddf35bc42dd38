// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Connected components of a Body3D's masses over its bonds: the pieces a drop has broken into.
//
// Interface:
//   ConnectedComponents cc;
//   cc.init(body.mass_count(), body.link_count()); // allocates; once, outside the audio thread
//   ---- no allocation ----
//   int n = cc.compute(body);                   // bonds: unbroken spring and breakable links
//   int n = cc.compute(mass_count, a, b, bonds);// generic: link l joins a[l], b[l] if bonds[l] != 0
//   int n = cc.update(body, body.breaks());     // after a step: only the pieces those breaks touched
//   int n = cc.update(mass_count, a, b, bonds, broken);   // generic: `broken` lists links now unbonded
//   cc.count();                                 // number of components
//   cc.component_of(mass);                      // 0 .. count - 1
//   cc.size_of(component);                      // masses in it; the sizes add up to mass_count
//   cc.components();                            // component_of for every mass, as a span
//   cc.changed();                               // components whose masses changed in the last update
//
// compute(): union-find (Tarjan 1975) with union by size and path halving: near-linear in masses +
// links, on arrays sized by init(), so a body can be split after links break without leaving the audio
// thread. Components are numbered in order of their lowest mass.
//
// update(): links only ever break (a reset or a new body goes through compute()), so a break can only
// split the component that held both its ends, and only if no other path joins them. The breaks are
// taken one at a time (a link not yet taken still binds), so after each the labels are the components
// so far (Even & Shiloach 1981, "An on-line edge-deletion problem", J. ACM 28:1). For a broken link whose
// ends still share a label, a bidirectional breadth-first search runs from both ends over the bonded
// links, one mass from each side in turn: it stops as soon as the two searches meet (still one piece) or
// one of them runs out, and that side is then a new piece, labelled count(). The cost is about twice the
// smaller side, not the whole body: a tear that leaves the drop whole costs the few masses around the
// torn link, a small piece its own masses. The adjacency (compressed rows over every non-contact link,
// broken or not: bonds are read when searched) is built on the first update after a compute(), within
// init()'s link capacity. New pieces are numbered after the old ones, so after an update the numbering
// is by creation, not by lowest mass; the partition and the sizes equal compute()'s exactly (the fuzz
// test compares them). If more than max_searches_per_update broken links join one piece, a search per
// link may cost more than starting over, and update() runs compute() instead (changed() then lists
// every component); so does a body with more links than init() was given.

// Contact links do not bind (two drops touching stay two drops). Fixed points are masses like any
// other: a fixed point bonded to two pieces joins them; leave such bonds out of a generic call if that
// is not wanted. A body with more masses (or, for update(), links) than init() was given is not split
// (count() == 0): growing the arrays would allocate. The generic calls ignore links whose ends are out
// of range.

#include <cstdint>
#include <span>
#include <vector>

namespace ameoto {

class Body3D;
struct LinkBreak;

class ConnectedComponents {
public:
    static constexpr int max_searches_per_update = 16;

    void init(int mass_count, int link_count = 0);

    int compute(const Body3D& body);
    int compute(int mass_count, std::span<const std::int32_t> link_a, std::span<const std::int32_t> link_b,
                std::span<const std::uint8_t> bonds);
    int update(const Body3D& body, std::span<const LinkBreak> breaks);
    int update(int mass_count, std::span<const std::int32_t> link_a, std::span<const std::int32_t> link_b,
               std::span<const std::uint8_t> bonds, std::span<const std::int32_t> broken_links);

    int count() const { return count_; }
    int component_of(int mass) const { return label_[static_cast<std::size_t>(mass)]; }
    int size_of(int component) const { return size_[static_cast<std::size_t>(component)]; }
    std::span<const int> components() const { return {label_.data(), static_cast<std::size_t>(mass_count_)}; }
    std::span<const int> changed() const { return {changed_.data(), static_cast<std::size_t>(changed_count_)}; }

private:
    void start(int mass_count);
    int find(int m);
    void unite(int a, int b);
    int finish();
    template <typename Links>
    bool build_adjacency(const Links& links);
    template <typename Links>
    bool split_if_severed(const Links& links, int a, int b);
    template <typename Links, typename Ends>
    int update_with(const Links& links, int broken_count, const Ends& ends);
    void mark_changed(int component);

    std::vector<int> parent_, size_, label_;
    // Incremental update: compressed adjacency (row_ start per mass, neighbour and link per entry),
    // two search queues, a visit stamp per mass, and the list of changed components.
    std::vector<int> row_, neighbour_, via_link_, queue_a_, queue_b_, changed_;
    std::vector<std::uint32_t> stamp_;
    std::vector<std::uint8_t> pending_;   // broken links this update has not taken yet: still binding
    std::uint32_t next_stamp_ = 0;
    int link_capacity_ = 0;
    bool adjacency_ready_ = false;
    int changed_count_ = 0;
    int mass_count_ = 0;
    int count_ = 0;
};

}  // namespace ameoto
