#include "engine/core/body3d.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ameoto {

double Body3DStability::margin() const {
    const double dt = time_step / sub_steps;
    return (omega_max_bound * omega_max_bound * dt * dt + 2.0 * gamma_max_bound * dt) / 4.0;
}

// ---------------------------------------------------------------------------------------------
// Build phase

int Body3D::add_mass(double mass_kg, Vec3 p) {
    if (!(mass_kg > 0.0) || !std::isfinite(mass_kg)) throw std::invalid_argument("mass must be positive and finite");
    if (!std::isfinite(p.x + p.y + p.z)) throw std::invalid_argument("mass position must be finite");
    for (auto* a : {&x_, &px_, &x0_}) a->push_back(p.x);
    for (auto* a : {&y_, &py_, &y0_}) a->push_back(p.y);
    for (auto* a : {&z_, &pz_, &z0_}) a->push_back(p.z);
    for (auto* a : {&vx_, &vy_, &vz_, &fx_, &fy_, &fz_, &ex_, &ey_, &ez_, &linear_drag_, &quadratic_drag_})
        a->push_back(0.0);
    mass_.push_back(mass_kg);
    inv_mass_.push_back(1.0 / mass_kg);
    fixed_.push_back(0);
    finalized_ = false;
    return mass_count() - 1;
}

int Body3D::add_fixed_point(Vec3 p) {
    const int m = add_mass(1.0, p);
    // Infinite mass: no force moves it, no gravity acts on it, and it carries no momentum.
    mass_.back() = 0.0;
    inv_mass_.back() = 0.0;
    fixed_.back() = 1;
    return m;
}

void Body3D::check_link_args(int a, int b) const {
    if (a == b || a < 0 || b < 0 || a >= mass_count() || b >= mass_count())
        throw std::invalid_argument("link must join two distinct existing masses");
}

int Body3D::add_link(int a, int b, LinkKind kind, double stiffness, double damping, double rest_length,
                     double break_force) {
    check_link_args(a, b);
    if (!(stiffness >= 0.0) || !(damping >= 0.0) || !(rest_length >= 0.0) || !std::isfinite(stiffness) ||
        !std::isfinite(damping) || !std::isfinite(rest_length))
        throw std::invalid_argument("link stiffness, damping and rest length must be finite and >= 0");
    if (!(break_force > 0.0)) throw std::invalid_argument("break force must be positive (no_break: never)");
    if (kind != LinkKind::breakable && kind != LinkKind::cohesive) break_force = no_break;
    link_a_.push_back(a);
    link_b_.push_back(b);
    kind_.push_back(kind);
    stiffness_.push_back(stiffness);
    damping_.push_back(damping);
    rest_.push_back(rest_length);
    break_force_.push_back(break_force);
    core_length_.push_back(0.0);
    core_stiffness_.push_back(0.0);
    broken_.push_back(0);
    finalized_ = false;
    return link_count() - 1;
}

int Body3D::add_cohesive(int a, int b, double k, double z, double rest_length, double break_force,
                         double core_length, double core_k) {
    if (!(core_length >= 0.0) || !(core_k >= 0.0) || !std::isfinite(core_length) || !std::isfinite(core_k))
        throw std::invalid_argument("core length and stiffness must be finite and >= 0");
    const int l = add_link(a, b, LinkKind::cohesive, k, z, rest_length, break_force);
    core_length_.back() = core_k > 0.0 ? core_length : 0.0;
    core_stiffness_.back() = core_k;
    return l;
}

void Body3D::reserve(int masses, int links) {
    if (masses < 0 || links < 0) throw std::invalid_argument("capacity must be >= 0");
    const auto m = idx(masses), l = idx(links);
    for (auto* a : {&x_, &y_, &z_, &px_, &py_, &pz_, &vx_, &vy_, &vz_, &fx_, &fy_, &fz_, &ex_, &ey_, &ez_, &x0_, &y0_,
                    &z0_, &mass_, &inv_mass_, &linear_drag_, &quadratic_drag_, &k_sum_, &z_sum_})
        a->reserve(m);
    fixed_.reserve(m);
    link_a_.reserve(l);
    link_b_.reserve(l);
    for (auto* a : {&stiffness_, &damping_, &rest_, &break_force_, &core_length_, &core_stiffness_}) a->reserve(l);
    kind_.reserve(l);
    broken_.reserve(l);
    events_.reserve(std::max<std::size_t>(l, 1));
}

