// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/wet_impact.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/core/body3d_drag.hpp"
#include "engine/models/drop.hpp"
#include "engine/models/drop_pool.hpp"

namespace ameoto {
namespace {

constexpr double hold_depth = 3.0 / 7.0;   // A(1): the depth (in parcel diameters) the pulse ends at

// The pulse's integral, Phi(s) = 5/2 s^(3/2) - 3/2 s^(5/2) (impact_force.hpp's shape_integral).
double pulse_integral(double s) { return s * std::sqrt(s) * (2.5 - 1.5 * s); }

}  // namespace

const char* impact_model_name(ImpactModel model) { return model == ImpactModel::seed ? "seed" : "wet"; }

std::optional<ImpactModel> find_impact_model(std::string_view name) {
    if (name == "wet") return ImpactModel::wet;
    if (name == "seed") return ImpactModel::seed;
    return std::nullopt;
}

double ContactLaw::parcel(double mass_kg) const {
    if (model == ImpactModel::seed) return 0.0;
    return std::cbrt(6.0 * mass_kg / (constants::pi * liquid_density));
}

double ContactLaw::reach(double mass_kg) const {
    if (model == ImpactModel::seed) return 0.0;
    return std::min(0.5 * parcel(mass_kg), max_reach_m);
}

double wet_phase(double x) {
    if (!(x > 0.0)) return 0.0;
    if (!(x < hold_depth)) return 1.0;
    // A(s) = s - s^(5/2) + (3/7) s^(7/2) with s = t^2: a polynomial in t, increasing on [0, 1]
    // (dA/dt = 2 t b(t^2) > 0 for t < 1). Newton, kept inside a bracket that bisection narrows when a
    // step would leave it: converges in a few steps except right at the end (A - 3/7 ~ (1 - s)^3).
    double lo = 0.0, hi = 1.0, t = std::min(std::sqrt(x), 1.0);
    for (int i = 0; i < 60; ++i) {
        const double t2 = t * t, t3 = t2 * t, t5 = t3 * t2;
        const double a = t2 - t5 + hold_depth * t5 * t2 - x;
        if (a > 0.0) hi = t; else lo = t;
        const double da = 2.0 * t * (1.0 - 2.5 * t3 + 1.5 * t5);
        double next = da > 0.0 ? t - a / da : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::fabs(next - t) < 1e-14) {
            t = next;
            break;
        }
        t = next;
    }
    return std::min(t * t, 1.0);
}

ContactImpulse contact_impulse(const ContactLaw& law, double m1, double m2, double h, double v1, double v2,
                               double time_step_s) {
    return contact_impulse_of_parcel(law, law.parcel(m1), m1, m2, h, v1, v2, time_step_s);
}

ContactImpulse contact_impulse_of_parcel(const ContactLaw& law, double parcel_m, double m1, double m2, double h,
                                         double v1, double v2, double time_step_s) {
    ContactImpulse c;
    const double closing = v1 - v2;
    if (law.model == ImpactModel::seed) {
        // membrane_collision.hpp's exchange, operation for operation (the seed's bits).
        if (!(h <= 0.0)) return c;
        if (!(closing < 0.0)) return c;                                  // separating or resting
        if (-h >= time_step_s * -closing + law.skin_m) return c;         // under the surface (swept test)
        const double mu = std::isinf(m2) ? m1 : m1 * m2 / (m1 + m2);
        c.contact = true;
        c.impulse = -(1.0 + law.restitution) * mu * closing;
        c.dissipated = 0.5 * mu * (1.0 - law.restitution * law.restitution) * closing * closing;
        return c;
    }
    const double l = parcel_m;
    const double depth = std::min(0.5 * l, law.max_reach_m) - h;   // since the parcel's underside touched (reach)
    if (!(depth >= 0.0)) return c;
    if (!(closing < 0.0)) return c;
    const double w = -closing;
    if (depth >= hold_depth * l + time_step_s * w + law.skin_m) return c;   // under the surface
    const double mu = std::isinf(m2) ? m1 : m1 * m2 / (m1 + m2);
    const double s = wet_phase(depth / l);
    double impulse = mu * w;   // the pulse is over (or the hold depth reached): e = 0
    if (s < 1.0) {
        const double w0 = w / (1.0 - pulse_integral(s));   // the closing speed the parcel touched at
        const double s1 = std::min(1.0, s + time_step_s * w0 / l);
        impulse = std::min(m1 * w0 * (pulse_integral(s1) - pulse_integral(s)), mu * w);
    }
    const double w_after = w - impulse / mu;
    c.contact = true;
    c.impulse = impulse;
    c.dissipated = 0.5 * mu * (w * w - w_after * w_after);
    return c;
}

