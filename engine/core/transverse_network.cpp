#include "engine/core/transverse_network.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

namespace ameoto {
namespace {

// The step's impulse energy for the guard (stability.hpp), sum f^2 / m, and the forces cleared, in one
// pass. Restrict parameters so it vectorises (integrators/explicit_verlet.cpp explains).
double take_forces(std::size_t n, double* __restrict f, const double* __restrict inv_m) {
    double s2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        s2 += f[i] * f[i] * inv_m[i];
        f[i] = 0.0;
    }
    return s2;
}

// The links in an order that keeps a gap between links sharing a mass, and keeps, for every mass, the
// order of the links that touch it. The explicit schemes add each link's force into f[a] and f[b] in
// link order; a link that reads f[a] right after the previous link stored it waits for that store
// (store-to-load forwarding, then the add: about 9 cycles) instead of overlapping with it, and a
// membrane's lattice is built node by node, so consecutive links mostly share a node (measured on the
// canopy's panels: the link loop was most of the canopy's step). Each mass still receives the same
// forces in the same order, so its sum, and every state bit, is unchanged (tested). Greedy list
// scheduling: a link is ready once every earlier link sharing a mass with it is placed; the earliest
// ready link whose masses no link among the last `gap` placed touches goes next, or, if the first
// `scan` ready links all share one, the earliest ready link.
std::vector<std::int32_t> interleaved_link_order(const NetworkArrays& a, int gap = 3, int scan = 32) {
    const std::size_t links = a.link_count(), masses = a.mass_count();
    std::vector<std::int32_t> start(masses + 1, 0), list(2 * links), head(masses, 0);
    for (std::size_t l = 0; l < links; ++l) {
        ++start[static_cast<std::size_t>(a.link_a[l]) + 1];
        ++start[static_cast<std::size_t>(a.link_b[l]) + 1];
    }
    for (std::size_t i = 0; i < masses; ++i) start[i + 1] += start[i];
    std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t l = 0; l < links; ++l) {
        list[static_cast<std::size_t>(fill[static_cast<std::size_t>(a.link_a[l])]++)] = static_cast<std::int32_t>(l);
        list[static_cast<std::size_t>(fill[static_cast<std::size_t>(a.link_b[l])]++)] = static_cast<std::int32_t>(l);
    }
    auto at_head = [&](std::int32_t mass, std::int32_t l) {
        const auto m = static_cast<std::size_t>(mass);
        return start[m] + head[m] < start[m + 1] && list[static_cast<std::size_t>(start[m] + head[m])] == l;
    };
    auto ready = [&](std::int32_t l) {
        const auto i = static_cast<std::size_t>(l);
        return at_head(a.link_a[i], l) && at_head(a.link_b[i], l);
    };
    std::set<std::int32_t> waiting;
    for (std::size_t l = 0; l < links; ++l)
        if (ready(static_cast<std::int32_t>(l))) waiting.insert(static_cast<std::int32_t>(l));
    std::vector<long> last(masses, -1000000);
    std::vector<std::int32_t> order;
    order.reserve(links);
    for (long t = 0; t < static_cast<long>(links); ++t) {
        std::int32_t pick = *waiting.begin();
        int looked = 0;
        for (const std::int32_t l : waiting) {
            if (++looked > scan) break;
            const auto i = static_cast<std::size_t>(l);
            if (t - last[static_cast<std::size_t>(a.link_a[i])] > gap && t - last[static_cast<std::size_t>(a.link_b[i])] > gap) {
                pick = l;
                break;
            }
        }
        waiting.erase(pick);
        order.push_back(pick);
        const auto i = static_cast<std::size_t>(pick);
        for (const std::int32_t mass : {a.link_a[i], a.link_b[i]}) {
            const auto m = static_cast<std::size_t>(mass);
            last[m] = t;
            ++head[m];
            if (start[m] + head[m] < start[m + 1]) {
                const std::int32_t next = list[static_cast<std::size_t>(start[m] + head[m])];
                if (ready(next)) waiting.insert(next);
            }
        }
    }
    return order;
}

