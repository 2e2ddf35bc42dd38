// SPDX-License-Identifier: GPL-3.0-or-later
// The canopy's air-loaded modes as resonators (air_canopy.hpp).
#include "engine/models/air_canopy.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <utility>

#include <Eigen/Eigenvalues>

#include "engine/core/integrators/mode_decay.hpp"
#include "engine/models/air_canopy_kernels.hpp"
#include "engine/models/air_loading.hpp"
#include "engine/models/air_loading_in_phase.hpp"
#include "engine/models/canopy.hpp"

namespace ameoto {

namespace {

// The whole canopy's mode k is in phase when every panel's part is panel 0's (block m = 0 of the
// panels' Fourier modes; the eigen-solve returns those, being simple, as such).
bool in_phase(const Eigen::VectorXd& shape, int panels, int nodes) {
    const Eigen::VectorXd first = shape.head(nodes);
    for (int p = 1; p < panels; ++p)
        if ((shape.segment(p * nodes, nodes) - first).norm() > 1e-6 * first.norm()) return false;
    return true;
}

struct Pole {
    double omega, rate;
    // Panel 0's part of the mode's shape (real, scaled to its residue) and of the force its extra air mass
    // puts on the air, Re (M_a(omega) - M_a(0)) times the shape: below. Every panel's is the same.
    Eigen::VectorXd shape, extra_force;
};

// The in-phase modes' poles with the compressible air mass: the canopy's block m = 0 (every panel alike)
// spanned by its in-phase modes psi (panel 0's parts; mass-normalised on M + M_a(0) over the canopy), in
// which the free motion q e^(i w t) obeys
//   T(w) q = (diag(w_k^2) + 2 i w diag(s_k) - w^2 (I + D(w))) q = 0,   D(w) = N psi' (M_a(w) - M_a(0)) psi,
// s_k the material's rates (classical damping, as the server's). A pole is a complex w with det T(w) = 0:
// the fixed point of w -> sqrt of the eigenvalue nearest the mode's w_k^2 of
// (I + D(w))^-1 (diag(w_k^2) + 2 i w diag(s_k)), D continued to the complex w (below), found by the
// secant. Its real part is the mode's frequency, its imaginary part the decay rate of its free
// ring (the -3 dB half-width of its response on the real axis: tested). Freezing D at the real part put the
// decays 8 % high (D grows with frequency). D couples the in-phase modes: the lowest two radiate through one
// net force, and the second's decay on its own shape alone was 16 /s where the block gives 7.7
// (docs/canopy-air.md). Without radiation, D's real part at the real frequency: the air's mass alone.
std::vector<Pole> in_phase_poles(const InPhaseAirMass& air, const Eigen::MatrixXd& psi, int panels, const Eigen::VectorXd& omega,
                                 const Eigen::VectorXd& material_rate, int wanted, bool radiate) {
    using cd = std::complex<double>;
    const auto n = psi.cols();
    std::vector<Pole> out;
    const Eigen::MatrixXcd shapes = psi.cast<cd>();
    // D at two real frequencies a mode's pole lies between (the compressible air lowers it 3-4 %), linear
    // between them and continued so to complex w: the interpolation is within 3e-4 of D there (D'' ~ 2 D /
    // w^2), 1e-5 of the pole's frequency and 3e-4 of its decay. Two of the block's 300-cell complex solves a
    // mode, not one for each of the secant's three or four steps.
    const auto projected = [&](const Eigen::MatrixXcd& change) {
        Eigen::MatrixXcd d = static_cast<double>(panels) * (shapes.transpose() * change * shapes);
        if (!radiate) d = d.real().cast<cd>();
        return d;
    };
    for (int j = 0; j < wanted; ++j) {
        const double w_low = 0.95 * omega[j], w_high = omega[j];
        const Eigen::MatrixXcd change_low = air.change_at(std::min(w_low, air.max_omega()));
        const Eigen::MatrixXcd change_high = air.change_at(std::min(w_high, air.max_omega()));
        const Eigen::MatrixXcd d_low = projected(change_low), d_high = projected(change_high);
        // The pole for mode j from D at w.
        const auto pole_at = [&](cd w) {
            const Eigen::MatrixXcd d = d_low + ((w - w_low) / (w_high - w_low)) * (d_high - d_low);
            Eigen::MatrixXcd stiffness = Eigen::MatrixXcd::Zero(n, n);
            for (Eigen::Index k = 0; k < n; ++k) stiffness(k, k) = omega[k] * omega[k] + cd(0.0, 2.0) * w * material_rate[k];
            const Eigen::MatrixXcd a = (Eigen::MatrixXcd::Identity(n, n) + d).partialPivLu().solve(stiffness);
            // The eigenvalue nearest w_j^2 by Rayleigh quotient iteration from mode j's own coordinate (the
            // block's modes are w_j's neighbours only through D, a few per cent): a 50 x 50 solve a round.
            Eigen::VectorXcd x = Eigen::VectorXcd::Zero(n);
            x[j] = 1.0;
            cd lambda = omega[j] * omega[j];
            for (int round = 0; round < 30; ++round) {
                const Eigen::VectorXcd y = (a - lambda * Eigen::MatrixXcd::Identity(n, n)).partialPivLu().solve(x);
                if (!y.allFinite()) break;   // lambda is an eigenvalue to the last bit
                x = y / y.norm();
                const cd next = x.dot(a * x);   // x^H A x, |x| = 1
                const bool settled = std::abs(next - lambda) <= 1e-14 * std::abs(next);
                lambda = next;
                if (settled) break;
            }
            if (!std::isfinite(lambda.real()) || !std::isfinite(lambda.imag()))
                throw std::runtime_error("air canopy: the in-phase poles' eigen-solve failed");
            const cd root = std::sqrt(lambda);
            return root.real() < 0.0 ? -root : root;
        };
        // The fixed point w = pole(w), by the secant on f(w) = pole(w) - w (analytic), to 1e-6 of w: the plain
        // iteration overshoots by a twelfth of its step each round.
        cd w0 = omega[j];
        cd f0 = pole_at(w0) - w0;
        cd w1 = w0 + f0;
        cd f1 = pole_at(w1) - w1;
        for (int round = 0; round < 12 && std::abs(f1) > 1e-6 * omega[j] && f1 != f0; ++round) {
            const cd w2 = w1 - f1 * (w1 - w0) / (f1 - f0);
            w0 = w1, f0 = f1;
            w1 = w2;
            f1 = pole_at(w1) - w1;
        }
        const cd pole = w1 + f1;
        // The mode's shape: the block's real eigenvector with the air's extra mass at the pole's frequency,
        // K x = lambda (I + Re D) x (the radiation stays in the pole), its coordinate j the largest. Near the
        // pole the block's response is x x' / (x' (dT/d(w^2)) x), and with D growing as w^2 that derivative
        // is I + Re D + w Re D' / 2 (about 1.13-1.17 here), so x is scaled to make it 1: its residue. The
        // incompressible shape misses the extra mass's coupling between the block's modes (the second
        // mode takes 0.115 of the first's shape), which a listener on the axis hears in the trough between
        // them (docs/canopy-air.md, "The in-phase modes' shapes").
        const double w_real = pole.real(), at = (w_real - w_low) / (w_high - w_low);
        const Eigen::MatrixXd d = (d_low + at * (d_high - d_low)).real();
        const Eigen::MatrixXd slope = (d_high - d_low).real() / (w_high - w_low);
        Eigen::MatrixXd stiffness = Eigen::MatrixXd::Zero(n, n);
        for (Eigen::Index k = 0; k < n; ++k) stiffness(k, k) = omega[k] * omega[k];
        const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solve(stiffness, Eigen::MatrixXd::Identity(n, n) + d);
        if (solve.info() != Eigen::Success) throw std::runtime_error("air canopy: the in-phase shapes' eigen-solve failed");
        Eigen::Index own = 0;
        solve.eigenvectors().row(j).cwiseAbs().maxCoeff(&own);
        Eigen::VectorXd x = solve.eigenvectors().col(own);
        x /= x[j];   // the incompressible shape's sign
        const double residue = x.dot((Eigen::MatrixXd::Identity(n, n) + d + (0.5 * w_real) * slope) * x);
        if (!(residue > 0.0)) throw std::runtime_error("air canopy: an in-phase shape's residue is not positive");
        x /= std::sqrt(residue);
        Eigen::VectorXd shape = psi * x;
        Eigen::VectorXd extra_force = (change_low + at * (change_high - change_low)).real() * shape;
        out.push_back({pole.real(), pole.imag(), std::move(shape), std::move(extra_force)});
    }
    return out;
}

}  // namespace

std::shared_ptr<const AirCanopyModes> build_air_canopy_modes(const Canopy& canopy, double time_step_s,
                                                             const AirCanopyOptions& o) {
    if (!(time_step_s > 0.0) || !std::isfinite(time_step_s)) throw std::invalid_argument("air canopy: the time step must be positive");
    if (!(o.air_density > 0.0 && o.air_density < 100.0)) throw std::invalid_argument("air canopy: air density outside 0..100 kg/m^3");
    if (!(o.speed_of_sound > 1.0 && o.speed_of_sound < 1e4)) throw std::invalid_argument("air canopy: speed of sound outside 1..1e4 m/s");
    if (!(o.max_frequency_hz > 0.0)) throw std::invalid_argument("air canopy: the cutoff must be positive");
    if (!(o.compressible_in_phase_ka >= 0.0 && o.compressible_in_phase_ka <= 10.0))
        throw std::invalid_argument("air canopy: the compressible poles' k a outside 0..10");
    const AddedMass added = canopy_added_mass(canopy, o.air_density, o.air_mass);
    const AirLoadedModes all = air_loaded_modes(canopy, added);
    Eigen::VectorXd radiation = Eigen::VectorXd::Zero(all.omega.size());
    if (o.radiation_damping) radiation = ameoto::radiation_damping(all, added, o.air_density, o.speed_of_sound);
    Eigen::VectorXd omega = all.omega, rate = all.damping_rate + radiation;
    Eigen::MatrixXd shapes = all.shapes;
    // Each mode's force on the air per unit q'' is M_a(0) phi_k, and the moved modes' add their extra mass's.
    Eigen::MatrixXd extra_force = Eigen::MatrixXd::Zero(all.shapes.rows(), all.shapes.cols());
    const double limit = o.compressible_in_phase_ka * o.speed_of_sound / canopy.geometry().radius_m;   // rad/s
    if (limit > 0.0 && all.omega.size() > 0 && all.omega[0] <= limit) {
        const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel();
        std::vector<Eigen::Index> index;   // the in-phase modes, ascending
        for (Eigen::Index k = 0; k < all.omega.size(); ++k)
            if (in_phase(all.shapes.col(k), panels, nodes)) index.push_back(k);
        int wanted = 0;
        while (wanted < static_cast<int>(index.size()) && all.omega[index[static_cast<std::size_t>(wanted)]] <= limit) ++wanted;
        if (wanted > 0) {
            Eigen::MatrixXd psi(nodes, static_cast<Eigen::Index>(index.size()));
            Eigen::VectorXd w(psi.cols()), s(psi.cols());
            for (Eigen::Index j = 0; j < psi.cols(); ++j) {
                const Eigen::Index k = index[static_cast<std::size_t>(j)];
                psi.col(j) = all.shapes.col(k).head(nodes);
                w[j] = all.omega[k];
                s[j] = all.damping_rate[k];
            }
            const InPhaseAirMass air(canopy, o.air_density, o.speed_of_sound, limit, o.air_mass);
            const std::vector<Pole> poles = in_phase_poles(air, psi, panels, w, s, wanted, o.radiation_damping);
            for (int j = 0; j < wanted; ++j) {
                const Eigen::Index k = index[static_cast<std::size_t>(j)];
                omega[k] = poles[static_cast<std::size_t>(j)].omega;
                rate[k] = poles[static_cast<std::size_t>(j)].rate;
                radiation[k] = o.radiation_damping ? rate[k] - all.damping_rate[k] : 0.0;   // the compressible air's share
                const Pole& pole = poles[static_cast<std::size_t>(j)];
                for (int p = 0; p < panels; ++p) {
                    shapes.col(k).segment(p * nodes, nodes) = pole.shape;
                    extra_force.col(k).segment(p * nodes, nodes) = pole.extra_force;
                }
            }
        }
    }

    auto m = std::make_shared<AirCanopyModes>();
    const auto n = static_cast<int>(all.omega.size());
    m->nodes = canopy.panel_count() * canopy.nodes_per_panel();
    m->modes_found = n;
    m->time_step_s = time_step_s;
    m->cutoff_hz = o.max_frequency_hz;
    std::vector<int> keep;
    for (int k = 0; k < n; ++k)   // ascending
        if (all.omega[k] <= 2.0 * constants::pi * o.max_frequency_hz) keep.push_back(k);
    const int kept = static_cast<int>(keep.size());
    m->modes = kept;
    m->omega.resize(kept);
    m->rate.resize(kept);
    m->radiation_rate.resize(kept);
    m->shape.assign(static_cast<std::size_t>(m->nodes) * static_cast<std::size_t>(kept), 0.0);
    m->air_force.resize(m->nodes, kept);
    const Eigen::MatrixXd force = added.matrix * shapes + extra_force;
    for (int j = 0; j < kept; ++j) {
        const int k = keep[static_cast<std::size_t>(j)];
        m->omega[j] = omega[k];
        m->radiation_rate[j] = radiation[k];
        m->rate[j] = rate[k];
        for (int i = 0; i < m->nodes; ++i) m->shape[static_cast<std::size_t>(i) * kept + j] = shapes(i, k);
        m->air_force.col(j) = force.col(k);
        const ModeDecay d = mode_decay(m->omega[j], m->rate[j], time_step_s);   // integrators/mode_decay.hpp
        m->t11.push_back(d.ec + m->rate[j] * d.es);
        m->t12.push_back(d.es);
        m->t21.push_back(-m->omega[j] * m->omega[j] * d.es);
        m->t22.push_back(d.ec - m->rate[j] * d.es);
    }
    m->contact_mass.assign(static_cast<std::size_t>(m->nodes), 0.0);
    for (int i = 0; i < m->nodes; ++i) {
        double mobility = 0.0;
        for (int j = 0; j < kept; ++j) {
            const double phi = m->shape[static_cast<std::size_t>(i) * kept + j];
            mobility += phi * phi;
        }
        // With every mode dropped a node cannot move: an infinitely heavy contact.
        m->contact_mass[static_cast<std::size_t>(i)] = mobility > 0.0 ? 1.0 / mobility : 1e300;
    }
    m->largest_shape.assign(static_cast<std::size_t>(kept), 0.0);
    for (int i = 0; i < m->nodes; ++i)
        for (int j = 0; j < kept; ++j)
            m->largest_shape[static_cast<std::size_t>(j)] =
                std::max(m->largest_shape[static_cast<std::size_t>(j)], std::abs(m->shape[static_cast<std::size_t>(i) * kept + j]));
    m->node_area.assign(added.area.data(), added.area.data() + added.area.size());
    // (M + M_a)^-1 = Phi Phi' over the kept modes (Phi' (M + M_a) Phi = I), so M_a (M + M_a)^-1 = (M_a Phi) Phi'.
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> phi(m->shape.data(), m->nodes, kept);
    m->instantaneous_push = m->air_force * phi.transpose();
    return m;
}

void AirCanopyState::init(const AirCanopyModes& m) {
    const auto n = static_cast<std::size_t>(m.modes);
    q_.assign(n, 0.0);
    qd_.assign(n, 0.0);
    p_.assign(n, 0.0);
    a_.assign(n, 0.0);
    omega2_.resize(n);
    const auto nodes = static_cast<std::size_t>(m.nodes);
    u_.assign(nodes, 0.0);
    v_.assign(nodes, 0.0);
    u_stamp_.assign(nodes, 0);
    v_stamp_.assign(nodes, 0);
    for (Forces* f : {&pending_, &taken_}) {
        f->node.assign(nodes, 0);
        f->newtons.assign(nodes, 0.0);
        f->count = 0;
    }
    forced_stamp_.assign(nodes, 0);
    steps_ = 1;
    kernels_ = &air_kernels();   // chosen here, in the build phase: the first call initialises a static
    for (std::size_t k = 0; k < n; ++k) omega2_[k] = m.omega[static_cast<Eigen::Index>(k)] * m.omega[static_cast<Eigen::Index>(k)];
}

void AirCanopyState::step(const AirCanopyModes& m) {
    // The step's generalised forces, phi_k' f, one projection per forced node (apply_force gathers them).
    double* const p = p_.data();
    const int n = m.modes;
    for (int j = 0; j < pending_.count; ++j) {
        const auto i = static_cast<std::size_t>(pending_.node[static_cast<std::size_t>(j)]);
        const double f = pending_.newtons[i];
        const double* row = m.shape.data() + i * static_cast<std::size_t>(n);
        for (int k = 0; k < n; ++k) p[k] += f * row[k];
    }
    kernels_->advance(static_cast<std::size_t>(m.modes), q_.data(), qd_.data(), p_.data(), a_.data(), m.t11.data(), m.t12.data(),
                          m.t21.data(), m.t22.data(), m.time_step_s, 1.0 / m.time_step_s);
    std::swap(pending_, taken_);   // the vectors' buffers trade places: no allocation
    pending_.clear();
    ++steps_;
}

bool AirCanopyState::finite() const {
    double s = 0.0;
    for (std::size_t k = 0; k < q_.size(); ++k) s += q_[k] + qd_[k];
    return std::isfinite(s);
}

void AirCanopyState::reset() {
    for (auto* v : {&q_, &qd_, &p_, &a_})
        for (double& x : *v) x = 0.0;
    pending_.clear();
    taken_.clear();
    ++steps_;
}

double AirCanopyState::energy() const {
    double e = 0.0;
    for (std::size_t k = 0; k < q_.size(); ++k) e += qd_[k] * qd_[k] + omega2_[k] * q_[k] * q_[k];
    return 0.5 * e;
}

}  // namespace ameoto
