// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Internal to the air's mass on the umbrella (air_loading.cpp, air_loading_helmholtz.cpp): one panel's
// triangle cut into nearly square sub-cells, each a uniform doublet (a vortex ring), and the coarser level
// of the same cells that Richardson's extrapolation pairs it with. Build phase only (allocates).
//
// Interface:
//   std::vector<SectorCell> c = sector_cells(canopy, rows);   // panel 0's sub-cells, rows from the shaft
//   single_elements(c), grouped_elements(c, nodes)            // the finer and the coarser level
//   ring_velocity(p, corners, cos, sin)                       // Biot-Savart at p of a unit ring, turned
//   ring_velocities(canopy, c, elements)                      // [d]: every element's at every other's

#include <cstddef>
#include <vector>

#include <Eigen/Dense>

#include "engine/core/triangular_lattice.hpp"

namespace ameoto {

class Canopy;

namespace air_sectors {

// A sub-cell of one panel's sampling: its polygon (counter-clockwise), centroid, area and node.
struct SectorCell {
    std::vector<Point2> corners;
    Point2 centroid;
    double area = 0.0;
    int node = -1;
    int row = 0;        // i below
    double v = 0.0;     // the cell's middle across the row, 0..1
};

// A unit of uniform doublet strength: one cell, or a group of cells (the coarse level, below) whose
// ring is the sum of its cells' rings (their shared edges cancel), collocated at its centroid.
struct SectorElement {
    std::vector<std::size_t> cells;
    Point2 centroid;
    double area = 0.0;
    int node = -1;
};

// Panel 0's triangle (the shaft O and the rib tips A, B) cut into rows parallel to the hem, row i
// (0..rows-1) between u = i / rows and (i + 1) / rows of the way from O to the hem, and row i into i + 1
// equal parts along the hem's direction: P(u, v) = u (A + v (B - A)). The cells are nearly square, all
// of one size (the apex's is a triangle); rows do not share corners (hanging corners are harmless:
// every cell is its own ring). Each cell belongs to the node Canopy::locate gives at its centroid.
std::vector<SectorCell> sector_cells(const Canopy& canopy, int rows);

// The Biot-Savart velocity of a unit ring at p (ring_segment_velocity summed, with sqrt for hypot: the
// sampling never meets its overflow range).
double ring_velocity(Point2 p, const std::vector<Point2>& ring, double cos_turn, double sin_turn);

// Every cell an element of its own (the finer level).
std::vector<SectorElement> single_elements(const std::vector<SectorCell>& cells);

// The coarser level of the same cells (rows even): the cells of rows 2I and 2I + 1 that fall in part J
// of I + 1 across the row (the sampling at rows / 2) and belong to one node form one element. Its
// nodes' regions are the finer level's exactly, so the two levels differ only in the doublets' size
// (sampling each level's regions afresh moves a node's share by up to a cell, not smoothly in h, which
// made the extrapolation indefinite).
std::vector<SectorElement> grouped_elements(const std::vector<SectorCell>& cells, int nodes);

// The Biot-Savart velocities of a level's unit rings (Laplace's kernel), one matrix per panel offset d:
// g_d(i, k), the velocity at panel 0's element i from panel d's element k (panel d is panel 0 turned by
// 2 pi d / N, its elements numbered alike).
std::vector<Eigen::MatrixXd> ring_velocities(const Canopy& canopy, const std::vector<SectorCell>& cells,
                                             const std::vector<SectorElement>& elements);

}  // namespace air_sectors
}  // namespace ameoto
