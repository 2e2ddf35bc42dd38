// SPDX-License-Identifier: GPL-3.0-or-later
// The FDTD reference solver of air around a thin screen: see air_solver.hpp and docs/air-reference.md.
#include "engine/reference/air_solver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "engine/core/physical_constants.hpp"

namespace ameoto::reference {

namespace {

int cells_for(double length, double dx) { return std::max(0, static_cast<int>(std::ceil(length / dx - 1e-9))); }

}  // namespace

GridSpec GridSpec::box(double dx, double half_x, double half_y, double z_below, double z_above, int pml_cells,
                       bool layer_below) {
    GridSpec g;
    g.dx = dx;
    g.pml_cells = pml_cells;
    g.nx = 2 * (cells_for(half_x, dx) + pml_cells);
    g.ny = 2 * (cells_for(half_y, dx) + pml_cells);
    g.pml_low[2] = layer_below;
    const int below = std::max(1, cells_for(z_below, dx)) + (layer_below ? pml_cells : 0);
    const int above = std::max(1, cells_for(z_above, dx)) + pml_cells;
    g.screen_k = below;
    g.nz = below + above;
    return g;
}

double GridSpec::time_step() const {
    const double c = sound_speed > 0.0 ? sound_speed : constants::speed_of_sound_air;
    return courant * dx / c;
}

int ScreenStructure::add_dof(double mass_kg, bool is_prescribed) {
    mass.push_back(mass_kg);
    prescribed.push_back(is_prescribed ? 1 : 0);
    return size() - 1;
}

// ---- the structure ----

StructureStepper::StructureStepper(const ScreenStructure& s, double time_step_s)
    : mass_(s.mass), inverse_mass_(s.mass.size()), x_(s.mass.size(), 0.0), velocity_(s.mass.size(), 0.0),
      mean_velocity_(s.mass.size(), 0.0), spring_force_(s.mass.size(), 0.0), x_start_(s.mass.size(), 0.0),
      prescribed_(s.prescribed), springs_(s.springs), alpha_(s.mass_damping), beta_(s.stiffness_damping),
      dt_(time_step_s) {
    const std::size_t n = mass_.size();
    prescribed_.resize(n, 0);
    std::vector<double> gershgorin(n, 0.0);
    for (const Spring& sp : springs_) {
        if (sp.a < 0 || sp.a >= static_cast<int>(n) || sp.b < -1 || sp.b >= static_cast<int>(n) || sp.a == sp.b ||
            !(sp.stiffness >= 0.0))
            throw std::invalid_argument("ScreenStructure: a spring joins DOFs that do not exist");
        const double w = sp.b < 0 ? 1.0 : 2.0;   // diagonal + off-diagonal of K's row
        gershgorin[static_cast<std::size_t>(sp.a)] += w * sp.stiffness;
        if (sp.b >= 0) gershgorin[static_cast<std::size_t>(sp.b)] += w * sp.stiffness;
    }
    double omega2 = 0.0;
    for (std::size_t d = 0; d < n; ++d) {
        if (!(mass_[d] > 0.0)) throw std::invalid_argument("ScreenStructure: every DOF needs a positive mass");
        inverse_mass_[d] = 1.0 / mass_[d];
        if (!prescribed_[d]) omega2 = std::max(omega2, gershgorin[d] * inverse_mass_[d]);
    }
    // Symplectic Euler is stable for omega dt < 2; 1.9 leaves room for the damping and the air.
    const double omega_dt = std::sqrt(omega2) * dt_ * (1.0 + beta_ * std::sqrt(omega2));
    sub_steps_ = std::max(1, static_cast<int>(std::ceil(omega_dt / 1.9)));
    if (!s.initial_displacement.empty()) {
        if (s.initial_displacement.size() != n)
            throw std::invalid_argument("ScreenStructure: initial_displacement needs one value per DOF");
        x_ = s.initial_displacement;
    }
}

void StructureStepper::step(const double* force) {
    const std::size_t n = mass_.size();
    const double h = dt_ / sub_steps_;
    x_start_ = x_;
    for (int s = 0; s < sub_steps_; ++s) {
        std::fill(spring_force_.begin(), spring_force_.end(), 0.0);
        for (const Spring& sp : springs_) {
            const std::size_t a = static_cast<std::size_t>(sp.a);
            const double xb = sp.b < 0 ? 0.0 : x_[static_cast<std::size_t>(sp.b)];
            const double vb = sp.b < 0 ? 0.0 : velocity_[static_cast<std::size_t>(sp.b)];
            const double f = sp.stiffness * ((xb - x_[a]) + beta_ * (vb - velocity_[a]));
            spring_force_[a] += f;
            if (sp.b >= 0) spring_force_[static_cast<std::size_t>(sp.b)] -= f;
        }
        for (std::size_t d = 0; d < n; ++d) {
            if (!prescribed_[d])
                velocity_[d] += h * inverse_mass_[d] * (force[d] + spring_force_[d] - alpha_ * mass_[d] * velocity_[d]);
            x_[d] += h * velocity_[d];
        }
    }
    for (std::size_t d = 0; d < n; ++d) mean_velocity_[d] = (x_[d] - x_start_[d]) / dt_;
}

// ---- the air ----

AirSolver::AirSolver(const GridSpec& grid, const ScreenStructure& structure)
    : grid_(grid),
      dt_(grid.time_step()),
      rho_(grid.density > 0.0 ? grid.density : constants::air_density),
      c_(grid.sound_speed > 0.0 ? grid.sound_speed : constants::speed_of_sound_air),
      structure_(structure, grid.time_step()),
      external_(static_cast<std::size_t>(structure.size()), 0.0),
      air_force_(static_cast<std::size_t>(structure.size()), 0.0),
      total_force_(static_cast<std::size_t>(structure.size()), 0.0) {
    const GridSpec& g = grid_;
    if (g.nx < 4 || g.ny < 4 || g.nz < 2 || g.nx % 2 || g.ny % 2)
        throw std::invalid_argument("AirSolver: the grid needs nx, ny even and at least 4, nz at least 2");
    if (!(g.dx > 0.0) || !(g.courant > 0.0) || g.courant >= 1.0 / std::sqrt(3.0))
        throw std::invalid_argument("AirSolver: dx must be positive and the Courant number in (0, 1/sqrt 3)");
    const std::array<int, 3> n{g.nx, g.ny, g.nz};
    for (int a = 0; a < 3; ++a)
        if ((g.pml_low[a] ? g.pml_cells : 0) + (g.pml_high[a] ? g.pml_cells : 0) >= n[a])
            throw std::invalid_argument("AirSolver: the absorbing layers fill the box");
    if (g.screen_k != -1 && (g.screen_k < 1 || g.screen_k >= g.nz))
        throw std::invalid_argument("AirSolver: screen_k must be in 1 .. nz-1 (or -1)");

    const std::size_t cells = static_cast<std::size_t>(g.nx) * g.ny * g.nz;
    const std::size_t plane = static_cast<std::size_t>(g.nx) * g.ny;
    p_.assign(cells, 0.0f);
    px_.assign(cells, 0.0f);
    py_.assign(cells, 0.0f);
    pz_.assign(cells, 0.0f);
    vx_.assign(cells + plane, 0.0f);
    vy_.assign(cells + plane, 0.0f);
    vz_.assign(cells + plane, 0.0f);

    // Berenger's layer: sigma = sigma_max d^2 (d: depth into the layer, 0..1), sigma_max from the design
    // reflection R0 = exp(-2 sigma_max L / (3 c)) of a quadratic profile at normal incidence.
    const double L = g.pml_cells * g.dx;
    const double sigma_max = g.pml_cells > 0 ? 3.0 * c_ * std::log(1.0 / g.pml_reflection) / (2.0 * L) : 0.0;
    const double K = rho_ * c_ * c_;
    for (int a = 0; a < 3; ++a) {
        const int na = n[a];
        const int lo = g.pml_low[a] ? g.pml_cells : 0;
        const int hi = na - (g.pml_high[a] ? g.pml_cells : 0);
        auto depth = [&](double pos) {   // pos in cells from the low wall
            if (pos < lo) return (lo - pos) / g.pml_cells;
            if (pos > hi) return (pos - hi) / g.pml_cells;
            return 0.0;
        };
        cell_a_[a].resize(static_cast<std::size_t>(na));
        cell_b_[a].resize(static_cast<std::size_t>(na));
        face_a_[a].resize(static_cast<std::size_t>(na));
        face_b_[a].resize(static_cast<std::size_t>(na));
        absorbing_[a].resize(static_cast<std::size_t>(na));
        auto coefficients = [&](double pos, float& A, float& B, double scale) {
            const double d = depth(pos);
            const double sigma = sigma_max * d * d;
            const double e = std::exp(-sigma * dt_);
            A = static_cast<float>(e);
            B = static_cast<float>((sigma > 0.0 ? (1.0 - e) / sigma : dt_) * scale);
        };
        for (int i = 0; i < na; ++i) {
            const auto u = static_cast<std::size_t>(i);
            coefficients(i + 0.5, cell_a_[a][u], cell_b_[a][u], K / g.dx);
            coefficients(i, face_a_[a][u], face_b_[a][u], 1.0 / (rho_ * g.dx));
            absorbing_[a][u] = (i < lo || i >= hi) ? 1 : 0;
        }
        if (a == 0) {
            inner_lo_ = lo;
            inner_hi_ = hi;
        }
    }
    owner_.assign(plane, air);
    if (g.screen_k != -1 && g.pml_cells > 0) {
        // The screen must lie outside the z layers (its faces take the plain update).
        if (absorbing_[2][static_cast<std::size_t>(g.screen_k)] || absorbing_[2][static_cast<std::size_t>(g.screen_k - 1)])
            throw std::invalid_argument("AirSolver: the screen plane lies in an absorbing layer");
    }
}

void AirSolver::set_face(int i, int j, int owner) {
    if (grid_.screen_k < 0) throw std::invalid_argument("AirSolver::set_face: the grid has no screen");
    if (i < 0 || i >= grid_.nx || j < 0 || j >= grid_.ny)
        throw std::invalid_argument("AirSolver::set_face: face outside the grid");
    if (owner < rigid || owner >= structure_.size())
        throw std::invalid_argument("AirSolver::set_face: owner is neither air, rigid nor a DOF");
    owner_[static_cast<std::size_t>(j * grid_.nx + i)] = owner;
    faces_dirty_ = true;
}

int AirSolver::faces_of(int dof) const {
    return static_cast<int>(std::count(owner_.begin(), owner_.end(), dof));
}

void AirSolver::couple_screen() {
    if (faces_dirty_) {   // the first step after set_face: group the faces by owner (allocates once)
        const int dofs = structure_.size();
        owned_start_.assign(static_cast<std::size_t>(dofs) + 1, 0);
        rigid_faces_.clear();
        for (std::size_t f = 0; f < owner_.size(); ++f) {
            if (owner_[f] >= 0) ++owned_start_[static_cast<std::size_t>(owner_[f]) + 1];
            if (owner_[f] == rigid) rigid_faces_.push_back(static_cast<int>(f));
        }
        for (int d = 0; d < dofs; ++d) owned_start_[static_cast<std::size_t>(d) + 1] += owned_start_[static_cast<std::size_t>(d)];
        owned_faces_.assign(static_cast<std::size_t>(owned_start_.back()), 0);
        std::vector<int> fill(owned_start_.begin(), owned_start_.end() - 1);
        for (std::size_t f = 0; f < owner_.size(); ++f)
            if (owner_[f] >= 0) owned_faces_[static_cast<std::size_t>(fill[static_cast<std::size_t>(owner_[f])]++)] = static_cast<int>(f);
        faces_dirty_ = false;
    }
}

void AirSolver::step() {
    const GridSpec& g = grid_;
    const std::size_t plane = static_cast<std::size_t>(g.nx) * g.ny;
    const int dofs = structure_.size();
    if (g.screen_k >= 0) couple_screen();
    // 1. The structure over t_n .. t_n+1, driven by the air's pressure at t_n.
    if (dofs > 0) {
        const double area = g.dx * g.dx;
        const float* above = p_.data() + static_cast<std::size_t>(g.screen_k) * plane;
        const float* below = above - plane;
        for (int d = 0; d < dofs; ++d) {
            double f = 0.0;
            if (air_loading_)
                for (int q = owned_start_[static_cast<std::size_t>(d)]; q < owned_start_[static_cast<std::size_t>(d) + 1]; ++q) {
                    const auto face = static_cast<std::size_t>(owned_faces_[static_cast<std::size_t>(q)]);
                    f -= (static_cast<double>(above[face]) - static_cast<double>(below[face])) * area;
                }
            air_force_[static_cast<std::size_t>(d)] = f;
            total_force_[static_cast<std::size_t>(d)] = f + external_[static_cast<std::size_t>(d)];
        }
        structure_.step(total_force_.data());
    }
    // 2. The air's velocity at t_n+1/2, then the screen's faces.
    update_velocity();
    if (g.screen_k >= 0) {
        float* vz = vz_.data() + static_cast<std::size_t>(g.screen_k) * plane;
        for (int f : rigid_faces_) vz[static_cast<std::size_t>(f)] = 0.0f;
        for (int d = 0; d < dofs; ++d) {
            const float v = air_loading_ ? static_cast<float>(structure_.velocity(d)) : 0.0f;
            for (int q = owned_start_[static_cast<std::size_t>(d)]; q < owned_start_[static_cast<std::size_t>(d) + 1]; ++q)
                vz[static_cast<std::size_t>(owned_faces_[static_cast<std::size_t>(q)])] = v;
        }
    }
    // 3. The pressure at t_n+1.
    update_pressure();
    ++steps_;
    for (Probe& q : probes_) q.samples.push_back(pressure_at(q.x, q.y, q.z));
    for (DofProbe& q : dof_probes_) {
        q.velocity.push_back(structure_.velocity(q.dof));
        q.force.push_back(air_force_[static_cast<std::size_t>(q.dof)]);
    }
}

int AirSolver::add_probe(double x, double y, double z) {
    probes_.push_back({x, y, z, {}});
    return static_cast<int>(probes_.size()) - 1;
}

int AirSolver::add_dof_probe(int dof) {
    if (dof < 0 || dof >= structure_.size()) throw std::invalid_argument("AirSolver::add_dof_probe: no such DOF");
    dof_probes_.push_back({dof, {}, {}});
    return static_cast<int>(dof_probes_.size()) - 1;
}

void AirSolver::reserve_probes(std::size_t steps) {
    for (Probe& q : probes_) q.samples.reserve(q.samples.size() + steps);
    for (DofProbe& q : dof_probes_) {
        q.velocity.reserve(q.velocity.size() + steps);
        q.force.reserve(q.force.size() + steps);
    }
}

void AirSolver::add_pressure(int i, int j, int k, double pa) {
    if (i < 0 || i >= grid_.nx || j < 0 || j >= grid_.ny || k < 0 || k >= grid_.nz ||
        absorbing_[0][static_cast<std::size_t>(i)] || absorbing_[1][static_cast<std::size_t>(j)] ||
        absorbing_[2][static_cast<std::size_t>(k)])
        throw std::invalid_argument("AirSolver::add_pressure: the cell is outside the box or in a layer");
    p_[index(i, j, k)] += static_cast<float>(pa);
}

void AirSolver::update_velocity() {
    const int nx = grid_.nx, ny = grid_.ny, nz = grid_.nz;
    const std::size_t row = static_cast<std::size_t>(nx), plane = row * static_cast<std::size_t>(ny);
    const float* __restrict p = p_.data();
    const float* __restrict fax = face_a_[0].data();
    const float* __restrict fbx = face_b_[0].data();
    for (int k = 0; k < nz; ++k) {
        const float az = face_a_[2][static_cast<std::size_t>(k)], bz = face_b_[2][static_cast<std::size_t>(k)];
        for (int j = 0; j < ny; ++j) {
            const float ay = face_a_[1][static_cast<std::size_t>(j)], by = face_b_[1][static_cast<std::size_t>(j)];
            const std::size_t base = static_cast<std::size_t>(k) * plane + static_cast<std::size_t>(j) * row;
            const float* __restrict pr = p + base;
            float* __restrict vx = vx_.data() + base;
            for (int i = 1; i < nx; ++i) vx[i] = fax[i] * vx[i] - fbx[i] * (pr[i] - pr[i - 1]);
            if (j > 0) {
                float* __restrict vy = vy_.data() + base;
                const float* __restrict ps = pr - row;
                for (int i = 0; i < nx; ++i) vy[i] = ay * vy[i] - by * (pr[i] - ps[i]);
            }
            if (k > 0) {
                float* __restrict vz = vz_.data() + base;
                const float* __restrict ps = pr - plane;
                for (int i = 0; i < nx; ++i) vz[i] = az * vz[i] - bz * (pr[i] - ps[i]);
            }
        }
    }
}

namespace {

// Split-field update over cells [i0, i1) of one row.
inline void split_row(int i0, int i1, std::size_t row, std::size_t plane, const float* __restrict vx,
                      const float* __restrict vy, const float* __restrict vz, float* __restrict px, float* __restrict py,
                      float* __restrict pz, float* __restrict p, const float* __restrict ax, const float* __restrict bx,
                      float ay, float by, float az, float bz) {
    for (int i = i0; i < i1; ++i) {
        px[i] = ax[i] * px[i] - bx[i] * (vx[i + 1] - vx[i]);
        py[i] = ay * py[i] - by * (vy[static_cast<std::size_t>(i) + row] - vy[i]);
        pz[i] = az * pz[i] - bz * (vz[static_cast<std::size_t>(i) + plane] - vz[i]);
        p[i] = px[i] + py[i] + pz[i];
    }
}

}  // namespace

void AirSolver::update_pressure() {
    const int nx = grid_.nx, ny = grid_.ny, nz = grid_.nz;
    const std::size_t row = static_cast<std::size_t>(nx), plane = row * static_cast<std::size_t>(ny);
    const float b0 = static_cast<float>(dt_ * rho_ * c_ * c_ / grid_.dx);
    const float* ax = cell_a_[0].data();
    const float* bx = cell_b_[0].data();
    for (int k = 0; k < nz; ++k) {
        const auto uk = static_cast<std::size_t>(k);
        const float az = cell_a_[2][uk], bz = cell_b_[2][uk];
        for (int j = 0; j < ny; ++j) {
            const auto uj = static_cast<std::size_t>(j);
            const float ay = cell_a_[1][uj], by = cell_b_[1][uj];
            const std::size_t base = uk * plane + uj * row;
            const float* __restrict vx = vx_.data() + base;
            const float* __restrict vy = vy_.data() + base;
            const float* __restrict vz = vz_.data() + base;
            float* __restrict p = p_.data() + base;
            float* px = px_.data() + base;
            float* py = py_.data() + base;
            float* pz = pz_.data() + base;
            if (absorbing_[1][uj] || absorbing_[2][uk]) {
                split_row(0, nx, row, plane, vx, vy, vz, px, py, pz, p, ax, bx, ay, by, az, bz);
                continue;
            }
            split_row(0, inner_lo_, row, plane, vx, vy, vz, px, py, pz, p, ax, bx, ay, by, az, bz);
            for (int i = inner_lo_; i < inner_hi_; ++i)
                p[i] -= b0 * ((vx[i + 1] - vx[i]) + (vy[static_cast<std::size_t>(i) + row] - vy[i]) +
                              (vz[static_cast<std::size_t>(i) + plane] - vz[i]));
            split_row(inner_hi_, nx, row, plane, vx, vy, vz, px, py, pz, p, ax, bx, ay, by, az, bz);
        }
    }
}

double AirSolver::pressure_at(double x, double y, double z) const {
    const GridSpec& g = grid_;
    auto locate = [](double pos, int n, int& i0, double& w) {
        pos = std::clamp(pos, 0.0, static_cast<double>(n - 1));
        i0 = std::min(static_cast<int>(std::floor(pos)), n - 2);
        w = pos - i0;
    };
    int i, j, k;
    double wx, wy, wz;
    locate(x / g.dx + g.nx / 2 - 0.5, g.nx, i, wx);
    locate(y / g.dx + g.ny / 2 - 0.5, g.ny, j, wy);
    locate(z / g.dx + (g.screen_k >= 0 ? g.screen_k : g.nz / 2) - 0.5, g.nz, k, wz);
    double sum = 0.0;
    for (int c = 0; c < 8; ++c) {
        const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
        const double w = (di ? wx : 1.0 - wx) * (dj ? wy : 1.0 - wy) * (dk ? wz : 1.0 - wz);
        if (w != 0.0) sum += w * p_[index(i + di, j + dj, k + dk)];
    }
    return sum;
}

double AirSolver::acoustic_energy() const {
    const GridSpec& g = grid_;
    double potential = 0.0, kinetic = 0.0;
    const int lo[3] = {g.pml_low[0] ? g.pml_cells : 0, g.pml_low[1] ? g.pml_cells : 0, g.pml_low[2] ? g.pml_cells : 0};
    const int hi[3] = {g.nx - (g.pml_high[0] ? g.pml_cells : 0), g.ny - (g.pml_high[1] ? g.pml_cells : 0),
                       g.nz - (g.pml_high[2] ? g.pml_cells : 0)};
    for (int k = lo[2]; k < hi[2]; ++k)
        for (int j = lo[1]; j < hi[1]; ++j)
            for (int i = lo[0]; i < hi[0]; ++i) {
                const std::size_t q = index(i, j, k);
                potential += static_cast<double>(p_[q]) * p_[q];
                kinetic += static_cast<double>(vx_[q]) * vx_[q] + static_cast<double>(vy_[q]) * vy_[q] +
                           static_cast<double>(vz_[q]) * vz_[q];
            }
    const double volume = g.dx * g.dx * g.dx;
    return volume * (potential / (2.0 * rho_ * c_ * c_) + 0.5 * rho_ * kinetic);
}

}  // namespace ameoto::reference
