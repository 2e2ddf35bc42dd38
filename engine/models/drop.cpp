// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/drop.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

#include "engine/core/body3d_drag.hpp"
#include "engine/core/connected_components.hpp"
#include "engine/core/physical_constants.hpp"
#include "engine/models/stretch_mode_table.hpp"
#include "engine/scene/terminal_speed.hpp"

namespace ameoto {
namespace {


// Orthonormal basis of the rigid motions of the shape (3 translations, up to 3 rotations): the null
// space of K for an unstressed lattice. Degenerate rotations (a pair rotating about its own axis) drop out.
std::vector<Eigen::VectorXd> rigid_basis(const LatticeBallShape& shape) {
    const int n = 3 * shape.mass_count();
    std::vector<Eigen::VectorXd> basis;
    for (int motion = 0; motion < 6; ++motion) {
        Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
        for (int i = 0; i < shape.mass_count(); ++i) {
            const Vec3 p = shape.position[static_cast<std::size_t>(i)];
            Vec3 d{};
            switch (motion) {
                case 0: d = {1, 0, 0}; break;
                case 1: d = {0, 1, 0}; break;
                case 2: d = {0, 0, 1}; break;
                case 3: d = {0, -p.z, p.y}; break;   // omega x p, omega = e_x
                case 4: d = {p.z, 0, -p.x}; break;
                default: d = {-p.y, p.x, 0}; break;
            }
            v.segment<3>(3 * i) << d.x, d.y, d.z;
        }
        const double scale = v.norm();
        for (const auto& b : basis) v -= b.dot(v) * b;
        if (v.norm() > 1e-9 * scale) basis.push_back(v.normalized());
    }
    return basis;
}

void project_out(Eigen::VectorXd& v, const std::vector<Eigen::VectorXd>& basis) {
    for (const auto& b : basis) v -= b.dot(v) * b;
}

}  // namespace

StretchMode stretch_mode(const LatticeBallShape& shape) {
    const int masses = shape.mass_count();
    if (masses < 2 || shape.link_count() == 0) return {};
    const int n = 3 * masses;

    // K for k = 1: each link adds u u^T to the diagonal blocks of its ends and -u u^T between them.
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<std::size_t>(shape.link_count()) * 36 + static_cast<std::size_t>(n));
    for (int l = 0; l < shape.link_count(); ++l) {
        const int a = shape.link_a[static_cast<std::size_t>(l)], b = shape.link_b[static_cast<std::size_t>(l)];
        const Vec3 d = shape.position[static_cast<std::size_t>(a)] - shape.position[static_cast<std::size_t>(b)];
        const Vec3 u = d / norm(d);
        const double uu[3] = {u.x, u.y, u.z};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const double v = uu[i] * uu[j];
                entries.emplace_back(3 * a + i, 3 * a + j, v);
                entries.emplace_back(3 * b + i, 3 * b + j, v);
                entries.emplace_back(3 * a + i, 3 * b + j, -v);
                entries.emplace_back(3 * b + i, 3 * a + j, -v);
            }
    }
    // Shift-invert about s: the lowest modes of K become the largest of (K + s I)^-1. K's diagonal is
    // about 4 (12 neighbours, sum of u u^T = 4 I), its n = 2 eigenvalues 0.08..1.5.
    constexpr double shift = 1e-2;
    for (int i = 0; i < n; ++i) entries.emplace_back(i, i, shift);
    Eigen::SparseMatrix<double> a_matrix(n, n);
    a_matrix.setFromTriplets(entries.begin(), entries.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(a_matrix);
    if (solver.info() != Eigen::Success) throw std::runtime_error("drop lattice: factorisation failed");

    const auto rigid = rigid_basis(shape);
    // Start: the n = 2 stretch along z, volume preserving to first order.
    Eigen::VectorXd q(n);
    for (int i = 0; i < masses; ++i) {
        const Vec3 p = shape.position[static_cast<std::size_t>(i)];
        q.segment<3>(3 * i) << -0.5 * p.x, -0.5 * p.y, p.z;
    }
    project_out(q, rigid);
    if (!(q.norm() > 0.0)) return {};
    q.normalize();

    // Lanczos with full reorthogonalisation (twice: Kahan's "twice is enough"). 30 steps: at 122-512
    // masses lambda_2 and its weight agree with 200 steps to 9 and 3 digits (the stretch's mode is the
    // dominant one at the low end, which shift-invert converges first); the factorisation dominates.
    const int steps = std::min(n - static_cast<int>(rigid.size()), 30);
    Eigen::MatrixXd basis(n, steps);
    std::vector<double> alpha, beta;
    basis.col(0) = q;
    int m = 0;
    for (; m < steps; ++m) {
        Eigen::VectorXd w = solver.solve(Eigen::VectorXd(basis.col(m)));
        project_out(w, rigid);
        alpha.push_back(basis.col(m).dot(w));
        for (int pass = 0; pass < 2; ++pass) w -= basis.leftCols(m + 1) * (basis.leftCols(m + 1).transpose() * w);
        const double b = w.norm();
        if (m + 1 == steps || b < 1e-10 * std::abs(alpha.back())) {
            ++m;
            break;
        }
        beta.push_back(b);
        basis.col(m + 1) = w / b;
    }
    Eigen::VectorXd diag(m), sub(std::max(m - 1, 0));
    for (int i = 0; i < m; ++i) diag(i) = alpha[static_cast<std::size_t>(i)];
    for (int i = 0; i + 1 < m; ++i) sub(i) = beta[static_cast<std::size_t>(i)];
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz;
    ritz.computeFromTridiagonal(diag, sub, Eigen::ComputeEigenvectors);

    // The Ritz value carrying the largest share of the start vector is the stretch's mode.
    StretchMode best;
    for (int i = 0; i < m; ++i) {
        const double theta = ritz.eigenvalues()(i);
        if (!(theta > 0.0)) continue;
        const double lambda = 1.0 / theta - shift;
        const double weight = ritz.eigenvectors()(0, i) * ritz.eigenvectors()(0, i);
        if (lambda > 1e-9 && weight > best.weight) best = {lambda, weight};
    }
    return best;
}