void Body3D::clear() {
    for (auto* a : {&x_, &y_, &z_, &px_, &py_, &pz_, &vx_, &vy_, &vz_, &fx_, &fy_, &fz_, &ex_, &ey_, &ez_, &x0_, &y0_,
                    &z0_, &mass_, &inv_mass_, &linear_drag_, &quadratic_drag_})
        a->clear();
    fixed_.clear();
    link_a_.clear();
    link_b_.clear();
    for (auto* a : {&stiffness_, &damping_, &rest_, &break_force_, &core_length_, &core_stiffness_}) a->clear();
    kind_.clear();
    broken_.clear();
    event_count_ = 0;
    last_energy_ = 0.0;
    last_position_sum_ = 0.0;
    resets_ = 0;
    dropped_breaks_ = 0;
    sub_dt_ = 0.0;
    stability_ = Body3DStability{};
    finalized_ = false;
    uniform_cohesive_ = false;
}

void Body3D::set_linear_drag(int mass, double c) {
    if (!(c >= 0.0) || !std::isfinite(c)) throw std::invalid_argument("linear drag must be finite and >= 0");
    linear_drag_.at(idx(mass)) = c;
}

void Body3D::set_quadratic_drag(int mass, double b) {
    if (!(b >= 0.0) || !std::isfinite(b)) throw std::invalid_argument("quadratic drag must be finite and >= 0");
    quadratic_drag_.at(idx(mass)) = b;
}

const Body3DStability& Body3D::finalize(double time_step_s, int forced_sub_steps) {
    if (!(time_step_s > 0.0) || !std::isfinite(time_step_s)) throw std::invalid_argument("time step must be positive");
    // Finalized before and run with CORDIS: its velocities live in x - x[n-1]; read them at the old step.
    if (integrator_ == Integrator::explicit_verlet && sub_dt_ > 0.0) {
        for (int i = 0; i < mass_count(); ++i) {
            const Vec3 v = velocity(i);
            vx_[idx(i)] = v.x;
            vy_[idx(i)] = v.y;
            vz_[idx(i)] = v.z;
        }
    }
    // Gershgorin on M^-1 K and M^-1 C by 3x3 blocks (see the header): a link adds its k to the
    // diagonal block of each free end and k to the off-diagonal block between them, so 2k for a link
    // between free masses and k (diagonal only) for a link to a fixed point.
    // A cohesive link's core counts as if active (k + k_c). The scratch sums are members: within a
    // reserve()d capacity, assign() reuses their storage.
    const std::size_t n = x_.size();
    k_sum_.assign(n, 0.0);
    z_sum_.assign(n, 0.0);
    auto& k_sum = k_sum_;
    auto& z_sum = z_sum_;
    for (std::size_t l = 0; l < link_a_.size(); ++l) {
        const auto a = idx(link_a_[l]), b = idx(link_b_[l]);
        const double share = (fixed_[a] || fixed_[b]) ? 1.0 : 2.0;
        const double k = stiffness_[l] + core_stiffness_[l];
        k_sum[a] += share * k;
        k_sum[b] += share * k;
        z_sum[a] += share * damping_[l];
        z_sum[b] += share * damping_[l];
    }
    double omega2 = 0.0, gamma = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (fixed_[i]) continue;
        const double drag = linear_drag_[i] + 2.0 * quadratic_drag_[i] * speed_bound_;
        omega2 = std::max(omega2, k_sum[i] * inv_mass_[i]);
        gamma = std::max(gamma, (z_sum[i] + drag) * inv_mass_[i]);
    }
    stability_.omega_max_bound = std::sqrt(omega2);
    stability_.gamma_max_bound = gamma;
    stability_.time_step = time_step_s;
    if (forced_sub_steps > 0) {
        stability_.sub_steps = forced_sub_steps;
    } else {
        // Fewest sub-steps with margin < 0.9 (10 % head-room against rounding and the bound's slack).
        stability_.sub_steps = 1;
        while (stability_.margin() >= 0.9) {
            if (stability_.sub_steps >= 4096)
                throw std::invalid_argument("body too stiff: needs more than 4096 sub-steps per step");
            ++stability_.sub_steps;
        }
    }
    sub_dt_ = time_step_s / stability_.sub_steps;

    // The state reset() returns to; the previous positions carry any velocity already set.
    x0_ = x_;
    y0_ = y_;
    z0_ = z_;
    for (std::size_t i = 0; i < n; ++i) {
        px_[i] = x_[i] - sub_dt_ * vx_[i];
        py_[i] = y_[i] - sub_dt_ * vy_[i];
        pz_[i] = z_[i] - sub_dt_ * vz_[i];
    }
    std::size_t breakable = 0;
    for (auto k : kind_) breakable += (k == LinkKind::breakable || k == LinkKind::cohesive) ? 1 : 0;
    uniform_cohesive_ = !link_a_.empty();
    for (std::size_t l = 0; l < link_a_.size() && uniform_cohesive_; ++l)
        uniform_cohesive_ = kind_[l] == LinkKind::cohesive && stiffness_[l] == stiffness_[0] && damping_[l] == damping_[0] &&
                            rest_[l] == rest_[0] && break_force_[l] == break_force_[0] &&
                            core_length_[l] == core_length_[0] && core_stiffness_[l] == core_stiffness_[0];
    events_.assign(std::max<std::size_t>(breakable, 1), LinkBreak{});
    event_count_ = 0;
    finalized_ = true;
    return stability_;
}

