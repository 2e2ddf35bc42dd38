// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/integrators/laned_network.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include "engine/core/cpu_features.hpp"

namespace ameoto {
namespace {

// What the kernels read and write (laned_kernels.inc): the shared network arrays and the node-major state.
struct LanedView {
    std::size_t n = 0, lanes = 0, links = 0;
    int sub_steps = 1;
    const std::int32_t *la = nullptr, *lb = nullptr;
    const double *lk = nullptr, *lz = nullptr, *ka = nullptr, *zg = nullptr, *inv_m = nullptr;
    double *x = nullptr, *second = nullptr, *force = nullptr, *velocity = nullptr, *ext = nullptr;
    double *total = nullptr, *sub_total = nullptr, *impulse = nullptr;   // per lane
    double dt = 0.0, inv_dt = 0.0;
};

using LanedKernel = void (*)(const LanedView&);

namespace baseline {
constexpr std::size_t kVectorBytes = 16;   // SSE2, in every x86-64
#include "engine/core/integrators/laned_kernels.inc"
}  // namespace baseline

}  // namespace

// The same kernels compiled for AVX2 whatever the build's target: called only where init() found AVX2.
#pragma GCC push_options
#pragma GCC target("avx2")
namespace {
namespace avx2 {
constexpr std::size_t kVectorBytes = 32;
#include "engine/core/integrators/laned_kernels.inc"
}  // namespace avx2
}  // namespace
#pragma GCC pop_options

// And for AVX-512 (eight doubles a register: the default canopy's 8 panels in one), called only where
// init() found AVX-512F and the lanes are a multiple of 8 (pick_kernel). The same element-wise IEEE
// operations as the other two sets (vaddpd, vsubpd, vmulpd, vdivpd are correctly rounded at any width;
// no FMA: -ffp-contract=off), so the same bits.
#pragma GCC push_options
#pragma GCC target("avx512f")
namespace {
namespace avx512 {
constexpr std::size_t kVectorBytes = 64;
#include "engine/core/integrators/laned_kernels.inc"
}  // namespace avx512
}  // namespace
#pragma GCC pop_options

namespace {

// The widest kernels allowed by the ceiling, the CPU and the lane count (a row must be whole vectors).
int kernel_width_for(int ceiling_bytes, std::size_t lanes) {
    if (ceiling_bytes >= 64 && lanes % 8 == 0 && cpu_has_avx512f()) return 64;
    if (ceiling_bytes >= 32 && cpu_has_avx2()) return 32;
    return 16;
}

LanedKernel pick_kernel(int width_bytes, bool verlet, std::size_t lanes) {
    if (width_bytes == 64) return avx512::pick(verlet, lanes);
    if (width_bytes == 32) return avx2::pick(verlet, lanes);
    return baseline::pick(verlet, lanes);
}

// AVX2 by default: the AVX-512 kernels, the same bits, ran slower on the development machine (an
// Emerald Rapids KVM guest: the canopy alone 1 816 ns a sample against 1 427 with AVX2, bench drop,
// 2026-12-02; cache-line aligned rows did not change that), so they are opt-in (ceiling 64).
std::atomic<int> default_ceiling{32};

}  // namespace

void LanedNetwork::set_default_kernel_ceiling(int bytes) { default_ceiling.store(bytes); }
int LanedNetwork::default_kernel_ceiling() { return default_ceiling.load(); }

void LanedNetwork::init(const TransverseNetwork& prototype, int count) {
    if (!supports(prototype.integrator()))
        throw std::invalid_argument("laned networks run explicit Verlet or symplectic Euler only");
    if (count < 1) throw std::invalid_argument("at least one lane");
    arrays_ = prototype.arrays();
    stability_ = prototype.stability();
    count_ = count;
    n_ = arrays_.mass_count();
    lanes_ = (static_cast<std::size_t>(count) + 3) / 4 * 4;
    verlet_ = stability_.integrator == Integrator::explicit_verlet;
    sub_steps_ = std::max(1, stability_.sub_steps);
    time_step_ = stability_.time_step;
    // As ExplicitVerlet::init / SymplecticEuler::init compute them (the same bits).
    dt_ = time_step_ / sub_steps_;
    inverse_dt_ = 1.0 / dt_;
    guards_.assign(static_cast<std::size_t>(count), RuntimeGuard{});
    for (RuntimeGuard& g : guards_) g.configure(prototype.guard_options(), time_step_);
    check_every_ = prototype.guard_options().check_every_steps;
    since_check_ = 0;
    const std::size_t cells = n_ * lanes_;
    x_.assign(cells, 0.0);
    second_.assign(cells, 0.0);
    force_.assign(cells, 0.0);
    velocity_.assign(cells, 0.0);
    ext_.assign(cells, 0.0);
    totals_.assign(lanes_, 0.0);
    sub_totals_.assign(lanes_, 0.0);
    impulses_.assign(lanes_, 0.0);
    lane_x_.assign(n_, 0.0);
    lane_v_.assign(n_, 0.0);
    if (ceiling_ == 0) ceiling_ = default_kernel_ceiling();
    set_kernel_ceiling(ceiling_);
}

void LanedNetwork::set_kernel_ceiling(int bytes) {
    ceiling_ = bytes;
    width_ = kernel_width_for(bytes, lanes_);
}

void LanedNetwork::step(double* net_forces) {
    LanedView v;
    v.n = n_;
    v.lanes = lanes_;
    v.links = arrays_.link_count();
    v.sub_steps = sub_steps_;
    v.la = arrays_.link_a.data();
    v.lb = arrays_.link_b.data();
    v.lk = arrays_.link_stiffness.data();
    v.lz = arrays_.link_damping.data();
    v.ka = arrays_.anchor_stiffness.data();
    v.zg = arrays_.ground_damping.data();
    v.inv_m = arrays_.inverse_mass.data();
    v.x = x_.data();
    v.second = second_.data();
    v.force = force_.data();
    v.velocity = velocity_.data();
    v.ext = ext_.data();
    v.total = totals_.data();
    v.sub_total = sub_totals_.data();
    v.impulse = impulses_.data();
    v.dt = dt_;
    v.inv_dt = inverse_dt_;
    pick_kernel(width_, verlet_, lanes_)(v);
    // TransverseNetwork::step()'s guard bookkeeping, lane by lane.
    for (int k = 0; k < count_; ++k) {
        const auto j = static_cast<std::size_t>(k);
        guards_[j].inject(time_step_ * std::sqrt(0.5 * impulses_[j]));
        net_forces[k] = totals_[j];
    }
    if (check_every_ > 0 && ++since_check_ >= check_every_) {
        since_check_ = 0;
        for (int k = 0; k < count_; ++k)
            if (guard(k)) net_forces[k] = 0.0;
    }
}

bool LanedNetwork::guard(int lane) {
    RuntimeGuard& g = guards_[static_cast<std::size_t>(lane)];
    if (!g.exceeded(finite(lane), energy(lane))) return false;
    reset(lane);
    g.count_reset();
    return true;
}

void LanedNetwork::reset(int lane) {
    for (std::size_t i = 0; i < n_; ++i) {
        const std::size_t c = at(lane, static_cast<int>(i));
        x_[c] = 0.0;
        second_[c] = 0.0;
        ext_[c] = 0.0;
    }
    guards_[static_cast<std::size_t>(lane)].clear();
}

void LanedNetwork::reset() {
    for (int k = 0; k < count_; ++k) reset(k);
}

// ExplicitVerlet::finite / SymplecticEuler::finite: the sum of x and the second state in mass order.
bool LanedNetwork::finite(int lane) const {
    double sum = 0.0;
    for (std::size_t i = 0; i < n_; ++i) {
        const std::size_t c = at(lane, static_cast<int>(i));
        sum += x_[c] + second_[c];
    }
    return std::isfinite(sum);
}

double LanedNetwork::energy(int lane) const {
    gather(x_, lane, lane_x_.data());
    velocities(lane, lane_v_.data());
    return arrays_.energy(lane_x_.data(), lane_v_.data());
}

double LanedNetwork::velocity(int lane, int m) const {
    const std::size_t c = at(lane, m);
    return verlet_ ? (x_[c] - second_[c]) * inverse_dt_ : second_[c];
}

void LanedNetwork::gather(const Row& from, int lane, double* out) const {
    for (std::size_t i = 0; i < n_; ++i) out[i] = from[i * lanes_ + static_cast<std::size_t>(lane)];
}

void LanedNetwork::positions(int lane, double* out) const { gather(x_, lane, out); }

void LanedNetwork::velocities(int lane, double* out) const {
    if (!verlet_) {
        gather(second_, lane, out);
        return;
    }
    for (std::size_t i = 0; i < n_; ++i) {
        const std::size_t c = i * lanes_ + static_cast<std::size_t>(lane);
        out[i] = (x_[c] - second_[c]) * inverse_dt_;
    }
}

namespace {

// Restrict parameters so the loop vectorises (laned_kernels.inc explains).
void backward_difference(std::size_t cells, const double* __restrict x, const double* __restrict xp, double inv_dt,
                         double* __restrict out) {
    for (std::size_t c = 0; c < cells; ++c) out[c] = (x[c] - xp[c]) * inv_dt;
}

}  // namespace

void LanedNetwork::velocities(double* out) const {
    if (verlet_) {
        backward_difference(x_.size(), x_.data(), second_.data(), inverse_dt_, out);
    } else {
        std::copy(second_.begin(), second_.end(), out);
    }
}

}  // namespace ameoto
