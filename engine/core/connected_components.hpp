#pragma once
// Connected components of a Body3D's masses over its bonds: the pieces a drop has broken into.
//
// Interface:
//   ConnectedComponents cc;
//   cc.init(body.mass_count());                 // allocates; once, outside the audio thread
//   ---- no allocation ----
//   int n = cc.compute(body);                   // bonds: unbroken spring and breakable links
//   int n = cc.compute(mass_count, a, b, bonds);// generic: link l joins a[l], b[l] if bonds[l] != 0
//   cc.count();                                 // number of components
//   cc.component_of(mass);                      // 0 .. count - 1, numbered in order of their lowest mass
//   cc.size_of(component);                      // masses in it; the sizes add up to mass_count
//   cc.components();                            // component_of for every mass, as a span
//
// Union-find (Tarjan 1975) with union by size and path halving: near-linear in masses + links, on
// arrays sized by init(), so a body can be split after links break without leaving the audio thread.
// Contact links do not bind (two drops touching stay two drops). Fixed points are masses like any
// other: a fixed point bonded to two pieces joins them; leave such bonds out of a generic call if that
// is not wanted. A body with more masses than init() was given is not split (count() == 0): growing
// the arrays would allocate. The generic call ignores links whose ends are out of range.

#include <cstdint>
#include <span>
#include <vector>

namespace ameoto {

class Body3D;

class ConnectedComponents {
public:
    void init(int mass_count);

    int compute(const Body3D& body);
    int compute(int mass_count, std::span<const std::int32_t> link_a, std::span<const std::int32_t> link_b,
                std::span<const std::uint8_t> bonds);

    int count() const { return count_; }
    int component_of(int mass) const { return label_[static_cast<std::size_t>(mass)]; }
    int size_of(int component) const { return size_[static_cast<std::size_t>(component)]; }
    std::span<const int> components() const { return {label_.data(), static_cast<std::size_t>(mass_count_)}; }

private:
    void start(int mass_count);
    int find(int m);
    void unite(int a, int b);
    int finish();

    std::vector<int> parent_, size_, label_;
    int mass_count_ = 0;
    int count_ = 0;
};

}  // namespace ameoto