// ---------------------------------------------------------------------------------------------
// Render phase

bool Body3D::set_integrator(Integrator integrator) {
    if (integrator != Integrator::explicit_verlet && integrator != Integrator::symplectic_euler) return false;
    if (integrator == integrator_) return true;
    // Symplectic Euler reads v as state; CORDIS left only its start-of-sub-step scratch there.
    if (integrator == Integrator::symplectic_euler && sub_dt_ > 0.0) {
        const double inv_dt = 1.0 / sub_dt_;
        for (std::size_t i = 0; i < x_.size(); ++i) {
            vx_[i] = (x_[i] - px_[i]) * inv_dt;
            vy_[i] = (y_[i] - py_[i]) * inv_dt;
            vz_[i] = (z_[i] - pz_[i]) * inv_dt;
        }
    }
    // Symplectic Euler keeps x[n-1] up to date, so the switch to CORDIS needs nothing.
    integrator_ = integrator;
    return true;
}

void Body3D::apply_force(int mass, Vec3 f) {
    const auto i = idx(mass);
    ex_[i] += f.x;
    ey_[i] += f.y;
    ez_[i] += f.z;
}

void Body3D::set_position(int mass, Vec3 p) {
    const auto i = idx(mass);
    const Vec3 v = velocity(mass);
    x_[i] = p.x;
    y_[i] = p.y;
    z_[i] = p.z;
    px_[i] = p.x - sub_dt_ * v.x;
    py_[i] = p.y - sub_dt_ * v.y;
    pz_[i] = p.z - sub_dt_ * v.z;
}

void Body3D::set_velocity(int mass, Vec3 v) {
    const auto i = idx(mass);
    if (fixed_[i]) return;
    vx_[i] = v.x;
    vy_[i] = v.y;
    vz_[i] = v.z;
    px_[i] = x_[i] - sub_dt_ * v.x;
    py_[i] = y_[i] - sub_dt_ * v.y;
    pz_[i] = z_[i] - sub_dt_ * v.z;
}

void Body3D::reset() {
    std::copy(x0_.begin(), x0_.end(), x_.begin());
    std::copy(y0_.begin(), y0_.end(), y_.begin());
    std::copy(z0_.begin(), z0_.end(), z_.begin());
    std::copy(x0_.begin(), x0_.end(), px_.begin());
    std::copy(y0_.begin(), y0_.end(), py_.begin());
    std::copy(z0_.begin(), z0_.end(), pz_.begin());
    for (auto* a : {&vx_, &vy_, &vz_, &ex_, &ey_, &ez_}) std::fill(a->begin(), a->end(), 0.0);
    std::fill(broken_.begin(), broken_.end(), std::uint8_t{0});
    event_count_ = 0;
    last_energy_ = 0.0;
    last_position_sum_ = 0.0;
}

