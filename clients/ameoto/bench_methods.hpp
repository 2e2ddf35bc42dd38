// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The methods `ameoto bench engine` measures: one row each. Adding a method (a new integrator, a
// new storage) is one row in bench_methods() (bench_methods.cpp) and, for a new body type, one
// build function.
//
// Interface:
//   for (const BenchMethod& m : bench_methods()) {
//       if (!m.fits(mesh)) continue;                       // e.g. dense modal above its limit
//       std::unique_ptr<BenchBody> body = m.build(mesh);   // allocates; may throw (refused)
//       body->impulses(samples, clock);                    // the panel benchmark's loop
//       body->pluck(samples, drive, out);                  // the triangle mesh's loop (bench_drive.hpp)
//   }
//
// Rows: the TransverseNetwork (gather/scatter over a link list) with each of its integrators, and
// the GridMembrane stencil (engine/core/grid_membrane.hpp, explicit Verlet only) in float and double.

#include <memory>
#include <string>
#include <vector>

#include "clients/ameoto/bench_drive.hpp"
#include "clients/ameoto/bench_mesh.hpp"
#include "engine/core/integrators/integrator.hpp"

namespace ameoto::client {

class BenchBody {
public:
    virtual ~BenchBody() = default;
    virtual int sub_steps() const = 0;                        // per sample, as the body chose
    virtual double impulses(long samples, long& clock) = 0;   // returns a checksum
    virtual double pluck(long samples, PluckDrive& drive, double* out) = 0;   // out: null or samples
};

struct BenchMethod {
    std::string body;         // "network" or "grid"
    std::string integrator;   // "explicit Verlet", "trapezoidal", ...
    std::string precision;    // "double" or "float"
    int max_masses = 0;       // > 0: not run on larger bodies (and why, in limit_reason)
    std::string limit_reason;
    Integrator integrator_id = Integrator::explicit_verlet;
    std::unique_ptr<BenchBody> (*make)(const BenchMethod& method, const BenchMesh& mesh) = nullptr;

    std::string name() const;   // "network explicit Verlet", "grid explicit Verlet (float)"
    bool fits(const BenchMesh& mesh) const { return max_masses <= 0 || static_cast<int>(mesh.nodes.size()) <= max_masses; }
    std::unique_ptr<BenchBody> build(const BenchMesh& mesh) const { return make(*this, mesh); }
};

const std::vector<BenchMethod>& bench_methods();

}  // namespace ameoto::client
