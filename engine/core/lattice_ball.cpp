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

struct Choice {
    int centre = 0;
    std::int64_t last_key = 0, next_key = 0;
    int count = 0;
    long error = std::numeric_limits<long>::max();
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

LatticeBallInfo add_lattice_ball(Body3D& body, const LatticeBallSpec& spec) {
    if (!(spec.diameter > 0.0) || !std::isfinite(spec.diameter)) throw std::invalid_argument("ball diameter must be positive");
    if (!(spec.density > 0.0)) throw std::invalid_argument("ball density must be positive");
    const int target = spec.target_masses > 0 ? spec.target_masses : seed_mass_count(spec.diameter);
    if (target > 200000) throw std::invalid_argument("lattice ball: more than 200000 masses requested");

    // Sites occupy 2 cubic lattice units each (4 per cube of side 2), so N sites fill a sphere of radius
    // (3 N / 2 pi)^(1/3) units. Enumerating a cube of half-side `reach` finds every site within
    // reach - 1 of any candidate centre (|centre| <= 1 per axis).
    const double radius_units = std::cbrt(3.0 * target / (2.0 * constants::pi));
    const int reach = static_cast<int>(std::ceil(1.5 * radius_units)) + 3;
    const std::int64_t complete_key = 36LL * (reach - 1) * (reach - 1);

    Choice best;
    for (int c = 0; c < static_cast<int>(kCentres6.size()); ++c) {
        auto sites = sites_around(c, reach);
        std::sort(sites.begin(), sites.end(), [](const Site& a, const Site& b) { return a.key < b.key; });
        for (std::size_t n = 0; n + 1 < sites.size() && sites[n + 1].key <= complete_key; ++n) {
            if (sites[n + 1].key == sites[n].key) continue;   // not the end of a shell
            const int count = static_cast<int>(n + 1);
            const long error = std::labs(static_cast<long>(count) - target);
            if (error < best.error) best = {c, sites[n].key, sites[n + 1].key, count, error};
        }
    }

    // Lattice unit -> metres: the sphere's radius sits half way between the last shell and the next.
    const double radius = 0.5 * spec.diameter;
    const double mid_units = (std::sqrt(static_cast<double>(best.last_key)) + std::sqrt(static_cast<double>(best.next_key))) / 12.0;
    const double unit = radius / mid_units;
    const auto& c6 = kCentres6[static_cast<std::size_t>(best.centre)];
    const double cx = c6[0] / 6.0, cy = c6[1] / 6.0, cz = c6[2] / 6.0;

    std::vector<Site> chosen;
    for (const auto& s : sites_around(best.centre, reach))
        if (s.key <= best.last_key) chosen.push_back(s);
    Vec3 mean{};
    for (const auto& s : chosen) mean = mean + Vec3{s.i - cx, s.j - cy, s.k - cz};
    mean = mean / static_cast<double>(chosen.size());

    LatticeBallInfo info;
    info.first_mass = body.mass_count();
    info.first_link = body.link_count();
    info.mass_count = static_cast<int>(chosen.size());
    info.spacing = std::sqrt(2.0) * unit;
    info.total_mass = spec.density * constants::pi * spec.diameter * spec.diameter * spec.diameter / 6.0;
    info.node_mass = info.total_mass / info.mass_count;
    info.sphere_offset = norm(mean) * unit;

    std::unordered_map<std::int64_t, int> index;
    for (const auto& s : chosen) {
        const Vec3 p = spec.centre + unit * (Vec3{s.i - cx, s.j - cy, s.k - cz} - mean);
        index[pack(s.i, s.j, s.k)] = body.add_mass(info.node_mass, p);
    }
    for (const auto& s : chosen) {
        const int a = index.at(pack(s.i, s.j, s.k));
        for (const auto& o : kHalfNeighbours) {
            const auto it = index.find(pack(s.i + o[0], s.j + o[1], s.k + o[2]));
            if (it == index.end()) continue;
            body.add_link(a, it->second, spec.link_kind, spec.stiffness, spec.damping, info.spacing, spec.break_force);
        }
    }
    info.link_count = body.link_count() - info.first_link;
    return info;
}

LatticeBall make_lattice_ball(const LatticeBallSpec& spec) {
    LatticeBall ball;
    ball.info = add_lattice_ball(ball.body, spec);
    return ball;
}

}  // namespace ameoto