void Body3D::sub_step(int index) {
    // Local restrict pointers (as in transverse_network.cpp): the force stores cannot alias the
    // positions, so the compiler keeps them in registers and vectorises the per-mass loops.
    const std::size_t n = x_.size();
    double* __restrict x = x_.data();
    double* __restrict y = y_.data();
    double* __restrict z = z_.data();
    double* __restrict px = px_.data();
    double* __restrict py = py_.data();
    double* __restrict pz = pz_.data();
    double* __restrict vx = vx_.data();
    double* __restrict vy = vy_.data();
    double* __restrict vz = vz_.data();
    double* __restrict fx = fx_.data();
    double* __restrict fy = fy_.data();
    double* __restrict fz = fz_.data();
    const double* __restrict ex = ex_.data();
    const double* __restrict ey = ey_.data();
    const double* __restrict ez = ez_.data();
    const double* __restrict m = mass_.data();
    const double* __restrict inv_m = inv_mass_.data();
    const double* __restrict lin = linear_drag_.data();
    const double* __restrict quad = quadratic_drag_.data();
    const double dt = sub_dt_, inv_dt = 1.0 / dt;
    const bool cordis = integrator_ == Integrator::explicit_verlet;

    // 1. Velocities (CORDIS: backward difference) and mass-local forces: external, gravity, drag.
    if (cordis) {
        for (std::size_t i = 0; i < n; ++i) {
            vx[i] = (x[i] - px[i]) * inv_dt;
            vy[i] = (y[i] - py[i]) * inv_dt;
            vz[i] = (z[i] - pz[i]) * inv_dt;
        }
    }
    const double gx = gravity_.x, gy = gravity_.y, gz = gravity_.z;
    double kinetic2 = 0.0;   // twice the kinetic energy
    for (std::size_t i = 0; i < n; ++i) {
        const double v2 = vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i];
        const double drag = lin[i] + quad[i] * std::sqrt(v2);   // -c v - b |v| v = -(c + b |v|) v
        fx[i] = ex[i] + m[i] * gx - drag * vx[i];
        fy[i] = ey[i] + m[i] * gy - drag * vy[i];
        fz[i] = ez[i] + m[i] * gz - drag * vz[i];
        kinetic2 += m[i] * v2;
    }

    // 2. Links (gather/scatter): s along u on a, -s u on b. A body whose links are all cohesive with
    // the same parameters (a drop) takes a loop with those parameters as constants: the same
    // arithmetic in the same order, so the same result to the bit, at about 3/4 of the cost.
    const std::size_t links = link_a_.size();
    const std::int32_t* __restrict la = link_a_.data();
    const std::int32_t* __restrict lb = link_b_.data();
    const double* __restrict lk = stiffness_.data();
    const double* __restrict lz = damping_.data();
    const double* __restrict l0 = rest_.data();
    const double* __restrict lbreak = break_force_.data();
    const LinkKind* __restrict kind = kind_.data();
    std::uint8_t* __restrict broken = broken_.data();
    const double* __restrict core_len = core_length_.data();
    const double* __restrict core_k = core_stiffness_.data();
    double elastic2 = 0.0;   // twice the elastic energy
    if (uniform_cohesive_) elastic2 = uniform_cohesive_links(index);
    const std::size_t generic_links = uniform_cohesive_ ? 0 : links;
    for (std::size_t l = 0; l < generic_links; ++l) {
        const LinkKind type = kind[l];
        const bool gone = broken[l] != 0;
        if (gone && type != LinkKind::cohesive) continue;   // a broken cohesive link keeps its core
        const auto a = static_cast<std::size_t>(la[l]);
        const auto b = static_cast<std::size_t>(lb[l]);
        const double dx = x[a] - x[b], dy = y[a] - y[b], dz = z[a] - z[b];
        const double length2 = dx * dx + dy * dy + dz * dz;
        if (gone && length2 >= core_len[l] * core_len[l]) continue;   // a broken bond's core, not touching
        const double length = std::sqrt(length2);
        const double inv_length = length > 0.0 ? 1.0 / length : 0.0;   // L = 0: no axis, no force
        const double ux = dx * inv_length, uy = dy * inv_length, uz = dz * inv_length;
        const double stretch = length - l0[l];
        double s = 0.0;
        if (type == LinkKind::cohesive) {
            const double gap = core_len[l] - length;   // the core pushes while gap > 0
            if (gap > 0.0) {
                s = core_k[l] * gap;
                elastic2 += core_k[l] * gap * gap;
            }
            if (!gone) {
                const double spring = -lk[l] * stretch;
                if (-spring > lbreak[l]) {   // torn apart: the spring's pull only (see the header)
                    broken[l] = 1;
                    if (event_count_ < events_.size()) {
                        events_[event_count_++] = LinkBreak{static_cast<std::int32_t>(l), la[l], lb[l], spring, index};
                    } else {
                        ++dropped_breaks_;
                    }
                } else {
                    const double axial_speed = (vx[a] - vx[b]) * ux + (vy[a] - vy[b]) * uy + (vz[a] - vz[b]) * uz;
                    s += spring - lz[l] * axial_speed;
                    elastic2 += lk[l] * stretch * stretch;
                }
            }
            if (s == 0.0) continue;
        } else {
            const double axial_speed = (vx[a] - vx[b]) * ux + (vy[a] - vy[b]) * uy + (vz[a] - vz[b]) * uz;
            s = -lk[l] * stretch - lz[l] * axial_speed;
            if (type == LinkKind::contact) {
                if (stretch >= 0.0) continue;   // not touching
                s = std::max(s, 0.0);           // push only
            }
            if (std::abs(s) > lbreak[l]) {      // only breakable links have a finite threshold
                broken[l] = 1;
                if (event_count_ < events_.size()) {
                    events_[event_count_++] = LinkBreak{static_cast<std::int32_t>(l), la[l], lb[l], s, index};
                } else {
                    ++dropped_breaks_;
                }
                continue;
            }
            elastic2 += lk[l] * stretch * stretch;
        }
        fx[a] += s * ux;
        fy[a] += s * uy;
        fz[a] += s * uz;
        fx[b] -= s * ux;
        fy[b] -= s * uy;
        fz[b] -= s * uz;
    }
    last_energy_ = 0.5 * (kinetic2 + elastic2);

    // 3. Update. Fixed points have 1/m = 0 and zero velocity, so both schemes leave them in place.
    double sum = 0.0;
    if (cordis) {
        // Position Verlet: x[n+1] = 2 x[n] - x[n-1] + T^2 F / m.
        const double dt2 = dt * dt;
        for (std::size_t i = 0; i < n; ++i) {
            const double nx = 2.0 * x[i] - px[i] + dt2 * fx[i] * inv_m[i];
            const double ny = 2.0 * y[i] - py[i] + dt2 * fy[i] * inv_m[i];
            const double nz = 2.0 * z[i] - pz[i] + dt2 * fz[i] * inv_m[i];
            px[i] = x[i];
            py[i] = y[i];
            pz[i] = z[i];
            x[i] = nx;
            y[i] = ny;
            z[i] = nz;
            sum += nx + ny + nz;
        }
    } else {
        // Symplectic Euler: v += T F / m, then x += T v with the new v.
        for (std::size_t i = 0; i < n; ++i) {
            vx[i] += dt * fx[i] * inv_m[i];
            vy[i] += dt * fy[i] * inv_m[i];
            vz[i] += dt * fz[i] * inv_m[i];
            px[i] = x[i];
            py[i] = y[i];
            pz[i] = z[i];
            x[i] += dt * vx[i];
            y[i] += dt * vy[i];
            z[i] += dt * vz[i];
            sum += x[i] + y[i] + z[i];
        }
    }
    last_position_sum_ = sum;
}