RigidImpact measure_rigid_impact(const RigidImpactSpec& spec) {
    if (!(spec.diameter_m > 0.0 && spec.diameter_m <= 8e-3)) throw std::invalid_argument("diameter must be in (0, 8 mm]");
    if (!(spec.sample_rate >= 8000.0 && spec.sample_rate <= 1e7))
        throw std::invalid_argument("sample rate must be 8 kHz to 10 MHz");
    if (!(spec.window_over_tau > 0.0) || !(spec.seconds >= 0.0)) throw std::invalid_argument("window must be positive");
    if (!(spec.speed_m_per_s >= 0.0 && std::isfinite(spec.speed_m_per_s))) throw std::invalid_argument("bad speed");
    if (std::string why = validate(spec.liquid); !why.empty()) throw std::invalid_argument(why);

    RigidImpact r;
    const double D = spec.diameter_m, T = 1.0 / spec.sample_rate;
    const double V = spec.speed_m_per_s > 0.0 ? spec.speed_m_per_s : arrival_speed(D, spec.liquid.density);
    ContactLaw law = spec.law;
    law.liquid_density = spec.liquid.density;

    DropPoolConfig pc;
    pc.capacity = 1;
    pc.max_diameter = std::max(D, 1e-3);
    pc.time_step = T;
    pc.max_sub_steps = 64;   // as drop_on_canopy.cpp
    pc.retire_below = -1e9;
    pc.max_lifetime = 0.0;
    pc.options.tilted = law.model == ImpactModel::wet;   // as drop_on_canopy.cpp's pool
    DropPool pool(pc);
    const int liquid = pool.add_liquid(spec.liquid);
    const DropCalibration cal = calibrate_drop(D, spec.liquid);
    const double reach = law.reach(cal.node_mass);
    // The lowest mass's parcel just touching the plane: its centre at its reach above it.
    if (!pool.spawn(D, liquid, Vec3{0.0, 0.0, pool.underside(D) + reach}, Vec3{0.0, 0.0, -V}, DragPreset::quadratic))
        throw std::invalid_argument("the drop could not be spawned");
    const int d = pool.active()[0];
    const int n = pool.mass_count(d);

    r.diameter_m = D;
    r.speed_m_per_s = V;
    r.sample_rate = spec.sample_rate;
    r.masses = n;
    r.mass_kg = cal.total_mass;

    const double tau = D / V;
    const int window = static_cast<int>(std::ceil(spec.window_over_tau * tau / T));
    const int steps = std::max(window + 8, static_cast<int>(std::ceil(spec.seconds / T)));
    r.force.assign(static_cast<std::size_t>(steps), 0.0);

    std::vector<double> z0(static_cast<std::size_t>(n));
    ImpactEnergy& e = r.energy;
    for (int m = 0; m < n; ++m) {
        const Vec3 v = pool.velocity(d, m);
        e.initial_kinetic += 0.5 * pool.mass(d, m) * dot(v, v);
        z0[static_cast<std::size_t>(m)] = pool.position(d, m).z;
    }
    const double g = constants::gravity;
    const double intact_drag = drag::drop_quadratic_drag(D) / n;
    constexpr double inf = std::numeric_limits<double>::infinity();

    for (int step = 0; step < steps; ++step) {
        double on_plane = 0.0;
        for (int m = 0; m < n; ++m) {
            const Vec3 p = pool.position(d, m), v = pool.velocity(d, m);
            const ContactImpulse c = contact_impulse(law, pool.mass(d, m), inf, p.z, v.z, 0.0, T);
            if (!c.contact) continue;
            pool.apply_force(d, m, Vec3{0.0, 0.0, c.impulse / T});
            on_plane += c.impulse / T;
            e.collision += c.dissipated;
        }
        r.force[static_cast<std::size_t>(step)] = on_plane;
        if (r.first_contact < 0 && on_plane > 0.0) r.first_contact = step;
        // Dissipation over the step, at the state it starts from (symplectic Euler's forces are those of
        // the start of each sub-step): the dampers z ((v_a - v_b) . u)^2 on bonded links, drag b |v|^3.
        if (pool.dormant(d)) {
            const Vec3 v = pool.velocity(d, 0);
            e.drag += T * n * intact_drag * std::pow(norm(v), 3);
        } else {
            const Body3D& body = pool.body(d);
            for (int m = 0; m < n; ++m) e.drag += T * body.quadratic_drag(m) * std::pow(norm(body.velocity(m)), 3);
            for (int l = 0; l < body.link_count(); ++l) {
                if (body.link_broken(l)) continue;
                const int a = body.link_a(l), b = body.link_b(l);
                const Vec3 axis = body.position(a) - body.position(b);
                const double len = norm(axis);
                if (!(len > 0.0)) continue;
                const double va = dot(body.velocity(a) - body.velocity(b), axis) / len;
                e.viscous += T * cal.damping * va * va;
            }
        }
        pool.step();
        if (!pool.dormant(d))
            for (const LinkBreak& b : pool.body(d).breaks()) e.broken += b.force * b.force / (2.0 * cal.stiffness);
    }

    // The pulse over the window from the first contact.
    if (r.first_contact >= 0) {
        const int end = std::min(steps, r.first_contact + window);
        double total = 0.0;
        for (int s = r.first_contact; s < end; ++s) {
            const double f = r.force[static_cast<std::size_t>(s)];
            total += f * T;
            if (f > r.peak_n) {
                r.peak_n = f;
                r.peak_time_s = (s - r.first_contact + 0.5) * T;
            }
        }
        r.impulse_n_s = total;
        // Where the cumulative impulse passes 5 % and 95 %, interpolated within its sample.
        auto crossing = [&](double fraction) {
            double sum = 0.0;
            for (int s = r.first_contact; s < end; ++s) {
                const double add = r.force[static_cast<std::size_t>(s)] * T;
                if (add > 0.0 && sum + add >= fraction * total)
                    return (s - r.first_contact + (fraction * total - sum) / add) * T;
                sum += add;
            }
            return (end - r.first_contact) * T;
        };
        r.length_s = crossing(0.95) - crossing(0.05);
    }

    // Where the energy is at the end.
    const Body3D& body = pool.body(d);
    e.kinetic = body.kinetic_energy();
    e.elastic = body.elastic_energy();
    for (int m = 0; m < n; ++m)
        e.gravity_work += body.mass(m) * g * (z0[static_cast<std::size_t>(m)] - body.position(m).z);
    std::vector<char> piece_touching(static_cast<std::size_t>(n), 0);
    for (int m = 0; m < n; ++m)
        if (body.position(m).z <= law.reach(body.mass(m)) + 1e-4)
            piece_touching[static_cast<std::size_t>(pool.piece_of(d, m))] = 1;
    for (int m = 0; m < n; ++m)
        if (!piece_touching[static_cast<std::size_t>(pool.piece_of(d, m))]) {
            const Vec3 v = body.velocity(m);
            e.kinetic_flying += 0.5 * body.mass(m) * dot(v, v);
        }
    r.pieces = pool.pieces(d);
    r.link_breaks = pool.stats().link_breaks;
    return r;
}

}  // namespace ameoto