std::optional<StretchMode> tabulated_stretch_mode(const LatticeBallShape& shape) {
    for (const TabulatedStretchMode& t : tabulated_stretch_modes())
        if (t.centre_kind == shape.centre_kind && t.last_shell_key == shape.last_shell_key)
            return t.masses == shape.mass_count() && t.links == shape.link_count()
                       ? std::optional<StretchMode>(StretchMode{t.lambda, t.weight})
                       : std::nullopt;
    return std::nullopt;
}

namespace {

struct LatticeCache {
    std::mutex mutex;
    std::map<int, std::shared_ptr<const DropLattice>> by_target;
    std::map<std::pair<int, long long>, std::shared_ptr<const DropLattice>> by_shape;
};

LatticeCache& cache() {
    static LatticeCache instance;
    return instance;
}

// The lattice of a choice: from the cache by shape, or built and analysed (outside the lock; if
// another thread built the same one meanwhile, the first stored wins).
std::shared_ptr<const DropLattice> lattice_for(int target, const LatticeBallChoice& choice) {
    LatticeCache& c = cache();
    const std::pair<int, long long> key{choice.centre_kind, choice.last_key};
    {
        std::lock_guard lock(c.mutex);
        if (auto it = c.by_target.find(target); it != c.by_target.end()) return it->second;
        if (auto it = c.by_shape.find(key); it != c.by_shape.end()) return c.by_target.emplace(target, it->second).first->second;
    }
    auto built = std::make_shared<DropLattice>();
    built->shape = lattice_ball_shape(choice);
    const std::optional<StretchMode> tabulated = tabulated_stretch_mode(built->shape);
    const StretchMode mode = tabulated ? *tabulated : stretch_mode(built->shape);
    built->lambda2 = mode.lambda;
    built->weight2 = mode.weight;
    std::lock_guard lock(c.mutex);
    const auto shape_it = c.by_shape.emplace(key, std::move(built)).first;
    return c.by_target.emplace(target, shape_it->second).first->second;
}

}  // namespace

