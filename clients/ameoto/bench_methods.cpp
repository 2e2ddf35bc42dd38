// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_methods.hpp"

#include "engine/core/grid_membrane.hpp"
#include "engine/core/transverse_network.hpp"

namespace ameoto::client {
namespace {

// Runs the benchmark loops of bench_drive.hpp on one concrete body (built in place by make_*).
template <typename Body>
struct Adapter final : BenchBody {
    explicit Adapter(const BenchMesh& mesh) : excite(mesh.excite_node), listen(mesh.listen_node) {}
    int sub_steps() const override { return body.stability().sub_steps; }
    double impulses(long samples, long& clock) override { return drive_impulses(body, excite, samples, clock); }
    double pluck(long samples, PluckDrive& drive, double* out) override {
        return drive_pluck(body, drive, excite, listen, samples, out);
    }
    Body body;
    int excite, listen;
};

// The body build_membrane makes (models/membrane.cpp): mass m with a damper alpha m to the ground,
// springs k with dampers beta k, anchors likewise.
std::unique_ptr<BenchBody> make_network(const BenchMethod& method, const BenchMesh& mesh) {
    auto adapter = std::make_unique<Adapter<TransverseNetwork>>(mesh);
    TransverseNetwork& net = adapter->body;
    for (std::size_t n = 0; n < mesh.nodes.size(); ++n) net.add_mass(mesh.node_mass, mesh.alpha * mesh.node_mass);
    for (const auto& l : mesh.links) net.add_link(l.a, l.b, l.k, mesh.beta * l.k);
    for (const auto& a : mesh.anchors) net.add_anchor(a.a, a.k, mesh.beta * a.k);
    NetworkOptions options;
    options.integrator = method.integrator_id;
    options.guard.enabled = false;   // the benchmark measures the step alone
    net.finalize(mesh.time_step, options);
    return adapter;
}

template <typename Real>
std::unique_ptr<BenchBody> make_grid(const BenchMethod&, const BenchMesh& mesh) {
    auto adapter = std::make_unique<Adapter<BasicGridMembrane<Real>>>(mesh);
    adapter->body = BasicGridMembrane<Real>(GridMembraneBody{mesh.node_mass, mesh.alpha, mesh.beta});
    BasicGridMembrane<Real>& grid = adapter->body;
    for (const auto& node : mesh.nodes) grid.add_node(node.i, node.j);
    for (const auto& l : mesh.links) grid.add_link(l.a, l.b, l.k);
    for (const auto& a : mesh.anchors) grid.add_anchor(a.a, a.k);
    grid.finalize(mesh.time_step);
    return adapter;
}

BenchMethod network_row(Integrator integrator, int max_masses = 0, std::string reason = {}) {
    return BenchMethod{"network", integrator_name(integrator), "double", max_masses, std::move(reason), integrator, make_network};
}

}  // namespace

std::string BenchMethod::name() const {
    std::string n = body + " " + integrator;
    if (body == "grid") n += " (" + precision + ")";
    return n;
}

const std::vector<BenchMethod>& bench_methods() {
    static const std::vector<BenchMethod> methods = {
        network_row(Integrator::explicit_verlet),
        network_row(Integrator::symplectic_euler),
        network_row(Integrator::trapezoidal),
        network_row(Integrator::backward_euler),
        // Dense eigen-decomposition: O(n^3) time, O(n^2) memory (10 000 masses: 800 MB, hours).
        network_row(Integrator::modal, 2500, "dense modal decomposition, limited to 2500 masses"),
        {"grid", integrator_name(Integrator::explicit_verlet), "float", 0, {}, Integrator::explicit_verlet, make_grid<float>},
        {"grid", integrator_name(Integrator::explicit_verlet), "double", 0, {}, Integrator::explicit_verlet, make_grid<double>},
    };
    return methods;
}

}  // namespace ameoto::client