NetworkArrays with_link_order(const NetworkArrays& a, const std::vector<std::int32_t>& order) {
    NetworkArrays r = a;
    for (std::size_t j = 0; j < order.size(); ++j) {
        const auto l = static_cast<std::size_t>(order[j]);
        r.link_a[j] = a.link_a[l];
        r.link_b[j] = a.link_b[l];
        r.link_stiffness[j] = a.link_stiffness[l];
        r.link_damping[j] = a.link_damping[l];
    }
    return r;
}

}  // namespace

int TransverseNetwork::add_mass(double mass_kg, double ground_damping) {
    if (!(mass_kg > 0.0) || !std::isfinite(mass_kg)) throw std::invalid_argument("mass must be positive and finite");
    arrays_.mass_kg.push_back(mass_kg);
    arrays_.inverse_mass.push_back(1.0 / mass_kg);
    arrays_.ground_damping.push_back(ground_damping);
    arrays_.anchor_stiffness.push_back(0.0);
    external_.push_back(0.0);
    return mass_count() - 1;
}

void TransverseNetwork::add_link(int a, int b, double stiffness, double damping) {
    if (a == b || a < 0 || b < 0 || a >= mass_count() || b >= mass_count())
        throw std::invalid_argument("link must join two distinct existing masses");
    arrays_.link_a.push_back(a);
    arrays_.link_b.push_back(b);
    arrays_.link_stiffness.push_back(stiffness);
    arrays_.link_damping.push_back(damping);
}

void TransverseNetwork::add_anchor(int a, double stiffness, double damping) {
    arrays_.anchor_stiffness.at(static_cast<std::size_t>(a)) += stiffness;
    arrays_.ground_damping.at(static_cast<std::size_t>(a)) += damping;
}

void TransverseNetwork::finalize(double time_step_s, const NetworkOptions& options) {
    if (!(time_step_s > 0.0) || !std::isfinite(time_step_s)) throw std::invalid_argument("time step must be positive");
    stability_ = assess_stability(arrays_, time_step_s, options.integrator, options.stability);
    if (stability_.refused) throw StabilityError(stability_.message);
    time_step_ = time_step_s;
    // The explicit schemes step a copy whose links are interleaved (interleaved_link_order: the same
    // bits, faster); everything else reads arrays_ in the order the links were added.
    stepping_ = arrays_;
    if (stability_.integrator == Integrator::explicit_verlet || stability_.integrator == Integrator::symplectic_euler)
        stepping_ = with_link_order(arrays_, interleaved_link_order(arrays_));
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: explicit_.init(arrays_, time_step_s, stability_.sub_steps); break;
        case Integrator::symplectic_euler: symplectic_.init(arrays_, time_step_s, stability_.sub_steps); break;
        case Integrator::trapezoidal: trapezoidal_.init(arrays_, time_step_s); break;
        case Integrator::backward_euler: backward_.init(arrays_, time_step_s); break;
        case Integrator::modal: modal_.init(arrays_, time_step_s, options.modal); break;
    }
    guard_.configure(options.guard, time_step_s);
    check_every_ = options.guard.check_every_steps;
    since_check_ = 0;
    std::fill(external_.begin(), external_.end(), 0.0);
}

double TransverseNetwork::step() {
    const double* ext = external_.data();
    double total = 0.0;
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: total = explicit_.step(stepping_, ext); break;
        case Integrator::symplectic_euler: total = symplectic_.step(stepping_, ext); break;
        case Integrator::trapezoidal: total = trapezoidal_.step(arrays_, ext); break;
        case Integrator::backward_euler: total = backward_.step(arrays_, ext); break;
        case Integrator::modal: total = modal_.step(arrays_, ext); break;
    }
    guard_.inject(time_step_ * std::sqrt(0.5 * take_forces(external_.size(), external_.data(), arrays_.inverse_mass.data())));
    if (check_every_ > 0 && ++since_check_ >= check_every_) {
        since_check_ = 0;
        if (guard()) total = 0.0;
    }
    return total;
}