std::shared_ptr<const DropLattice> drop_lattice(int target_masses) {
    const int target = std::max(1, target_masses);
    {
        LatticeCache& c = cache();
        std::lock_guard lock(c.mutex);
        if (auto it = c.by_target.find(target); it != c.by_target.end()) return it->second;
    }
    return lattice_for(target, lattice_ball_choices(target).back());
}

std::vector<std::shared_ptr<const DropLattice>> drop_lattices(int max_target) {
    {
        // Every target already cached (each pool of a scene build asks for the same ones): no enumeration.
        LatticeCache& c = cache();
        std::lock_guard lock(c.mutex);
        std::vector<std::shared_ptr<const DropLattice>> cached;
        cached.reserve(static_cast<std::size_t>(std::max(max_target, 1)));
        for (int t = 1; t <= std::max(max_target, 1); ++t) {
            const auto it = c.by_target.find(t);
            if (it == c.by_target.end()) break;
            cached.push_back(it->second);
        }
        if (cached.size() == static_cast<std::size_t>(std::max(max_target, 1))) return cached;
    }
    const auto choices = lattice_ball_choices(max_target);
    std::vector<std::shared_ptr<const DropLattice>> lattices;
    lattices.reserve(choices.size());
    for (std::size_t i = 0; i < choices.size(); ++i) lattices.push_back(lattice_for(static_cast<int>(i) + 1, choices[i]));
    return lattices;
}

double rayleigh_frequency(double diameter, const Liquid& liquid, int n) {
    const double a = 0.5 * diameter;
    const double omega2 = n * (n - 1.0) * (n + 2.0) * liquid.surface_tension / (liquid.density * a * a * a);
    return std::sqrt(omega2) / (2.0 * constants::pi);
}

double lamb_decay_time(double diameter, const Liquid& liquid, int n) {
    const double a = 0.5 * diameter;
    return a * a / ((n - 1.0) * (2.0 * n + 1.0) * liquid.kinematic_viscosity());
}

double arrival_speed(double diameter, double density) {
    return terminal_speed(diameter) * std::sqrt(density / constants::water_density);
}

Vec3 drop_orientation(Vec3 p, bool tilted) {
    if (!tilted) return p;
    // An orthonormal frame (e1, e2, n), n = (1, g, g^2) / |.|: the point's coordinates in it.
    constexpr double g = 1.6180339887498949;
    const double inv = 1.0 / std::sqrt(1.0 + g * g + g * g * g * g);
    const Vec3 n{inv, g * inv, g * g * inv};
    const double inv1 = 1.0 / std::sqrt(n.x * n.x + n.y * n.y);
    const Vec3 e1{n.y * inv1, -n.x * inv1, 0.0};
    const Vec3 e2{n.y * e1.z - n.z * e1.y, n.z * e1.x - n.x * e1.z, n.x * e1.y - n.y * e1.x};
    return Vec3{dot(e1, p), dot(e2, p), dot(n, p)};
}

DropCalibration calibrate_drop(const DropLattice& lattice, double diameter, const Liquid& liquid,
                               const DropOptions& options) {
    DropCalibration c;
    c.tilted = options.tilted;
    c.diameter = diameter;
    c.density = liquid.density;
    c.surface_tension = liquid.surface_tension;
    c.viscosity = liquid.viscosity;
    c.masses = lattice.mass_count();
    c.total_mass = liquid.density * constants::pi * diameter * diameter * diameter / 6.0;
    c.node_mass = c.total_mass / c.masses;
    c.spacing = diameter * lattice.shape.spacing;
    c.rayleigh_hz = rayleigh_frequency(diameter, liquid);
    c.lambda2 = lattice.lambda2;
    c.decay_time = lamb_decay_time(diameter, liquid);
    c.arrival_speed = arrival_speed(diameter, liquid.density);
    if (c.masses < 2 || !(lattice.lambda2 > 0.0)) return c;   // one mass: no links
    const double omega2 = 2.0 * constants::pi * c.rayleigh_hz;
    c.stiffness = c.node_mass * omega2 * omega2 / lattice.lambda2;
    c.damping = 2.0 * c.stiffness / (c.decay_time * omega2 * omega2);
    c.break_force = 0.5 * constants::pi * liquid.surface_tension * c.spacing;
    if (options.core) {
        c.core_length = options.core_length * c.spacing;
        const double omega_core = options.core_speed / c.spacing;
        c.core_stiffness = c.node_mass * omega_core * omega_core;
    }
    return c;
}

