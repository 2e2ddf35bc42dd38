// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/lattice_ball.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace ameoto {
namespace {

// Candidate centres of the cutting sphere, in lattice units times 6 (so that squared distances times
// 36 are exact integers): a site, an octahedral hole, a tetrahedral hole, a bond midpoint, the centroid
// of a triangle of three mutual neighbours.
constexpr std::array<std::array<int, 3>, 5> kCentres6{{{0, 0, 0}, {6, 0, 0}, {3, 3, 3}, {3, 3, 0}, {4, 4, 4}}};

// Six of the 12 neighbour offsets, one of each +- pair: each link is made once.
constexpr std::array<std::array<int, 3>, 6> kHalfNeighbours{{{1, 1, 0}, {1, -1, 0}, {1, 0, 1}, {1, 0, -1}, {0, 1, 1}, {0, 1, -1}}};

struct Site {
    int i, j, k;
    std::int64_t key;   // 36 * squared distance from the centre, in lattice units
};


std::vector<Site> sites_around(int centre, int reach) {
    const auto& c = kCentres6[static_cast<std::size_t>(centre)];
    std::vector<Site> sites;
    for (int i = -reach; i <= reach; ++i)
        for (int j = -reach; j <= reach; ++j)
            for (int k = -reach; k <= reach; ++k) {
                if ((i + j + k) % 2 != 0) continue;
                const std::int64_t dx = 6 * i - c[0], dy = 6 * j - c[1], dz = 6 * k - c[2];
                sites.push_back({i, j, k, dx * dx + dy * dy + dz * dz});
            }
    return sites;
}

std::int64_t pack(int i, int j, int k) {
    constexpr std::int64_t base = 1 << 20;
    return ((static_cast<std::int64_t>(i) + base / 2) * base + (j + base / 2)) * base + (k + base / 2);
}

}  // namespace

int seed_mass_count(double diameter_m) {
    const double d_mm = diameter_m * 1e3;
    return std::max(1, static_cast<int>(std::lround(d_mm * d_mm * d_mm)));
}

namespace {

// Enumerating a cube of half-side `reach` finds every site within reach - 1 of any candidate centre
// (|centre| <= 1 per axis). Sites occupy 2 cubic lattice units each (4 per cube of side 2), so N sites
// fill a sphere of radius (3 N / 2 pi)^(1/3) units: half as far again, plus 3, holds every count near N.
int reach_for(int target) {
    const double radius_units = std::cbrt(3.0 * target / (2.0 * constants::pi));
    return static_cast<int>(std::ceil(1.5 * radius_units)) + 3;
}

// For each candidate centre, the counts that end a complete shell within `reach`, ascending.
using ShellTable = std::array<std::vector<LatticeBallChoice>, kCentres6.size()>;

ShellTable shell_table(int reach) {
    const std::int64_t complete_key = 36LL * (reach - 1) * (reach - 1);
    ShellTable table;
    for (int c = 0; c < static_cast<int>(kCentres6.size()); ++c) {
        auto sites = sites_around(c, reach);
        std::sort(sites.begin(), sites.end(), [](const Site& a, const Site& b) { return a.key < b.key; });
        for (std::size_t n = 0; n + 1 < sites.size() && sites[n + 1].key <= complete_key; ++n) {
            if (sites[n + 1].key == sites[n].key) continue;   // not the end of a shell
            table[static_cast<std::size_t>(c)].push_back({c, sites[n].key, sites[n + 1].key, static_cast<int>(n + 1)});
        }
    }
    return table;
}

// The count nearest the target; ties go to the earlier centre, then the smaller count. A table for a
// larger reach only adds counts far above the target, so the choice does not depend on the reach.
LatticeBallChoice choose(int target, const ShellTable& table) {
    LatticeBallChoice best;
    long best_error = std::numeric_limits<long>::max();
    for (const auto& shells : table)
        for (const auto& candidate : shells) {
            const long error = std::labs(static_cast<long>(candidate.count) - target);
            if (error < best_error) {
                best = candidate;
                best_error = error;
            }
        }
    return best;
}

}  // namespace

std::vector<LatticeBallChoice> lattice_ball_choices(int max_target) {
    const int top = std::max(1, max_target);
    if (top > 200000) throw std::invalid_argument("lattice ball: more than 200000 masses requested");
    const ShellTable table = shell_table(reach_for(top));
    std::vector<LatticeBallChoice> choices;
    choices.reserve(static_cast<std::size_t>(top));
    for (int t = 1; t <= top; ++t) choices.push_back(choose(t, table));
    return choices;
}

