// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The bodies `ameoto bench engine` measures, described once so that every method builds the same body.
//
// Interface:
//   BenchMesh panel = canopy_panel_mesh(1000);   // an umbrella panel of about 1000 masses at 48 kHz
//   BenchMesh mesh = mi_triangle_mesh();         // Faust's mi-faust triangleMesh.dsp, in sample units
//   mesh.nodes, mesh.links, mesh.anchors         // axial lattice coordinates, springs, fixed points
//   MiTriangle::faust_index(i, j)                // that point's place in the .dsp's list of masses
//
// A BenchMesh is a membrane with Rayleigh damping (models/membrane.hpp): every node has mass
// node_mass and a damper alpha m to the ground; every spring k (link or anchor) has a damper beta k.
// Nodes carry axial coordinates (engine/core/grid_membrane.hpp) so the grid can lay them out.
//
// The canopy panel: the default umbrella's panel (8 panels of 0.5 m, hem free, ribs fixed) in nylon
// (MembraneMaterial::nylon_canopy), spacing chosen for the mass count, as build_membrane makes it.
//
// The mi-faust triangle (faust-common's examples/physicalModeling/mi-faust/12_TriangleMesh, James
// Leonard 2020): points t_m<j>_<i> for rows j = 0..9 and i = 0..9-j (55 points), the corners (0,0),
// (9,0) and (0,9) fixed (mi.ground), the other 52 mi.oscil(m = 1, k = 0, z = Zo = 5e-5); 135
// mi.springDamper(K = 0.1, Z = 0.001) between every pair of neighbours: (i,j)-(i+1,j), (i,j)-(i,j+1)
// and (i+1,j)-(i,j+1). A spring to a fixed corner is an anchor here. mi.lib works in sample units
// (T = 1): its oscil is x[n+1] = (2 - Zo/m) x - (1 - Zo/m) x[n-1] + F/m and its springDamper
// F = -K dx - Z d(dx), the explicit CORDIS scheme with alpha = Zo / m and beta = Z / K. Excitation:
// mi.nlPluck(0.5, 0.03, 0.001) between the position input (the "Pluck Position" slider through
// si.smoo) and t_m4_3; output: 30 x(t_m5_1). See bench_drive.hpp.

#include <string>
#include <vector>

#include "clients/ameoto/bench_timer.hpp"   // bench_sample_rate

namespace ameoto::client {

struct BenchMesh {
    struct Node {
        int i = 0, j = 0;   // axial lattice coordinates
    };
    struct Spring {
        int a = 0, b = 0;   // b < 0: an anchor of a (a spring to a fixed point)
        double k = 0.0;     // N/m
    };
    std::string name;
    double node_mass = 1.0;       // kg
    double alpha = 0.0;           // 1/s: ground damper alpha m per node
    double beta = 0.0;            // s: damper beta k beside every spring
    double time_step = 1.0;       // s
    std::vector<Node> nodes;
    std::vector<Spring> links;    // between nodes
    std::vector<Spring> anchors;  // b = -1
    int excite_node = 0;          // where the benchmark's force (or pluck) acts
    int listen_node = 0;          // whose position is the output (triangle mesh)
};

BenchMesh canopy_panel_mesh(int target_masses);

struct MiTriangle {
    static constexpr int side = 10;                 // points per edge
    static constexpr double mass = 1.0, stiffness = 0.1, damping = 0.001, air_friction = 5e-5;
    static constexpr int pluck_i = 3, pluck_j = 4;  // t_m4_3
    static constexpr int listen_i = 1, listen_j = 5;  // t_m5_1
    static constexpr double output_gain = 30.0;
    static bool fixed(int i, int j);                // the three corners
    static int faust_index(int i, int j);           // m<k> in the .dsp's routing
};

BenchMesh mi_triangle_mesh();

}  // namespace ameoto::client