DropCalibration calibrate_drop(double diameter, const Liquid& liquid, const DropOptions& options) {
    if (!(diameter > 0.0) || !std::isfinite(diameter)) throw std::invalid_argument("drop diameter must be positive");
    if (std::string why = validate(liquid); !why.empty()) throw std::invalid_argument(why);
    return calibrate_drop(*drop_lattice(seed_mass_count(diameter)), diameter, liquid, options);
}

DropInfo add_drop(Body3D& body, const DropLattice& lattice, const DropCalibration& c, Vec3 centre, Vec3 velocity,
                  DragPreset drag) {
    DropInfo info;
    info.first_mass = body.mass_count();
    info.first_link = body.link_count();
    info.mass_count = lattice.mass_count();
    const double quadratic = drag == DragPreset::quadratic ? drag::drop_quadratic_drag(c.diameter) / info.mass_count : 0.0;
    const double linear = drag == DragPreset::seed_linear ? drag::seed_linear_drag : 0.0;
    for (const Vec3& p : lattice.shape.position) {
        const int m = body.add_mass(c.node_mass, centre + c.diameter * drop_orientation(p, c.tilted));
        body.set_velocity(m, velocity);
        body.set_quadratic_drag(m, quadratic);
        body.set_linear_drag(m, linear);
    }
    for (int l = 0; l < lattice.shape.link_count(); ++l)
        body.add_cohesive(info.first_mass + lattice.shape.link_a[static_cast<std::size_t>(l)],
                          info.first_mass + lattice.shape.link_b[static_cast<std::size_t>(l)], c.stiffness, c.damping,
                          c.spacing, c.break_force, c.core_length, c.core_stiffness);
    info.link_count = body.link_count() - info.first_link;
    return info;
}

void set_piece_drag(Body3D& body, const DropInfo& info, const DropCalibration& c, const ConnectedComponents& components,
                    DragPreset drag) {
    if (drag != DragPreset::quadratic || components.count() == 0) return;
    const double n_total = static_cast<double>(info.mass_count);
    for (int i = 0; i < info.mass_count; ++i) {
        const int m = info.first_mass + i;
        const int n = components.size_of(components.component_of(m));
        const double d_piece = c.diameter * std::cbrt(n / n_total);
        body.set_quadratic_drag(m, drag::drop_quadratic_drag(d_piece) / n);
    }
}

Drop make_drop(double diameter, const Liquid& liquid, Vec3 centre, std::optional<Vec3> velocity, DragPreset drag,
               const DropOptions& options) {
    Drop drop;
    if (!(diameter > 0.0) || !std::isfinite(diameter)) throw std::invalid_argument("drop diameter must be positive");
    if (std::string why = validate(liquid); !why.empty()) throw std::invalid_argument(why);
    drop.lattice = drop_lattice(seed_mass_count(diameter));
    drop.calibration = calibrate_drop(*drop.lattice, diameter, liquid, options);
    const Vec3 v = velocity.value_or(Vec3{0.0, 0.0, -drop.calibration.arrival_speed});
    drop.info = add_drop(drop.body, *drop.lattice, drop.calibration, centre, v, drag);
    drop.body.set_gravity(Vec3{0.0, 0.0, -constants::gravity});
    drop.body.set_integrator(Integrator::symplectic_euler);
    return drop;
}

}  // namespace ameoto
