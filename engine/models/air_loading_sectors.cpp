// SPDX-License-Identifier: GPL-3.0-or-later
// One panel's sub-cells for the air's mass: see air_loading_sectors.hpp.
#include "engine/models/air_loading_sectors.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "engine/core/physical_constants.hpp"
#include "engine/models/canopy.hpp"

namespace ameoto::air_sectors {

std::vector<SectorCell> sector_cells(const Canopy& canopy, int rows) {
    const double r = canopy.geometry().radius_m, a0 = canopy.panel_azimuth(0);
    const double half = constants::pi / canopy.panel_count();
    const Point2 ta{r * std::cos(a0 - half), r * std::sin(a0 - half)}, tb{r * std::cos(a0 + half), r * std::sin(a0 + half)};
    const auto at = [&](double u, double v) {
        return Point2{u * (ta.x + v * (tb.x - ta.x)), u * (ta.y + v * (tb.y - ta.y))};
    };
    std::vector<SectorCell> cells;
    for (int i = 0; i < rows; ++i) {
        const double u0 = static_cast<double>(i) / rows, u1 = static_cast<double>(i + 1) / rows;
        for (int j = 0; j <= i; ++j) {
            const double v0 = static_cast<double>(j) / (i + 1), v1 = static_cast<double>(j + 1) / (i + 1);
            SectorCell c;
            if (i == 0) c.corners = {at(u0, 0.0), at(u1, v0), at(u1, v1)};
            else c.corners = {at(u0, v0), at(u1, v0), at(u1, v1), at(u0, v1)};
            // Shoelace area and centroid.
            double area2 = 0.0, cx = 0.0, cy = 0.0;
            for (std::size_t q = 0; q < c.corners.size(); ++q) {
                const Point2 p = c.corners[q], n = c.corners[(q + 1) % c.corners.size()];
                const double cross = p.x * n.y - n.x * p.y;
                area2 += cross;
                cx += (p.x + n.x) * cross;
                cy += (p.y + n.y) * cross;
            }
            c.area = 0.5 * area2;
            c.centroid = {cx / (3.0 * area2), cy / (3.0 * area2)};
            const CanopyHit hit = canopy.locate(c.centroid.x, c.centroid.y);
            if (hit.panel != 0) throw std::runtime_error("canopy_added_mass: a sub-cell's centre is off panel 0");
            c.node = hit.node;
            c.row = i;
            c.v = 0.5 * (v0 + v1);
            cells.push_back(std::move(c));
        }
    }
    return cells;
}

double ring_velocity(Point2 p, const std::vector<Point2>& ring, double cos_turn, double sin_turn) {
    double w = 0.0;
    const std::size_t n = ring.size();
    for (std::size_t q = 0; q < n; ++q) {
        const Point2 a0 = ring[q], b0 = ring[(q + 1) % n];
        const double ax = cos_turn * a0.x - sin_turn * a0.y, ay = sin_turn * a0.x + cos_turn * a0.y;
        const double bx = cos_turn * b0.x - sin_turn * b0.y, by = sin_turn * b0.x + cos_turn * b0.y;
        const double r1x = p.x - ax, r1y = p.y - ay, r2x = p.x - bx, r2y = p.y - by;
        const double r0x = bx - ax, r0y = by - ay;
        const double cross = r1x * r2y - r1y * r2x;
        const double length2 = r0x * r0x + r0y * r0y;
        const double l1 = std::sqrt(r1x * r1x + r1y * r1y), l2 = std::sqrt(r2x * r2x + r2y * r2y);
        if (std::abs(cross) <= 1e-12 * length2 || l1 == 0.0 || l2 == 0.0) continue;
        w += (r0x * (r1x / l1 - r2x / l2) + r0y * (r1y / l1 - r2y / l2)) / (4.0 * constants::pi * cross);
    }
    return w;
}

std::vector<SectorElement> single_elements(const std::vector<SectorCell>& cells) {
    std::vector<SectorElement> out(cells.size());
    for (std::size_t c = 0; c < cells.size(); ++c) out[c] = {{c}, cells[c].centroid, cells[c].area, cells[c].node};
    return out;
}

std::vector<SectorElement> grouped_elements(const std::vector<SectorCell>& cells, int nodes) {
    std::vector<SectorElement> out;
    std::vector<long> key_of;   // (I, J, node) packed, per element
    for (std::size_t c = 0; c < cells.size(); ++c) {
        const int big_row = cells[c].row / 2;
        const int part = std::min(big_row, static_cast<int>(cells[c].v * (big_row + 1)));
        const long key = (static_cast<long>(big_row) * (big_row + 1) / 2 + part) * nodes + cells[c].node;
        std::size_t e = 0;
        while (e < key_of.size() && key_of[e] != key) ++e;
        if (e == key_of.size()) {
            key_of.push_back(key);
            out.push_back({{}, Point2{}, 0.0, cells[c].node});
        }
        SectorElement& el = out[e];
        el.cells.push_back(c);
        el.area += cells[c].area;
        el.centroid.x += cells[c].area * cells[c].centroid.x;
        el.centroid.y += cells[c].area * cells[c].centroid.y;
    }
    for (SectorElement& el : out) el.centroid = {el.centroid.x / el.area, el.centroid.y / el.area};
    return out;
}

std::vector<Eigen::MatrixXd> ring_velocities(const Canopy& canopy, const std::vector<SectorCell>& cells,
                                             const std::vector<SectorElement>& elements) {
    const int panels = canopy.panel_count(), n = static_cast<int>(elements.size());
    std::vector<Eigen::MatrixXd> g(static_cast<std::size_t>(panels), Eigen::MatrixXd(n, n));
    for (int d = 0; d < panels; ++d) {
        const double turn = canopy.panel_azimuth(d) - canopy.panel_azimuth(0);
        const double ct = std::cos(turn), st = std::sin(turn);
        for (int kk = 0; kk < n; ++kk)
            for (int i = 0; i < n; ++i) {
                double w = 0.0;
                for (const std::size_t c : elements[static_cast<std::size_t>(kk)].cells)
                    w += ring_velocity(elements[static_cast<std::size_t>(i)].centroid, cells[c].corners, ct, st);
                g[static_cast<std::size_t>(d)](i, kk) = w;
            }
    }
    return g;
}

}  // namespace ameoto::air_sectors