bool TransverseNetwork::guard() {
    if (!guard_.exceeded(finite(), kinetic_plus_potential_energy())) return false;
    reset();
    guard_.count_reset();
    return true;
}

void TransverseNetwork::reset() {
    explicit_.reset();
    symplectic_.reset();
    trapezoidal_.reset();
    backward_.reset();
    modal_.reset();
    std::fill(external_.begin(), external_.end(), 0.0);
    guard_.clear();
}

bool TransverseNetwork::finite() const {
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: return explicit_.finite();
        case Integrator::symplectic_euler: return symplectic_.finite();
        case Integrator::trapezoidal: return trapezoidal_.finite();
        case Integrator::backward_euler: return backward_.finite();
        case Integrator::modal: return modal_.finite();
    }
    return false;
}

double TransverseNetwork::position(int m) const {
    const auto i = static_cast<std::size_t>(m);
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: return explicit_.position(i);
        case Integrator::symplectic_euler: return symplectic_.position(i);
        case Integrator::trapezoidal: return trapezoidal_.position(i);
        case Integrator::backward_euler: return backward_.position(i);
        case Integrator::modal: return modal_.position(i);
    }
    return 0.0;
}

double TransverseNetwork::velocity(int m) const {
    const auto i = static_cast<std::size_t>(m);
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: return explicit_.velocity(i);
        case Integrator::symplectic_euler: return symplectic_.velocity(i);
        case Integrator::trapezoidal: return trapezoidal_.velocity(i);
        case Integrator::backward_euler: return backward_.velocity(i);
        case Integrator::modal: return modal_.velocity(i);
    }
    return 0.0;
}

namespace {

// The integrator's own inline position(i) / velocity(i) in one loop (vectorised where they allow).
template <class Scheme>
void read_all(const Scheme& scheme, std::size_t n, double* __restrict out, bool velocity) {
    if (velocity) {
        for (std::size_t i = 0; i < n; ++i) out[i] = scheme.velocity(i);
    } else {
        for (std::size_t i = 0; i < n; ++i) out[i] = scheme.position(i);
    }
}

}  // namespace

void TransverseNetwork::positions(double* out) const {
    const std::size_t n = arrays_.mass_count();
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: read_all(explicit_, n, out, false); break;
        case Integrator::symplectic_euler: read_all(symplectic_, n, out, false); break;
        case Integrator::trapezoidal: read_all(trapezoidal_, n, out, false); break;
        case Integrator::backward_euler: read_all(backward_, n, out, false); break;
        case Integrator::modal: read_all(modal_, n, out, false); break;
    }
}

void TransverseNetwork::velocities(double* out) const {
    const std::size_t n = arrays_.mass_count();
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: read_all(explicit_, n, out, true); break;
        case Integrator::symplectic_euler: read_all(symplectic_, n, out, true); break;
        case Integrator::trapezoidal: read_all(trapezoidal_, n, out, true); break;
        case Integrator::backward_euler: read_all(backward_, n, out, true); break;
        case Integrator::modal: read_all(modal_, n, out, true); break;
    }
}

double TransverseNetwork::kinetic_plus_potential_energy() const {
    switch (stability_.integrator) {
        case Integrator::explicit_verlet: return explicit_.energy(arrays_);
        case Integrator::symplectic_euler: return symplectic_.energy(arrays_);
        case Integrator::trapezoidal: return trapezoidal_.energy(arrays_);
        case Integrator::backward_euler: return backward_.energy(arrays_);
        case Integrator::modal: return modal_.energy(arrays_);
    }
    return 0.0;
}

}  // namespace ameoto
