#include "engine/core/body3d.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <immintrin.h>
#include <stdexcept>

#include "engine/core/cpu_features.hpp"

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

// reserve() for the render phase: the capacity is also written once (resize, then clear), so its pages
// are resident before the audio thread first fills them. A reserved but untouched page is faulted in by
// the kernel on its first write, which would be on the audio thread, when a pooled drop first uses it
// (a page fault is a trip into the kernel that can wait for memory); and RSS would then creep with each
// slot the rain happens to use (the soak's RSS readings varied by 20 MB with it). Contents and size are
// kept, as reserve() keeps them.
namespace {
template <typename Vector>
void reserve_touched(Vector& v, std::size_t n) {
    const std::size_t size = v.size();
    if (n <= size) return;
    v.resize(n);
    v.resize(size);   // shrinking keeps the capacity
}
}  // namespace

void Body3D::reserve(int masses, int links) {
    if (masses < 0 || links < 0) throw std::invalid_argument("capacity must be >= 0");
    const auto m = idx(masses), l = idx(links);
    for (auto* a : {&x_, &y_, &z_, &px_, &py_, &pz_, &vx_, &vy_, &vz_, &fx_, &fy_, &fz_, &ex_, &ey_, &ez_, &x0_, &y0_,
                    &z0_, &mass_, &inv_mass_, &linear_drag_, &quadratic_drag_, &k_sum_, &z_sum_})
        reserve_touched(*a, m);
    reserve_touched(fixed_, m);
    reserve_touched(link_a_, l);
    reserve_touched(link_b_, l);
    for (auto* a : {&stiffness_, &damping_, &rest_, &break_force_, &core_length_, &core_stiffness_}) reserve_touched(*a, l);
    reserve_touched(kind_, l);
    reserve_touched(broken_, l);
    reserve_touched(events_, std::max<std::size_t>(l, 1));
    // The uniform pass's scratch (build_link_scratch()): groups of 4 masses hold 4 x (their largest
    // degree) slots, at most 4 x (the sum of their degrees), so at most 8 per link.
    reserve_touched(mirror_, 8 * m + 8);
    reserve_touched(contribution_, 4 * (2 * l + 1) + 8);
    reserve_touched(slots_, 8 * l);
    reserve_touched(slot_start_, m / 4 + 2);
    reserve_touched(degree_, m);
    reserve_touched(link_ends_, 2 * l);
    reserve_touched(candidates_, l);
    reserve_touched(near_links_, l);
    for (auto* a : {&listed_x_, &listed_y_, &listed_z_}) reserve_touched(*a, m);
    reserve_touched(coarse_bonds_, l);
    reserve_touched(core_extra_, m);
    reserve_touched(touched_, m);
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
    broken_count_ = 0;
    candidates_valid_ = false;
    next_bound_fresh_ = false;
    event_count_ = 0;
    last_energy_ = 0.0;
    last_position_sum_ = 0.0;
    lowest_z_ = -std::numeric_limits<double>::infinity();
    coarse_looked_ = false;   // coarse_factor() looks at the links again
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
    gershgorin_maxima(omega2, gamma);
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
    broken_count_ = static_cast<std::size_t>(broken_link_count());
    if (uniform_cohesive_) build_link_scratch();
    // Below 16 masses the kernels' fixed cost outweighs their gain (a 2 mm drop, 7 masses: 0.29 us
    // against the scalar 0.20 us); either step gives the same bits.
    use_avx2_ = !portable_kernels_ && n >= 16 && cpu_has_avx2();
    // Coarse steps' reach (body3d_coarse.cpp): only contacts and cores can start acting between masses
    // that are apart; a body with neither has nothing to look out for.
    double longest = 0.0;
    bool can_touch = false;
    for (std::size_t l = 0; l < link_a_.size(); ++l) {
        longest = std::max(longest, std::max(rest_[l], core_length_[l]));
        can_touch = can_touch || kind_[l] == LinkKind::contact || (kind_[l] == LinkKind::cohesive && core_stiffness_[l] > 0.0);
    }
    coarse_reach_m_ = can_touch ? coarse_reach * longest : std::numeric_limits<double>::infinity();
    core_extra_.assign(n, 0.0);
    touched_.assign(n, 0);
    coarse_bonds_.clear();
    coarse_bonds_.reserve(link_a_.size());   // within reserve()'s capacity: no allocation
    lowest_z_ = -std::numeric_limits<double>::infinity();
    coarse_looked_ = false;   // coarse_factor() looks at the links again
    finalized_ = true;
    return stability_;
}

// The largest omega^2 and gamma over the free masses from the per-mass sums in k_sum_ and z_sum_
// (finalize() and coarse_factor()'s look fill them): omega^2 <= k_sum / m, gamma <= (z_sum + drag) / m,
// the quadratic drag linearised at the speed bound (see the header).
void Body3D::gershgorin_maxima(double& omega2, double& gamma) const {
    omega2 = 0.0;
    gamma = 0.0;
    for (std::size_t i = 0; i < x_.size(); ++i) {
        if (fixed_[i]) continue;
        const double drag = linear_drag_[i] + 2.0 * quadratic_drag_[i] * speed_bound_;
        omega2 = std::max(omega2, k_sum_[i] * inv_mass_[i]);
        gamma = std::max(gamma, (z_sum_[i] + drag) * inv_mass_[i]);
    }
}