LatticeBallShape lattice_ball_shape(int target_masses) {
    const int target = std::max(1, target_masses);
    if (target > 200000) throw std::invalid_argument("lattice ball: more than 200000 masses requested");
    return lattice_ball_shape(choose(target, shell_table(reach_for(target))));
}

LatticeBallShape lattice_ball_shape(const LatticeBallChoice& best) {
    // The sites of the chosen shells, in the enumeration's (i, j, k) order, which does not depend on
    // the reach as long as it holds them all.
    const int reach = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(best.last_key)) / 6.0)) + 2;
    // Lattice unit -> metres of a 1 m ball: its radius (0.5) sits half way between the last shell and
    // the next.
    const double mid_units = (std::sqrt(static_cast<double>(best.last_key)) + std::sqrt(static_cast<double>(best.next_key))) / 12.0;
    const double unit = 0.5 / mid_units;
    const auto& c6 = kCentres6[static_cast<std::size_t>(best.centre_kind)];
    const double cx = c6[0] / 6.0, cy = c6[1] / 6.0, cz = c6[2] / 6.0;

    std::vector<Site> chosen;
    for (const auto& s : sites_around(best.centre_kind, reach))
        if (s.key <= best.last_key) chosen.push_back(s);
    Vec3 mean{};
    for (const auto& s : chosen) mean = mean + Vec3{s.i - cx, s.j - cy, s.k - cz};
    mean = mean / static_cast<double>(chosen.size());

    LatticeBallShape shape;
    shape.spacing = std::sqrt(2.0) * unit;
    shape.sphere_offset = norm(mean) * unit;
    shape.centre_kind = best.centre_kind;
    shape.last_shell_key = best.last_key;
    std::unordered_map<std::int64_t, int> index;
    for (const auto& s : chosen) {
        index[pack(s.i, s.j, s.k)] = shape.mass_count();
        shape.position.push_back(unit * (Vec3{s.i - cx, s.j - cy, s.k - cz} - mean));
    }
    for (const auto& s : chosen) {
        const int a = index.at(pack(s.i, s.j, s.k));
        for (const auto& o : kHalfNeighbours) {
            const auto it = index.find(pack(s.i + o[0], s.j + o[1], s.k + o[2]));
            if (it == index.end()) continue;
            shape.link_a.push_back(a);
            shape.link_b.push_back(it->second);
        }
    }
    return shape;
}

LatticeBallInfo add_lattice_ball(Body3D& body, const LatticeBallSpec& spec) {
    if (!(spec.diameter > 0.0) || !std::isfinite(spec.diameter)) throw std::invalid_argument("ball diameter must be positive");
    if (!(spec.density > 0.0)) throw std::invalid_argument("ball density must be positive");
    const int target = spec.target_masses > 0 ? spec.target_masses : seed_mass_count(spec.diameter);
    if (target > 200000) throw std::invalid_argument("lattice ball: more than 200000 masses requested");
    const LatticeBallShape shape = lattice_ball_shape(target);

    LatticeBallInfo info;
    info.first_mass = body.mass_count();
    info.first_link = body.link_count();
    info.mass_count = shape.mass_count();
    info.spacing = spec.diameter * shape.spacing;
    info.total_mass = spec.density * constants::pi * spec.diameter * spec.diameter * spec.diameter / 6.0;
    info.node_mass = info.total_mass / info.mass_count;
    info.sphere_offset = spec.diameter * shape.sphere_offset;
    for (const Vec3& p : shape.position) body.add_mass(info.node_mass, spec.centre + spec.diameter * p);
    for (int l = 0; l < shape.link_count(); ++l)
        body.add_link(info.first_mass + shape.link_a[static_cast<std::size_t>(l)], info.first_mass + shape.link_b[static_cast<std::size_t>(l)],
                      spec.link_kind, spec.stiffness, spec.damping, info.spacing, spec.break_force);
    info.link_count = body.link_count() - info.first_link;
    return info;
}

LatticeBall make_lattice_ball(const LatticeBallSpec& spec) {
    LatticeBall ball;
    ball.info = add_lattice_ball(ball.body, spec);
    return ball;
}

}  // namespace ameoto