double Body3D::uniform_cohesive_links(int index) {
    const std::size_t links = link_a_.size();
    const double* __restrict x = x_.data();
    const double* __restrict y = y_.data();
    const double* __restrict z = z_.data();
    const double* __restrict vx = vx_.data();
    const double* __restrict vy = vy_.data();
    const double* __restrict vz = vz_.data();
    double* __restrict fx = fx_.data();
    double* __restrict fy = fy_.data();
    double* __restrict fz = fz_.data();
    const std::int32_t* __restrict la = link_a_.data();
    const std::int32_t* __restrict lb = link_b_.data();
    std::uint8_t* __restrict broken = broken_.data();
    const double k = stiffness_[0], damping = damping_[0], l0 = rest_[0], threshold = break_force_[0];
    const double core_len = core_length_[0], core_k = core_stiffness_[0];
    double elastic2 = 0.0;
    // The cohesive branch of sub_step()'s loop, with the parameters hoisted.
    for (std::size_t l = 0; l < links; ++l) {
        const bool gone = broken[l] != 0;
        const auto a = static_cast<std::size_t>(la[l]);
        const auto b = static_cast<std::size_t>(lb[l]);
        const double dx = x[a] - x[b], dy = y[a] - y[b], dz = z[a] - z[b];
        const double length2 = dx * dx + dy * dy + dz * dz;
        if (gone && length2 >= core_len * core_len) continue;
        const double length = std::sqrt(length2);
        const double inv_length = length > 0.0 ? 1.0 / length : 0.0;
        const double ux = dx * inv_length, uy = dy * inv_length, uz = dz * inv_length;
        const double stretch = length - l0;
        double s = 0.0;
        const double gap = core_len - length;
        if (gap > 0.0) {
            s = core_k * gap;
            elastic2 += core_k * gap * gap;
        }
        if (!gone) {
            const double spring = -k * stretch;
            if (-spring > threshold) {
                broken[l] = 1;
                if (event_count_ < events_.size()) {
                    events_[event_count_++] = LinkBreak{static_cast<std::int32_t>(l), la[l], lb[l], spring, index};
                } else {
                    ++dropped_breaks_;
                }
            } else {
                const double axial_speed = (vx[a] - vx[b]) * ux + (vy[a] - vy[b]) * uy + (vz[a] - vz[b]) * uz;
                s += spring - damping * axial_speed;
                elastic2 += k * stretch * stretch;
            }
        }
        if (s == 0.0) continue;
        fx[a] += s * ux;
        fy[a] += s * uy;
        fz[a] += s * uz;
        fx[b] -= s * ux;
        fy[b] -= s * uy;
        fz[b] -= s * uz;
    }
    return elastic2;
}

