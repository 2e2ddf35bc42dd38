// SPDX-License-Identifier: GPL-3.0-or-later
// Body3D's build phase (body3d.hpp, "Interface"): masses, links and their checks, drag settings,
// reserve() and clear() for reuse, and finalize(): the Gershgorin bounds and the sub-steps, the state
// reset() returns to, the event list, the choice of kernels, and the uniform cohesive pass's lists and
// scratch (build_link_scratch(), read by body3d_step_avx2.cpp, body3d_links_avx2.cpp and
// body3d_sparse_links.cpp). gershgorin_maxima() is shared with the coarse steps' look (body3d_coarse.cpp).
// Threads: whichever thread builds the body (a pooled body's owner, or the render thread for a pooled
// drop). add_*, reserve() and finalize() allocate, except that within a reserve()d capacity clear(),
// add_* and finalize() do not (drop_pool.hpp builds drops on the audio thread that way).
#include "engine/core/body3d.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
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

}  // namespace ameoto