// The AVX2 uniform pass's lists. Per group of 4 masses (4 g .. 4 g + 3), rows of 4 slots, one per
// mass, each naming the contribution entry to add (2 l: link l's force on a; 2 l + 1: on b; 2 links:
// -0.0, the padding; stored as offsets 4 e), in link order per mass: the order in which the scalar pass
// adds them. Per link its masses as rows of the mirror (8 a, 8 b). And the sparse pass's scratch.
void Body3D::build_link_scratch() {
    const std::size_t n = x_.size(), links = link_a_.size(), groups = (n + 3) / 4;
    degree_.assign(n, 0);
    for (std::size_t l = 0; l < links; ++l) {
        ++degree_[idx(link_a_[l])];
        ++degree_[idx(link_b_[l])];
    }
    slot_start_.assign(groups + 1, 0);
    for (std::size_t g = 0; g < groups; ++g) {
        std::int32_t rows = 0;
        for (std::size_t i = 4 * g; i < std::min(n, 4 * g + 4); ++i) rows = std::max(rows, degree_[i]);
        slot_start_[g + 1] = slot_start_[g] + 4 * rows;
    }
    slots_.assign(static_cast<std::size_t>(slot_start_[groups]), static_cast<std::int32_t>(8 * links));   // padding
    std::fill(degree_.begin(), degree_.end(), 0);   // now each mass's next row
    auto place = [&](std::size_t mass, std::int32_t entry) {
        slots_[static_cast<std::size_t>(slot_start_[mass / 4] + 4 * degree_[mass]) + mass % 4] = entry;
        ++degree_[mass];
    };
    link_ends_.resize(2 * links);
    for (std::size_t l = 0; l < links; ++l) {
        place(idx(link_a_[l]), static_cast<std::int32_t>(8 * l));   // offsets in doubles
        place(idx(link_b_[l]), static_cast<std::int32_t>(8 * l + 4));
        link_ends_[2 * l] = 8 * link_a_[l];
        link_ends_[2 * l + 1] = 8 * link_b_[l];
    }
    candidates_.assign(links, 0);
    near_links_.assign(links, 0);
    near_link_count_ = 0;
    far_travel_ = 0.0;
    for (auto* a : {&listed_x_, &listed_y_, &listed_z_}) a->assign(n, 0.0);
    candidates_valid_ = false;
    next_bound_fresh_ = false;
    mirror_.assign(8 * n + 8, 0.0);
    contribution_.assign(4 * (2 * links + 1) + 8, -0.0);
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
    external_forces_ = true;
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
    next_bound_fresh_ = false;   // the sparse pass measures its bound again (sub_step_avx2())
    lowest_z_ = -std::numeric_limits<double>::infinity();   // unknown until the next step
    coarse_looked_ = false;   // coarse_factor() looks at the links again
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
    broken_count_ = 0;
    candidates_valid_ = false;
    next_bound_fresh_ = false;
    event_count_ = 0;
    last_energy_ = 0.0;
    last_position_sum_ = 0.0;
    lowest_z_ = -std::numeric_limits<double>::infinity();
    coarse_looked_ = false;   // coarse_factor() looks at the links again
}

// ---------------------------------------------------------------------------------------------
// The AVX2 step (see the header, "Vectorisation"): kernels on a StepView, compiled for AVX2 whatever the
// build's target (the region below), run only where finalize() found AVX2. Written on 4-lane vectors
// (GCC vector extensions): lane by lane the same IEEE operations in the same order as the scalar code
// of sub_step_baseline() and uniform_cohesive_links(), so the same bits. No FMA (AVX2 does not include
// it, and this file is compiled with -ffp-contract=off), no reassociation (sums across lanes are added
// lane by lane, in the scalar order). sub_step_avx2() runs them in order: forces(), the links
// (generic_links(), dense_links() or sparse_links()), update().

#pragma GCC push_options
#pragma GCC target("avx2")