bool Body3D::step() {
    event_count_ = 0;
    if (!finalized_) return false;   // built or changed since finalize(): nothing is sized to run
    for (int s = 0; s < stability_.sub_steps; ++s) sub_step(s);
    for (auto* a : {&ex_, &ey_, &ez_}) std::fill(a->begin(), a->end(), 0.0);
    // The guard: a NaN or Inf anywhere reaches the position sum (or the energy); the limit catches a
    // blow-up before it overflows.
    if (!std::isfinite(last_position_sum_) || !std::isfinite(last_energy_) || last_energy_ > energy_limit_) {
        reset();
        ++resets_;
        return false;
    }
    return true;
}

// ---------------------------------------------------------------------------------------------
// Queries

Vec3 Body3D::position(int m) const {
    const auto i = idx(m);
    return {x_[i], y_[i], z_[i]};
}

Vec3 Body3D::velocity(int m) const {
    const auto i = idx(m);
    if (integrator_ == Integrator::symplectic_euler || !(sub_dt_ > 0.0)) return {vx_[i], vy_[i], vz_[i]};
    const double inv_dt = 1.0 / sub_dt_;
    return {(x_[i] - px_[i]) * inv_dt, (y_[i] - py_[i]) * inv_dt, (z_[i] - pz_[i]) * inv_dt};
}

double Body3D::total_mass() const {
    double total = 0.0;
    for (double m : mass_) total += m;
    return total;
}

Vec3 Body3D::centre_of_mass() const {
    Vec3 sum{};
    for (std::size_t i = 0; i < x_.size(); ++i) sum = sum + mass_[i] * Vec3{x_[i], y_[i], z_[i]};
    return sum / total_mass();
}

Vec3 Body3D::momentum() const {
    Vec3 p{};
    for (int i = 0; i < mass_count(); ++i) p = p + mass_[idx(i)] * velocity(i);
    return p;
}

double Body3D::kinetic_energy() const {
    double e = 0.0;
    for (int i = 0; i < mass_count(); ++i) {
        const Vec3 v = velocity(i);
        e += 0.5 * mass_[idx(i)] * dot(v, v);
    }
    return e;
}

double Body3D::elastic_energy() const {
    double e = 0.0;
    for (std::size_t l = 0; l < link_a_.size(); ++l) {
        const auto a = idx(link_a_[l]), b = idx(link_b_[l]);
        const double length = norm(Vec3{x_[a] - x_[b], y_[a] - y_[b], z_[a] - z_[b]});
        const double gap = core_length_[l] - length;
        if (gap > 0.0) e += 0.5 * core_stiffness_[l] * gap * gap;   // cohesive cores, bonded or not
        if (broken_[l]) continue;
        const double stretch = length - rest_[l];
        if (kind_[l] == LinkKind::contact && stretch >= 0.0) continue;
        e += 0.5 * stiffness_[l] * stretch * stretch;
    }
    return e;
}

int Body3D::broken_link_count() const {
    int count = 0;
    for (auto b : broken_) count += b;
    return count;
}

}  // namespace ameoto
