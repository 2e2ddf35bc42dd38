// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// N identical transverse networks (a canopy's panels) stepped together as SIMD lanes: explicit Verlet
// or symplectic Euler, each lane bit-identical to its own TransverseNetwork.
//
// Interface:
//   LanedNetwork lanes;
//   LanedNetwork::supports(Integrator::explicit_verlet)     // true for the two explicit schemes
//   lanes.init(prototype, 8);               // 8 copies of a finalized TransverseNetwork (its arrays,
//                                           // stability report, sub-steps, guard options); allocates;
//                                           // throws std::invalid_argument for another integrator
//   lanes.set_portable_kernels(true);       // the baseline (SSE2) kernels even on AVX2 (tests)
//   lanes.set_kernel_ceiling(64);           // at most 16 (SSE2), 32 (AVX2) or 64 (AVX-512) byte vectors;
//                                           // the widest the CPU has below it is used (AVX-512 only for
//                                           // a multiple of 8 lanes); kernel_width() says which
//   LanedNetwork::set_default_kernel_ceiling(64);   // build phase, any thread: the ceiling init() gives
//                                           // a network not given one; 32 (AVX2) unless set: the
//                                           // AVX-512 kernels measured slower (laned_network.cpp)
//   ---- render phase: never allocates ----
//   lanes.apply_force(lane, mass, newtons); // for the next step
//   lanes.step(net_forces);                 // one output step of every lane; net_forces[lane], N
//   lanes.guard(lane); lanes.reset(lane); lanes.reset();
//   lanes.finite(lane), lanes.energy(lane), lanes.guard_resets(lane), lanes.guard_energy_limit(lane)
//   lanes.position(lane, m), lanes.velocity(lane, m)
//   lanes.positions(lane, out), lanes.velocities(lane, out)   // one network's masses, out[m]
//   lanes.positions(), lanes.velocities(out)  // every lane at once, node-major: [m * lanes() + lane]
//
// Layout: every state array is mass-major with the lane as the fastest index, x[m * lanes() + lane],
// lanes() = count rounded up to a multiple of 4 (the padding lanes are never forced and stay at rest).
// The networks share their arrays (masses, links, k, z), so each link is visited once for all lanes:
// its two masses' rows are contiguous runs of lanes() doubles, loaded and stored without gather or
// scatter, and no two lanes of one row can conflict. The loop over lanes vectorises (two doubles per
// SSE2 register in the baseline build; four per AVX2 register, or eight per AVX-512 register, in kernels
// compiled for AVX2 and AVX-512F whatever the build's target, picked at init() where the CPU has them, as
// core/body3d_step_avx2.cpp does; AVX-512, opt-in, when the lanes are a multiple of 8: the default
// canopy's 8 panels are then one register a row, half the vector operations of AVX2, yet it measured
// slower than AVX2 on the development machine, so AVX2 stays the default).
//
// Bit identity. Each lane performs exactly the IEEE operations of ExplicitVerlet::step /
// SymplecticEuler::step and TransverseNetwork::step (integrators/explicit_verlet.cpp, symplectic_euler.cpp,
// ../transverse_network.cpp) in the same order: the mass terms ext - k_a x - z_g v, the links in link
// order (each mass's accumulator receives its link forces in the same sequence), the update, the net
// force summed over masses in mass order then over sub-steps, the guard's impulse sum f^2 / m in mass
// order. +, -, *, / are correctly rounded whatever the vector width; nothing is reassociated (sums run
// along the masses within a lane, never across lanes); no FMA (SSE2 and AVX2 have none, and this code
// is built with -ffp-contract=off in case a build targets a CPU that has). So a canopy renders the same
// samples laned or not, on any x86-64 (tests/engine/core/integrators/laned_network_test.cpp checks
// every position, velocity and net force against per-panel TransverseNetworks, both kernel sets).
// The guard's finite() sum and energy() use the scalar code itself on one lane's values, gathered.

#include <cstdint>
#include <vector>

#include "engine/core/aligned_allocator.hpp"
#include "engine/core/transverse_network.hpp"

namespace ameoto {

class LanedNetwork {
public:
    static bool supports(Integrator integrator) { return conditionally_stable(integrator); }

    void init(const TransverseNetwork& prototype, int count);
    void set_portable_kernels(bool on) { set_kernel_ceiling(on ? 16 : default_kernel_ceiling()); }
    void set_kernel_ceiling(int bytes);
    int kernel_width() const { return width_; }   // bytes per vector of the kernels in use
    bool avx2_kernels() const { return width_ >= 32; }
    static void set_default_kernel_ceiling(int bytes);
    static int default_kernel_ceiling();

    void apply_force(int lane, int mass, double newtons) { ext_[at(lane, mass)] += newtons; }
    void step(double* net_forces);   // net_forces[0 .. count())

    bool guard(int lane);            // TransverseNetwork::guard() for one lane: true if it reset
    void reset(int lane);
    void reset();
    bool finite(int lane) const;
    double energy(int lane) const;   // J, TransverseNetwork::kinetic_plus_potential_energy()
    std::uint64_t guard_resets(int lane) const { return guards_[static_cast<std::size_t>(lane)].resets(); }
    double guard_energy_limit(int lane) const { return guards_[static_cast<std::size_t>(lane)].energy_limit(); }

    int count() const { return count_; }
    int lanes() const { return static_cast<int>(lanes_); }
    int mass_count() const { return static_cast<int>(n_); }
    double position(int lane, int m) const { return x_[at(lane, m)]; }
    double velocity(int lane, int m) const;
    void positions(int lane, double* out) const;
    void velocities(int lane, double* out) const;
    const double* positions() const { return x_.data(); }   // node-major (header)
    // Explicit Verlet: x one sub-step earlier, node-major; velocity = (x - previous) * inverse_dt(),
    // exactly as velocities() forms it (the far field fuses that pass with its own). nullptr for Euler.
    const double* previous_positions() const { return verlet_ ? second_.data() : nullptr; }
    double inverse_dt() const { return inverse_dt_; }
    void velocities(double* out) const;                      // node-major, every lane (padding: 0)
    const NetworkArrays& arrays() const { return arrays_; }
    const StabilityReport& stability() const { return stability_; }
    Integrator integrator() const { return stability_.integrator; }

private:
    // Rows start on cache lines (64 bytes: an AVX-512 row of 8 lanes is one line, never split).
    using Row = std::vector<double, AlignedAllocator<double, 64>>;
    std::size_t at(int lane, int m) const {
        return static_cast<std::size_t>(m) * lanes_ + static_cast<std::size_t>(lane);
    }
    void gather(const Row& from, int lane, double* out) const;

    NetworkArrays arrays_;
    StabilityReport stability_;
    std::vector<RuntimeGuard> guards_;
    int count_ = 0, sub_steps_ = 1, check_every_ = 0, since_check_ = 0;
    std::size_t n_ = 0, lanes_ = 4;
    double time_step_ = 0.0, dt_ = 0.0, inverse_dt_ = 0.0;
    bool verlet_ = true;
    int ceiling_ = 0, width_ = 16;   // set_kernel_ceiling (0: the default at init), the kernels' width
    // State, node-major: x_; second_ is x one sub-step earlier (Verlet) or the velocity (Euler).
    Row x_, second_, force_, velocity_, ext_;
    Row totals_, sub_totals_, impulses_;   // per lane
    mutable std::vector<double> lane_x_, lane_v_;          // one lane gathered (guard, energy)
};

}  // namespace ameoto