namespace {

using v4d = double __attribute__((vector_size(32)));
using v4m = std::int64_t __attribute__((vector_size(32)));   // a lane mask, 0 or -1, as comparisons give

#define AMEOTO_INLINE inline __attribute__((always_inline))

AMEOTO_INLINE v4d load4(const double* p) {
    v4d v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}
AMEOTO_INLINE void store4(double* p, const v4d& v) { __builtin_memcpy(p, &v, sizeof v); }
// Lanes past `count` (an array's tail) read as 0 and are not written.
AMEOTO_INLINE v4d loadn(const double* p, int count) {
    if (count == 4) return load4(p);
    v4d v = {0.0, 0.0, 0.0, 0.0};
    for (int k = 0; k < count; ++k) v[k] = p[k];
    return v;
}
AMEOTO_INLINE void storen(double* p, const v4d& v, int count) {
    if (count == 4) return store4(p, v);
    for (int k = 0; k < count; ++k) p[k] = v[k];
}
AMEOTO_INLINE v4d splat(double a) { return v4d{a, a, a, a}; }
AMEOTO_INLINE v4d vsqrt(const v4d& a) { return _mm256_sqrt_pd(a); }

// Rows (x y z w) of four items <-> columns x, y, z (w dropped; w = 0 going back).
AMEOTO_INLINE void rows_to_columns(const v4d& r0, const v4d& r1, const v4d& r2, const v4d& r3, v4d& x, v4d& y,
                                   v4d& z) {
    const v4d t0 = __builtin_shufflevector(r0, r1, 0, 4, 2, 6);   // x0 x1 z0 z1
    const v4d t1 = __builtin_shufflevector(r0, r1, 1, 5, 3, 7);   // y0 y1 w0 w1
    const v4d t2 = __builtin_shufflevector(r2, r3, 0, 4, 2, 6);   // x2 x3 z2 z3
    const v4d t3 = __builtin_shufflevector(r2, r3, 1, 5, 3, 7);   // y2 y3 w2 w3
    x = __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
    y = __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
    z = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
}
AMEOTO_INLINE void columns_to_rows(const v4d& x, const v4d& y, const v4d& z, v4d& r0, v4d& r1, v4d& r2, v4d& r3) {
    const v4d zero = {0.0, 0.0, 0.0, 0.0};
    const v4d t0 = __builtin_shufflevector(x, y, 0, 4, 2, 6);      // x0 y0 x2 y2
    const v4d t1 = __builtin_shufflevector(x, y, 1, 5, 3, 7);      // x1 y1 x3 y3
    const v4d t2 = __builtin_shufflevector(z, zero, 0, 4, 2, 6);   // z0 0 z2 0
    const v4d t3 = __builtin_shufflevector(z, zero, 1, 5, 3, 7);   // z1 0 z3 0
    r0 = __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
    r1 = __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
    r2 = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
    r3 = __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
}

// A lane mask as bits (lane k: bit k).
AMEOTO_INLINE int lane_bits(const v4m& m) { return _mm256_movemask_pd(reinterpret_cast<__m256d>(m)); }

double* align64(double* p) {
    const auto u = reinterpret_cast<std::uintptr_t>(p);
    return reinterpret_cast<double*>((u + 63) & ~std::uintptr_t{63});
}

// Everything a sub-step's kernels read and write. Each kernel copies it first: a local copy lives in
// registers, where a reference would be read again after every store of a double.
struct StepView {
    std::size_t n = 0, links = 0;
    double *x, *y, *z, *px, *py, *pz, *vx, *vy, *vz, *fx, *fy, *fz;
    const double *ex, *ey, *ez, *m, *inv_m, *lin, *quad;
    double gx, gy, gz, dt, inv_dt;
    bool cordis;
    bool energy;                    // sum the energies (only for a finite energy limit: the guard)
    // The uniform cohesive pass (null otherwise).
    double* mirror;                 // per mass x y z 0 vx vy vz 0, written by forces()
    double* contribution;           // entry e at 4 e: [2 l] = +t, [2 l + 1] = -t of link l, [2 links] = -0.0
    const std::int32_t* ends;       // per link 8 a, 8 b: its masses' rows in the mirror
    const std::int32_t* slots;      // per group of 4 masses, rows of 4 entries x 4 (one per mass);
                                    // null: the sparse pass
    const std::int32_t* slot_start;
    std::int32_t* candidates;       // the sparse pass's links
    std::size_t candidate_count;
    std::int32_t* near_links;       // the links a partial listing looks at (list_candidates())
    std::size_t* near_link_count;
    double far;                     // ... a full listing leaves out broken links at least this long
    double near;                    // a broken link is listed if its masses are closer than this
    double *listed_x, *listed_y, *listed_z;   // positions when listed
    const std::int32_t *la, *lb;
    std::uint8_t* broken;
    double k, damping, l0, threshold, core_len, core_len2, core_k;
    LinkBreak* events;
    std::size_t event_capacity;
    std::size_t* event_count;
    long* dropped;
    std::size_t* broken_count;
    int index;
};

// 1. Velocities (CORDIS: backward difference) and mass-local forces: external, gravity, drag; for the
// uniform pass also the mirror (position and velocity as one 64-byte row per mass: a link reads each
// end with two loads). Adds m v^2 to kinetic2 in mass order.
// External: apply_force() was called this step (s.ex set). Otherwise every external force is +0.0 and
// +0.0 stands in for its load (0.0 + m g is still added, as the scalar step adds ex = +0.0: the same bits,
// -0.0 included), which frees three of the loop's many pointers.
template <int Count, bool External>
AMEOTO_INLINE void forces_group(const StepView& s, std::size_t i, double& kinetic2) {
    v4d vx, vy, vz;
    if (s.cordis) {
        const v4d inv_dt = splat(s.inv_dt);
        vx = (loadn(s.x + i, Count) - loadn(s.px + i, Count)) * inv_dt;
        vy = (loadn(s.y + i, Count) - loadn(s.py + i, Count)) * inv_dt;
        vz = (loadn(s.z + i, Count) - loadn(s.pz + i, Count)) * inv_dt;
        storen(s.vx + i, vx, Count);
        storen(s.vy + i, vy, Count);
        storen(s.vz + i, vz, Count);
    } else {
        vx = loadn(s.vx + i, Count);
        vy = loadn(s.vy + i, Count);
        vz = loadn(s.vz + i, Count);
    }
    const v4d v2 = vx * vx + vy * vy + vz * vz;
    const v4d drag = loadn(s.lin + i, Count) + loadn(s.quad + i, Count) * vsqrt(v2);   // -(c + b |v|) v
    const v4d m = loadn(s.m + i, Count);
    const v4d ex = External ? loadn(s.ex + i, Count) : splat(0.0);
    const v4d ey = External ? loadn(s.ey + i, Count) : splat(0.0);
    const v4d ez = External ? loadn(s.ez + i, Count) : splat(0.0);
    storen(s.fx + i, ex + m * splat(s.gx) - drag * vx, Count);
    storen(s.fy + i, ey + m * splat(s.gy) - drag * vy, Count);
    storen(s.fz + i, ez + m * splat(s.gz) - drag * vz, Count);
    if (s.energy) {
        const v4d mv2 = m * v2;
        for (int k = 0; k < Count; ++k) kinetic2 += mv2[k];
    }
    if (s.mirror) {
        v4d p0, p1, p2, p3, v0, v1, v2, v3;
        columns_to_rows(loadn(s.x + i, Count), loadn(s.y + i, Count), loadn(s.z + i, Count), p0, p1, p2, p3);
        columns_to_rows(vx, vy, vz, v0, v1, v2, v3);
        double* row = s.mirror + 8 * i;
        store4(row, p0);
        store4(row + 4, v0);
        if (Count > 1) store4(row + 8, p1);
        if (Count > 1) store4(row + 12, v1);
        if (Count > 2) store4(row + 16, p2);
        if (Count > 2) store4(row + 20, v2);
        if (Count > 3) store4(row + 24, p3);
        if (Count > 3) store4(row + 28, v3);
    }
}

template <bool External>
AMEOTO_INLINE double forces(const StepView& view) {
    const StepView s = view;
    double kinetic2 = 0.0;   // twice the kinetic energy
    std::size_t i = 0;
    for (; i + 4 <= s.n; i += 4) forces_group<4, External>(s, i, kinetic2);
    switch (s.n - i) {
        case 3: forces_group<3, External>(s, i, kinetic2); break;
        case 2: forces_group<2, External>(s, i, kinetic2); break;
        case 1: forces_group<1, External>(s, i, kinetic2); break;
        default: break;
    }
    return kinetic2;
}

// 2. The uniform cohesive pass, four links per group. Per lane exactly the scalar pass's arithmetic
// (uniform_cohesive_links()), its branches turned into lane masks. A link's force is s u on a and -s u
// on b; s = 0 or a skipped link (broken, core not touching) adds nothing. Two ways to add them, both in
// link order per mass (so the scalar pass's sums):
//   dense (at least a quarter of the links bonded): links l .. l + 3 at a time; each writes +t = s u
//     and -t to `contribution`, -0.0 for nothing (x + -0 = x for every x), and accumulate() adds them
//     per mass through the slot lists;
//   sparse (most links broken): the candidate links (see sub_step_avx2()), four at a time; the acting
//     ones are added at once to the force accumulator, lane after lane, as the scalar pass does.
// Adds the elastic terms to elastic2 in link order.

// A group's links: l[k] for lane k; lanes past Count repeat the last link and are ignored.
struct LaneLinks {
    std::size_t l[4];
};

template <bool Dense, int Count>
AMEOTO_INLINE void add_link_forces(const StepView& s, const LaneLinks& g, int live, const v4d& tx, const v4d& ty,
                                   const v4d& tz) {
    if constexpr (Dense) {
        // Dense groups are consecutive links: entries 2 l[0] ... are one block.
        const v4d minus_zero = splat(-0.0);
        v4d p0, p1, p2, p3, m0, m1, m2, m3;
        if (live == (1 << Count) - 1) [[likely]] {
            columns_to_rows(tx, ty, tz, p0, p1, p2, p3);
            m0 = -p0;   // exact negation
            m1 = -p1;
            m2 = -p2;
            m3 = -p3;
        } else {
            const v4m on = {-std::int64_t{(live & 1) != 0}, -std::int64_t{(live & 2) != 0},
                            -std::int64_t{(live & 4) != 0}, -std::int64_t{(live & 8) != 0}};
            columns_to_rows(on ? tx : minus_zero, on ? ty : minus_zero, on ? tz : minus_zero, p0, p1, p2, p3);
            columns_to_rows(on ? -tx : minus_zero, on ? -ty : minus_zero, on ? -tz : minus_zero, m0, m1, m2, m3);
        }
        double* out = s.contribution + 8 * g.l[0];
        store4(out, p0);
        store4(out + 4, m0);
        if (Count > 1) store4(out + 8, p1);
        if (Count > 1) store4(out + 12, m1);
        if (Count > 2) store4(out + 16, p2);
        if (Count > 2) store4(out + 20, m2);
        if (Count > 3) store4(out + 24, p3);
        if (Count > 3) store4(out + 28, m3);
    } else {
        for (int k = 0; k < Count; ++k) {
            if (!(live & (1 << k))) continue;
            const auto a = static_cast<std::size_t>(s.la[g.l[k]]), b = static_cast<std::size_t>(s.lb[g.l[k]]);
            s.fx[a] += tx[k];
            s.fy[a] += ty[k];
            s.fz[a] += tz[k];
            s.fx[b] -= tx[k];
            s.fy[b] -= ty[k];
            s.fz[b] -= tz[k];
        }
    }
}

// d = x_a - x_b of the group's links, as columns.
template <int Count>
AMEOTO_INLINE void link_offsets(const StepView& s, const LaneLinks& g, int row, v4d& x, v4d& y, v4d& z) {
    auto a = [&](int k) { return s.mirror + s.ends[2 * g.l[k]] + row; };
    auto b = [&](int k) { return s.mirror + s.ends[2 * g.l[k] + 1] + row; };
    rows_to_columns(load4(a(0)) - load4(b(0)), load4(a(1)) - load4(b(1)), load4(a(2)) - load4(b(2)),
                    load4(a(3)) - load4(b(3)), x, y, z);
}

template <int Count>
AMEOTO_INLINE int gone_bits(const StepView& s, const LaneLinks& g, bool consecutive) {
    if (Count == 4 && consecutive) {
        std::uint32_t word;   // broken flags are 0 or 1
        __builtin_memcpy(&word, s.broken + g.l[0], sizeof word);
        return static_cast<int>((word & 1u) | (word >> 7 & 2u) | (word >> 14 & 4u) | (word >> 21 & 8u));
    }
    int bits = 0;
    for (int k = 0; k < Count; ++k) bits |= s.broken[g.l[k]] != 0 ? 1 << k : 0;
    return bits;
}

AMEOTO_INLINE v4m lane_mask(int bits) {
    return v4m{-std::int64_t{(bits & 1) != 0}, -std::int64_t{(bits & 2) != 0}, -std::int64_t{(bits & 4) != 0},
               -std::int64_t{(bits & 8) != 0}};
}

template <bool Dense, int Count>
AMEOTO_INLINE void link_group(const StepView& s, const LaneLinks& g, bool consecutive, double& elastic2) {
    constexpr int all = (1 << Count) - 1;   // the valid lanes' bits
    const int gone_lanes = gone_bits<Count>(s, g, consecutive);
    const v4d zero = splat(0.0), minus_zero = splat(-0.0);
    v4d dx, dy, dz;   // d = x_a - x_b
    link_offsets<Count>(s, g, 0, dx, dy, dz);
    const v4d length2 = dx * dx + dy * dy + dz * dz;
    const v4m gone = lane_mask(gone_lanes);
    const v4m skip = gone & (length2 >= splat(s.core_len2));   // a broken bond's core, not touching
    if (gone_lanes == all && (lane_bits(skip) & all) == all) {
        // All broken and apart (much of a shattered drop): the distance test is all.
        if constexpr (Dense) add_link_forces<Dense, Count>(s, g, 0, zero, zero, zero);
        return;
    }
    v4d wx, wy, wz;   // w = v_a - v_b
    link_offsets<Count>(s, g, 4, wx, wy, wz);
    const v4d length = vsqrt(length2);
    const v4d inv_length = length > zero ? splat(1.0) / length : zero;   // L = 0: no axis, no force
    const v4d ux = dx * inv_length, uy = dy * inv_length, uz = dz * inv_length;
    const v4d stretch = length - splat(s.l0);
    const v4d gap = splat(s.core_len) - length;   // the core pushes while gap > 0
    const v4d spring = splat(-s.k) * stretch;
    const v4d axial_speed = wx * ux + wy * uy + wz * uz;
    const v4d bond = spring - splat(s.damping) * axial_speed;
    const v4d e_spring = splat(s.k) * stretch * stretch;
    // The common case: bonded, no core, not breaking, and s = 0.0 + bond != 0 (so s = bond).
    if (gone_lanes == 0 && lane_bits((gap > zero) | (-spring > splat(s.threshold)) | (bond == zero)) == 0) [[likely]] {
        if (s.energy)
            for (int k = 0; k < Count; ++k) elastic2 += e_spring[k];
        add_link_forces<Dense, Count>(s, g, all, bond * ux, bond * uy, bond * uz);
        return;
    }
    const v4m core_on = (gap > zero) & ~skip;
    const v4d s_core = core_on ? splat(s.core_k) * gap : zero;
    const v4m breaking = ~gone & (-spring > splat(s.threshold));   // torn apart: the spring's pull only
    const v4m acting = ~gone & ~breaking;
    const v4d force = acting ? s_core + bond : s_core;
    const v4d e_core = core_on ? splat(s.core_k) * gap * gap : minus_zero;
    const v4d e_bond = acting ? e_spring : minus_zero;
    if (s.energy)
        for (int k = 0; k < Count; ++k) {
            elastic2 += e_core[k];
            elastic2 += e_bond[k];
        }
    const int breaks = lane_bits(breaking) & all;
    for (int k = 0; k < Count; ++k) {
        if (!(breaks & (1 << k))) continue;
        const std::size_t l = g.l[k];
        s.broken[l] = 1;
        ++*s.broken_count;
        if (*s.event_count < s.event_capacity) {
            s.events[(*s.event_count)++] = LinkBreak{static_cast<std::int32_t>(l), s.la[l], s.lb[l], spring[k], s.index};
        } else {
            ++*s.dropped;
        }
    }
    const int live = lane_bits(~skip & (force != zero)) & all;
    add_link_forces<Dense, Count>(s, g, live, force * ux, force * uy, force * uz);
}

template <int Count>
AMEOTO_INLINE LaneLinks consecutive_links(std::size_t first) {
    LaneLinks g;
    for (int k = 0; k < 4; ++k) g.l[k] = first + static_cast<std::size_t>(k < Count ? k : Count - 1);
    return g;
}

template <int Count>
AMEOTO_INLINE LaneLinks listed_links(const std::int32_t* list) {
    LaneLinks g;
    for (int k = 0; k < 4; ++k) g.l[k] = static_cast<std::size_t>(list[k < Count ? k : Count - 1]);
    return g;
}

// Dense: every link, l .. l + 3 at a time.
AMEOTO_INLINE double dense_links(const StepView& view) {
    const StepView s = view;
    double elastic2 = 0.0;   // twice the elastic energy
    std::size_t l = 0;
    for (; l + 4 <= s.links; l += 4) link_group<true, 4>(s, consecutive_links<4>(l), true, elastic2);
    switch (s.links - l) {
        case 3: link_group<true, 3>(s, consecutive_links<3>(l), true, elastic2); break;
        case 2: link_group<true, 2>(s, consecutive_links<2>(l), true, elastic2); break;
        case 1: link_group<true, 1>(s, consecutive_links<1>(l), true, elastic2); break;
        default: break;
    }
    return elastic2;
}

// Sparse: the candidates, four at a time.
AMEOTO_INLINE double sparse_links(const StepView& view) {
    const StepView s = view;
    double elastic2 = 0.0;
    std::size_t j = 0;
    for (; j + 4 <= s.candidate_count; j += 4) link_group<false, 4>(s, listed_links<4>(s.candidates + j), false, elastic2);
    switch (s.candidate_count - j) {
        case 3: link_group<false, 3>(s, listed_links<3>(s.candidates + j), false, elastic2); break;
        case 2: link_group<false, 2>(s, listed_links<2>(s.candidates + j), false, elastic2); break;
        case 1: link_group<false, 1>(s, listed_links<1>(s.candidates + j), false, elastic2); break;
        default: break;
    }
    return elastic2;
}

// The sparse pass's candidates: the bonded links and the broken ones whose masses are closer than
// s.near (core length + margin), in link order; and the positions they were listed at. Returns how many.
// A full listing looks at every link and also keeps, in link order, the bonded links and the broken ones
// closer than s.far (core length + a wider margin: s.near_links); a partial one looks at those only
// (sub_step_avx2() says when a partial one suffices).
template <int Count, bool Full>
AMEOTO_INLINE void list_group(const StepView& s, const LaneLinks& g, std::size_t& count, std::size_t& near_count) {
    const int gone_lanes = gone_bits<Count>(s, g, Full);   // a full listing's groups are consecutive links
    int keep = ~gone_lanes, near = ~gone_lanes;
    if (gone_lanes != 0) {
        v4d dx, dy, dz;
        link_offsets<Count>(s, g, 0, dx, dy, dz);
        const v4d length2 = dx * dx + dy * dy + dz * dz;
        keep |= lane_bits(~(length2 >= splat(s.near * s.near)));   // NaN: kept
        if constexpr (Full) near |= lane_bits(~(length2 >= splat(s.far * s.far)));
    }
    for (int k = 0; k < Count; ++k) {
        if (keep & (1 << k)) s.candidates[count++] = static_cast<std::int32_t>(g.l[k]);
    }
    if constexpr (Full) {
        for (int k = 0; k < Count; ++k) {
            if (near & (1 << k)) s.near_links[near_count++] = static_cast<std::int32_t>(g.l[k]);
        }
    }
}

template <bool Full>
AMEOTO_INLINE std::size_t list_candidates(const StepView& view) {
    const StepView s = view;
    std::size_t count = 0, near_count = 0;
    if constexpr (Full) {
        std::size_t l = 0;
        for (; l + 4 <= s.links; l += 4) list_group<4, true>(s, consecutive_links<4>(l), count, near_count);
        switch (s.links - l) {
            case 3: list_group<3, true>(s, consecutive_links<3>(l), count, near_count); break;
            case 2: list_group<2, true>(s, consecutive_links<2>(l), count, near_count); break;
            case 1: list_group<1, true>(s, consecutive_links<1>(l), count, near_count); break;
            default: break;
        }
        *s.near_link_count = near_count;
    } else {
        const std::size_t links = *s.near_link_count;
        std::size_t j = 0;
        for (; j + 4 <= links; j += 4) list_group<4, false>(s, listed_links<4>(s.near_links + j), count, near_count);
        switch (links - j) {
            case 3: list_group<3, false>(s, listed_links<3>(s.near_links + j), count, near_count); break;
            case 2: list_group<2, false>(s, listed_links<2>(s.near_links + j), count, near_count); break;
            case 1: list_group<1, false>(s, listed_links<1>(s.near_links + j), count, near_count); break;
            default: break;
        }
    }
    __builtin_memcpy(s.listed_x, s.x, s.n * sizeof(double));
    __builtin_memcpy(s.listed_y, s.y, s.n * sizeof(double));
    __builtin_memcpy(s.listed_z, s.z, s.n * sizeof(double));
    return count;
}

// The displacements' range, gathered four masses at a time (lanes), by approach_bound2() or, fused
// into the update, by update() for the next sub-step. (Members set by clear(), not by initialisers: an
// implicit constructor would be compiled outside this AVX2 region.)
struct DisplacementRange4 {
    v4d lo_x, lo_y, lo_z, hi_x, hi_y, hi_z;
    v4m bad;
    AMEOTO_INLINE void clear() {
        lo_x = lo_y = lo_z = hi_x = hi_y = hi_z = v4d{0.0, 0.0, 0.0, 0.0};
        bad = v4m{0, 0, 0, 0};
    }
    // dx, dy, dz: displacements since listing (lanes past an array's tail: 0, a displacement of 0).
    // Without NaN: the caller knows otherwise whether one was NaN (update(): see there).
    template <bool NoteNaN = true>
    AMEOTO_INLINE void take(const v4d& dx, const v4d& dy, const v4d& dz) {
        if constexpr (NoteNaN) bad |= (dx != dx) | (dy != dy) | (dz != dz);
        lo_x = _mm256_min_pd(lo_x, dx);
        lo_y = _mm256_min_pd(lo_y, dy);
        lo_z = _mm256_min_pd(lo_z, dz);
        hi_x = _mm256_max_pd(hi_x, dx);
        hi_y = _mm256_max_pd(hi_y, dy);
        hi_z = _mm256_max_pd(hi_z, dz);
    }
    AMEOTO_INLINE double bound2() const {
        if (lane_bits(bad) != 0) return std::numeric_limits<double>::quiet_NaN();
        const v4d rx = hi_x - lo_x, ry = hi_y - lo_y, rz = hi_z - lo_z;
        double range_x = 0.0, range_y = 0.0, range_z = 0.0;
        for (int k = 0; k < 4; ++k) {
            range_x = std::max(range_x, rx[k]);
            range_y = std::max(range_y, ry[k]);
            range_z = std::max(range_z, rz[k]);
        }
        return range_x * range_x + range_y * range_y + range_z * range_z;
    }
};

// How far any two masses can have moved towards each other since they were listed: the relative
// displacement of a and b is at most the range (max - min over the masses) of the displacements, per
// axis. Returns the squared bound (NaN if a position is not finite).
AMEOTO_INLINE double approach_bound2(const StepView& view) {
    const StepView s = view;
    DisplacementRange4 range;
    range.clear();
    auto take = [&](std::size_t i, int count) {
        range.take(loadn(s.x + i, count) - loadn(s.listed_x + i, count), loadn(s.y + i, count) - loadn(s.listed_y + i, count),
                   loadn(s.z + i, count) - loadn(s.listed_z + i, count));
    };
    std::size_t i = 0;
    for (; i + 4 <= s.n; i += 4) take(i, 4);
    if (i < s.n) take(i, static_cast<int>(s.n - i));   // the tail's empty lanes read 0: a displacement of 0
    return range.bound2();
}

// 3. Update, four masses per group; for the uniform pass first the link forces, added per mass in link
// order. Adds the new coordinates to sum in mass order. Fixed points have 1/m = 0 and zero velocity,
// so both schemes leave them in place.
template <int Count, bool Track>
AMEOTO_INLINE void update_group(const StepView& s, std::size_t i, v4d& sum, v4d& lowest, DisplacementRange4& range) {
    v4d fx = loadn(s.fx + i, Count), fy = loadn(s.fy + i, Count), fz = loadn(s.fz + i, Count);
    if (s.slots) {
        v4d f0, f1, f2, f3;
        columns_to_rows(fx, fy, fz, f0, f1, f2, f3);
        const std::int32_t* slot = s.slots + s.slot_start[i / 4];
        const std::int32_t* const end = s.slots + s.slot_start[i / 4 + 1];
        for (; slot != end; slot += 4) {
            f0 += load4(s.contribution + slot[0]);
            f1 += load4(s.contribution + slot[1]);
            f2 += load4(s.contribution + slot[2]);
            f3 += load4(s.contribution + slot[3]);
        }
        rows_to_columns(f0, f1, f2, f3, fx, fy, fz);
    }
    const v4d inv_m = loadn(s.inv_m + i, Count);
    const v4d x = loadn(s.x + i, Count), y = loadn(s.y + i, Count), z = loadn(s.z + i, Count);
    v4d nx, ny, nz;
    if (s.cordis) {
        // Position Verlet: x[n+1] = 2 x[n] - x[n-1] + T^2 F / m.
        const v4d dt2 = splat(s.dt * s.dt), two = splat(2.0);
        nx = two * x - loadn(s.px + i, Count) + dt2 * fx * inv_m;
        ny = two * y - loadn(s.py + i, Count) + dt2 * fy * inv_m;
        nz = two * z - loadn(s.pz + i, Count) + dt2 * fz * inv_m;
    } else {
        // Symplectic Euler: v += T F / m, then x += T v with the new v.
        const v4d dt = splat(s.dt);
        const v4d vx = loadn(s.vx + i, Count) + dt * fx * inv_m;
        const v4d vy = loadn(s.vy + i, Count) + dt * fy * inv_m;
        const v4d vz = loadn(s.vz + i, Count) + dt * fz * inv_m;
        storen(s.vx + i, vx, Count);
        storen(s.vy + i, vy, Count);
        storen(s.vz + i, vz, Count);
        nx = x + dt * vx;
        ny = y + dt * vy;
        nz = z + dt * vz;
    }
    storen(s.px + i, x, Count);
    storen(s.py + i, y, Count);
    storen(s.pz + i, z, Count);
    storen(s.x + i, nx, Count);
    storen(s.y + i, ny, Count);
    storen(s.z + i, nz, Count);
    // Lane k sums the masses i = k mod 4 (the scalar step's sum[i % 4]); the lanes past Count add
    // 0 + 0 + 0 = +0, which leaves a lane unchanged (a lane starts at +0 and never becomes -0).
    sum += nx + ny + nz;
    // The lowest z (Body3D::lowest_z()): min is exact, so the scalar step's min gives the same value. The
    // lanes past Count hold 0, not a mass: +infinity there.
    if constexpr (Count == 4) {
        lowest = _mm256_min_pd(lowest, nz);
    } else {
        const v4d inf = splat(std::numeric_limits<double>::infinity());
        const v4d tail = {0.0, Count > 1 ? 0.0 : 1.0, Count > 2 ? 0.0 : 1.0, 1.0};   // 1: a lane past Count
        lowest = _mm256_min_pd(lowest, tail != splat(0.0) ? inf : nz);
    }
    // The sparse pass's next approach bound (approach_bound2() on the positions just written; the
    // tail's empty lanes are 0 - 0).
    if constexpr (Track)
        range.template take<false>(nx - loadn(s.listed_x + i, Count), ny - loadn(s.listed_y + i, Count),
                                   nz - loadn(s.listed_z + i, Count));
}

// Returns the coordinates' sum and sets lowest_z (the lowest new z); with Track, also the approach bound
// of the positions written (bound2).
template <bool Track>
AMEOTO_INLINE double update(const StepView& view, double& lowest_z, double& bound2) {
    const StepView s = view;
    v4d sum = splat(0.0);
    v4d lowest = splat(std::numeric_limits<double>::infinity());
    DisplacementRange4 range;
    if constexpr (Track) range.clear();
    std::size_t i = 0;
    for (; i + 4 <= s.n; i += 4) update_group<4, Track>(s, i, sum, lowest, range);
    switch (s.n - i) {
        case 3: update_group<3, Track>(s, i, sum, lowest, range); break;
        case 2: update_group<2, Track>(s, i, sum, lowest, range); break;
        case 1: update_group<1, Track>(s, i, sum, lowest, range); break;
        default: break;
    }
    // A displacement is NaN only if a position written or listed is not finite, and a coordinate that is
    // not finite never becomes finite again (x + T v, 2 x - x[n-1] + ...), so then the sum is not finite
    // either: the sum stands for the NaN mask (fewer registers in the loop).
    const double total = ((sum[0] + sum[1]) + sum[2]) + sum[3];
    if constexpr (Track) bound2 = std::isfinite(total) ? range.bound2() : std::numeric_limits<double>::quiet_NaN();
    lowest_z = std::min(std::min(lowest[0], lowest[1]), std::min(lowest[2], lowest[3]));
    return total;
}

#undef AMEOTO_INLINE

// The kernels as functions of their own (AVX2 code: called only where finalize() found AVX2).
double forces_avx2(const StepView& s) { return s.ex ? forces<true>(s) : forces<false>(s); }
double dense_links_avx2(const StepView& s) { return dense_links(s); }
double sparse_links_avx2(const StepView& s) { return sparse_links(s); }
std::size_t list_candidates_avx2(const StepView& s, bool full) {
    return full ? list_candidates<true>(s) : list_candidates<false>(s);
}
double approach_bound2_avx2(const StepView& s) { return approach_bound2(s); }
double update_avx2(const StepView& s, double& lowest_z) {
    double unused = 0.0;
    return update<false>(s, lowest_z, unused);
}
double update_tracking_avx2(const StepView& s, double& lowest_z, double& bound2) {
    return update<true>(s, lowest_z, bound2);
}

}  // namespace

#pragma GCC pop_options

void Body3D::sub_step(int index) {
    if (use_avx2_) {
        sub_step_avx2(index);
    } else {
        sub_step_baseline(index);
    }
}

void Body3D::sub_step_avx2(int index) {
    StepView s;
    s.n = x_.size();
    s.links = link_a_.size();
    s.x = x_.data();
    s.y = y_.data();
    s.z = z_.data();
    s.px = px_.data();
    s.py = py_.data();
    s.pz = pz_.data();
    s.vx = vx_.data();
    s.vy = vy_.data();
    s.vz = vz_.data();
    s.fx = fx_.data();
    s.fy = fy_.data();
    s.fz = fz_.data();
    // Null: no apply_force() this step, every external force is +0.0 (forces_group()).
    s.ex = external_forces_ ? ex_.data() : nullptr;
    s.ey = external_forces_ ? ey_.data() : nullptr;
    s.ez = external_forces_ ? ez_.data() : nullptr;
    s.m = mass_.data();
    s.inv_m = inv_mass_.data();
    s.lin = linear_drag_.data();
    s.quad = quadratic_drag_.data();
    s.gx = gravity_.x;
    s.gy = gravity_.y;
    s.gz = gravity_.z;
    s.dt = sub_dt_ * dt_scale_;   // x 1.0 (exact) but in a coarse step
    s.inv_dt = 1.0 / s.dt;
    s.cordis = integrator_ == Integrator::explicit_verlet;
    s.energy = energy_limit_ < std::numeric_limits<double>::infinity();
    s.mirror = nullptr;
    s.contribution = nullptr;
    s.slots = nullptr;
    s.slot_start = nullptr;
    if (uniform_cohesive_) {
        s.mirror = align64(mirror_.data());
        s.contribution = align64(contribution_.data());
        s.ends = link_ends_.data();
        // Dense while at least a quarter of the links are bonded (see dense_links()).
        const bool dense = 4 * (link_a_.size() - broken_count_) >= link_a_.size();
        s.slots = dense ? slots_.data() : nullptr;
        s.candidates = candidates_.data();
        s.listed_x = listed_x_.data();
        s.listed_y = listed_y_.data();
        s.listed_z = listed_z_.data();
        s.near = core_length_[0] + near_margin * rest_[0];
        s.far = core_length_[0] + far_margin * rest_[0];
        s.near_links = near_links_.data();
        s.near_link_count = &near_link_count_;
        s.slot_start = slot_start_.data();
        s.la = link_a_.data();
        s.lb = link_b_.data();
        s.broken = broken_.data();
        s.k = stiffness_[0];
        s.damping = damping_[0];
        s.l0 = rest_[0];
        s.threshold = break_force_[0];
        s.core_len = core_length_[0];
        s.core_len2 = core_length_[0] * core_length_[0];
        s.core_k = core_stiffness_[0];
        s.events = events_.data();
        s.event_capacity = events_.size();
        s.event_count = &event_count_;
        s.dropped = &dropped_breaks_;
        s.broken_count = &broken_count_;
        s.index = index;
    }
    const double kinetic2 = forces_avx2(s);
    double elastic2 = 0.0;
    if (!uniform_cohesive_) {
        elastic2 = generic_links(index);
    } else if (s.slots) {
        candidates_valid_ = false;
        elastic2 = dense_links_avx2(s);
    } else {
        // The sparse pass computes only the candidates: a broken link left out had its masses at least
        // core length + near_margin h = 4 h apart (h: rest length) when listed, and the list is made again
        // before they can have approached by 2 h (so they stay 2 h clear of the core, far beyond
        // rounding): until then the scalar pass skips it too. The bound compares the positions with
        // those listed, so it holds whatever moved them (set_position() too). A position not finite:
        // listed again, NaN links kept.
        // (Margin and bound measured on a shattered 5 mm drop: 8 h and 4 h, listing about every 9 steps,
        // cost 1.7 % more per drop in instructions: more candidates far from touching.)
        // The bound of the positions now: the last sparse sub-step's update measured it (fused, no pass
        // of its own), unless something has moved a mass since (set_position, reset, finalize).
        // A partial listing (the links a full one found closer than core length + far_margin h: the
        // bonded and the nearby broken ones) suffices while the others are still near_margin h clear of
        // the core:
        // each listing's bound (the approach since the listing before) adds to far_travel_, which bounds
        // the approach since the last full listing (the triangle inequality), and the next listing comes
        // before a further near_margin h / 2; so a full listing when far_travel_ passes far_margin h -
        // near_margin h, leaving every link left out at least near_margin h / 2 clear of its core, as above.
        bool full = !candidates_valid_;   // invalidated (dense, reset, finalize): list everything
        if (candidates_valid_) {
            const double bound2 = next_bound_fresh_ ? next_bound2_ : approach_bound2_avx2(s);
            if (!(bound2 < 0.25 * near_margin * near_margin * rest_[0] * rest_[0])) {
                candidates_valid_ = false;
                far_travel_ += std::sqrt(bound2);   // NaN: a full listing
                full = !(far_travel_ <= (far_margin - near_margin) * rest_[0]);
            }
        }
        if (!candidates_valid_) {
            candidate_count_ = list_candidates_avx2(s, full);
            if (full) far_travel_ = 0.0;
            candidates_valid_ = true;
        }
        s.candidate_count = candidate_count_;
        elastic2 = sparse_links_avx2(s);
    }
    last_energy_ = s.energy ? 0.5 * (kinetic2 + elastic2) : 0.0;
    const bool sparse = uniform_cohesive_ && !s.slots;
    last_position_sum_ = sparse ? update_tracking_avx2(s, lowest_z_, next_bound2_) : update_avx2(s, lowest_z_);
    next_bound_fresh_ = sparse;
}

// The scalar step: the reference, and the code on a CPU without AVX2.
void Body3D::sub_step_baseline(int index) {
    // Local restrict pointers (as in transverse_network.cpp): the force stores cannot alias the
    // positions, so the compiler keeps them in registers. (The loops stay scalar: their sums keep the
    // scalar order; sub_step_avx2() vectorises them.)
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
    const double dt = sub_dt_ * dt_scale_, inv_dt = 1.0 / dt;   // x 1.0 (exact) but in a coarse step
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
    const bool energy = energy_limit_ < std::numeric_limits<double>::infinity();
    double kinetic2 = 0.0;   // twice the kinetic energy
    for (std::size_t i = 0; i < n; ++i) {
        const double v2 = vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i];
        const double drag = lin[i] + quad[i] * std::sqrt(v2);   // -c v - b |v| v = -(c + b |v|) v
        fx[i] = ex[i] + m[i] * gx - drag * vx[i];
        fy[i] = ey[i] + m[i] * gy - drag * vy[i];
        fz[i] = ez[i] + m[i] * gz - drag * vz[i];
        if (energy) kinetic2 += m[i] * v2;
    }

    // 2. Links: the uniform cohesive pass (a drop) or any links. (Their elastic energy is summed
    // whatever the limit: the scalar step is the reference, and its cost matters less.)
    const double elastic2 = uniform_cohesive_ ? uniform_cohesive_links(index) : generic_links(index);
    last_energy_ = energy ? 0.5 * (kinetic2 + elastic2) : 0.0;

    // 3. Update. Fixed points have 1/m = 0 and zero velocity, so both schemes leave them in place.
    // The coordinates' sum for the guard in four partial sums, sum[i % 4] (the AVX2 step's lanes).
    double sum[4] = {0.0, 0.0, 0.0, 0.0};
    double lowest = std::numeric_limits<double>::infinity();
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
            sum[i % 4] += nx + ny + nz;
            lowest = std::min(lowest, nz);
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
            sum[i % 4] += x[i] + y[i] + z[i];
            lowest = std::min(lowest, z[i]);
        }
    }
    last_position_sum_ = ((sum[0] + sum[1]) + sum[2]) + sum[3];
    lowest_z_ = lowest;
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
    // The cohesive branch of generic_links(), with the parameters hoisted.
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
                ++broken_count_;
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

// 2. Links, any kind (gather/scatter): s along u on a, -s u on b, added to the force accumulator in link
// order. The reference for the uniform pass above. Returns twice the elastic energy.
double Body3D::generic_links(int index) {
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
    const double* __restrict lk = stiffness_.data();
    const double* __restrict lz = damping_.data();
    const double* __restrict l0 = rest_.data();
    const double* __restrict lbreak = break_force_.data();
    const LinkKind* __restrict kind = kind_.data();
    std::uint8_t* __restrict broken = broken_.data();
    const double* __restrict core_len = core_length_.data();
    const double* __restrict core_k = core_stiffness_.data();
    double elastic2 = 0.0;   // twice the elastic energy
    for (std::size_t l = 0; l < links; ++l) {
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
                    ++broken_count_;
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
                ++broken_count_;
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
    return elastic2;
}

bool Body3D::step(int time_multiple) {
    event_count_ = 0;
    if (!finalized_) return false;   // built or changed since finalize(): nothing is sized to run
    if (time_multiple > 1 && integrator_ == Integrator::symplectic_euler) {
        // A coarse step (see the header): the same sub-steps with a k times longer step.
        dt_scale_ = static_cast<double>(time_multiple);
        for (int s = 0; s < stability_.sub_steps; ++s) sub_step(s);
        dt_scale_ = 1.0;
        since_look_ += time_multiple * stability_.time_step;
        since_bonds_ += time_multiple * stability_.time_step;
    } else {
        // CORDIS keeps x[n-1], tied to the sub-step: k ordinary steps (their breaks all listed).
        for (int k = 0; k < std::max(time_multiple, 1); ++k)
            for (int s = 0; s < stability_.sub_steps; ++s) sub_step(s);
        since_look_ += std::max(time_multiple, 1) * stability_.time_step;
        since_bonds_ += std::max(time_multiple, 1) * stability_.time_step;
    }
    // Held for this step only. Cleared only if apply_force() was called since the last clearing (collisions
    // touch a drop for a few steps of its life): otherwise they are all +0.0 already.
    if (external_forces_) {
        for (auto* a : {&ex_, &ey_, &ez_}) std::fill(a->begin(), a->end(), 0.0);
        external_forces_ = false;
    }
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
