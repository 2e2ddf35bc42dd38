// SPDX-License-Identifier: GPL-3.0-or-later
// The air reference's validations: see validations.hpp and docs/air-reference.md.
#include "engine/reference/validations.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"
#include "engine/reference/air_solver.hpp"
#include "engine/reference/spectrum.hpp"

namespace ameoto::reference {

namespace {

constexpr double pi = constants::pi;

// Gives the faces whose centres lie within `radius` of the axis to `owner`; returns how many.
int disc_faces(AirSolver& air, double radius, int owner) {
    int count = 0;
    for (int j = 0; j < air.grid().ny; ++j)
        for (int i = 0; i < air.grid().nx; ++i)
            if (std::hypot(air.face_x(i), air.face_y(j)) < radius) {
                air.set_face(i, j, owner);
                ++count;
            }
    return count;
}

double db(double x) { return 20.0 * std::log10(x); }

struct Pulse {   // exp(-((t - t0) / tau)^2): spectrum exp(-(omega tau / 2)^2), down to 2 % at omega_max
    double tau, t0;
    explicit Pulse(double omega_max) : tau(4.0 / omega_max), t0(4.0 * tau) {}
    double operator()(double t) const { return std::exp(-((t - t0) / tau) * ((t - t0) / tau)); }
    double derivative(double t) const { return -2.0 * (t - t0) / (tau * tau) * (*this)(t); }
    double end() const { return t0 + 4.0 * tau; }
};

}  // namespace

double PistonResult::worst_error_db() const {
    double worst = 0.0;
    for (const auto& q : points) worst = std::max(worst, std::abs(q.error_db()));
    return worst;
}

double DiscResult::worst_error_db() const {
    double worst = 0.0;
    for (const auto& q : points) worst = std::max(worst, std::abs(q.error_db()));
    return worst;
}

PistonResult baffled_piston(const PistonSetup& setup) {
    const double a = setup.radius_m, dx = a / setup.cells_per_radius, z = setup.listener_over_radius * a;
    const double half = a * (1.0 + setup.margin_over_radius);
    GridSpec g = GridSpec::box(dx, half, half, dx, z + 0.5 * a, setup.pml_cells, false);
    ScreenStructure s;
    s.add_dof(1.0, true);
    AirSolver air(g, s);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) air.set_face(i, j, AirSolver::rigid);   // the baffle
    const int faces = disc_faces(air, a, 0);
    PistonResult r;
    r.dx = dx;
    r.effective_radius = std::sqrt(faces / pi) * dx;
    r.listener_z = z;
    r.cells = static_cast<long>(air.cells());
    const double c = air.sound_speed(), rho = air.density(), dt = air.time_step();
    const Pulse pulse(1.1 * setup.ka_high * c / r.effective_radius);
    const double t_end = pulse.end() + std::hypot(z, a) / c + 6.0 * a / c;
    const int listener = air.add_probe(0.0, 0.0, z), piston = air.add_dof_probe(0);
    while (air.time() < t_end) {
        air.prescribe_velocity(0, pulse(air.time() + 0.5 * dt));
        air.step();
    }
    r.steps = air.steps();
    const std::vector<double>& u = air.dof_probe_velocity(piston);
    const std::vector<double>& p = air.probe(listener);
    const double ae = r.effective_radius, R = std::hypot(z, ae);
    for (double ka = setup.ka_low; ka <= setup.ka_high + 1e-9; ka += setup.ka_step) {
        const double k = ka / ae, f = k * c / (2.0 * pi);
        const auto P = fourier_at(p, dt, dt, f), U = fourier_at(u, dt, 0.5 * dt, f);
        const double analytic = 2.0 * rho * c * std::abs(std::sin(0.5 * k * (R - z)));
        r.points.push_back({ka, db(std::abs(P / U)), db(analytic)});
    }
    return r;
}

DiscResult rigid_disc(const DiscSetup& setup) {
    const double a = setup.radius_m, dx = a / setup.cells_per_radius, rz = setup.listener_over_radius * a;
    const double half = a * (1.0 + setup.margin_over_radius);
    const GridSpec g = GridSpec::box(dx, half, half, setup.margin_over_radius * a, rz + 0.5 * a, setup.pml_cells);
    DiscResult r;
    r.dx = dx;
    r.listener_r = rz;
    auto run = [&](double disc_mass, std::vector<double>& u, std::vector<double>& force, std::vector<double>* p) {
        ScreenStructure s;
        s.add_dof(disc_mass > 0.0 ? disc_mass : 1.0, !(disc_mass > 0.0));
        AirSolver air(g, s);
        const int faces = disc_faces(air, a, 0);
        r.effective_radius = std::sqrt(faces / pi) * dx;
        r.cells = static_cast<long>(air.cells());
        const double c = air.sound_speed(), dt = air.time_step();
        const Pulse pulse(1.2 * setup.ka_high * c / r.effective_radius);
        const double t_end = pulse.end() + rz / c + 6.0 * a / c;
        while (air.time() < t_end) {
            if (disc_mass > 0.0) {   // a force of no net impulse: the free disc ends at rest
                const double f = pulse.derivative(air.time()) * pulse.tau;
                air.set_external_force(0, f);
                force.push_back(f);
            } else {
                air.prescribe_velocity(0, pulse(air.time() + 0.5 * dt));
            }
            air.step();
            u.push_back(air.dof_velocity(0));
            if (!(disc_mass > 0.0)) force.push_back(air.dof_air_force(0));
            if (p) p->push_back(air.pressure_at(0.0, 0.0, rz));
        }
        r.steps = air.steps();
        return dt;
    };
    std::vector<double> u, force, p;
    const double dt = run(0.0, u, force, &p);
    const double c = constants::speed_of_sound_air, rho = constants::air_density;
    const double ae = r.effective_radius;
    r.lamb_mass = 8.0 / 3.0 * rho * ae * ae * ae;
    auto added_mass = [&](const std::vector<double>& uu, const std::vector<double>& ff, double ka) {
        const double w = ka * c / ae, f = w / (2.0 * pi);
        // u: the mean over step n (t_n + dt/2); the air's force: from p at t_n.
        return -std::imag(fourier_at(ff, dt, 0.0, f) / fourier_at(uu, dt, 0.5 * dt, f)) / w;
    };
    r.added_mass = added_mass(u, force, setup.mass_ka);
    for (double ka = setup.ka_low * 0.5; ka <= setup.ka_high + 1e-9; ka += setup.ka_step) {
        r.mass_ka.push_back(ka);
        r.mass_ratio.push_back(added_mass(u, force, ka) / r.lamb_mass);
    }
    for (double ka = setup.ka_low; ka <= setup.ka_high + 1e-9; ka += setup.ka_step) {
        const double k = ka / ae, f = k * c / (2.0 * pi);
        const auto P = fourier_at(p, dt, dt, f), U = fourier_at(u, dt, 0.5 * dt, f);
        const double near = std::abs(1.0 + 1.0 / std::complex<double>(0.0, k * rz));
        const double analytic = rho * c * 2.0 / (3.0 * pi) * k * k * ae * ae * ae / rz * near;
        r.points.push_back({ka, db(std::abs(P / U)), db(analytic)});
    }
    if (setup.disc_mass_kg > 0.0) {
        std::vector<double> u2, f2;
        run(setup.disc_mass_kg, u2, f2, nullptr);
        const double w = setup.mass_ka * c / ae, f = w / (2.0 * pi);
        // (M + m) i omega U = F: F at t_n held over step n, U the mean over it.
        const auto ratio = fourier_at(f2, dt, 0.0, f) / (std::complex<double>(0.0, w) * fourier_at(u2, dt, 0.5 * dt, f));
        r.force_driven_added_mass = std::real(ratio) - setup.disc_mass_kg;
    }
    return r;
}

TimpaniResult timpani(const TimpaniSetup& setup) {
    const double a = setup.radius_m, dx = a / setup.cells_per_radius;
    const double half = a * (1.0 + setup.margin_xy_over_radius), hz = a * setup.margin_z_over_radius;
    const GridSpec g = GridSpec::box(dx, half, half, hz, hz, setup.pml_cells);
    // The head on the screen's faces: a DOF per face inside the rim, springs T between neighbours (the
    // 5-point Laplacian: s dx^2 u_tt = T sum (u_j - u_i)), anchors of T across the rim.
    std::vector<int> dof(static_cast<std::size_t>(g.nx * g.ny), -1);
    auto fx = [&](int i) { return (i + 0.5 - g.nx / 2) * dx; };
    auto fy = [&](int j) { return (j + 0.5 - g.ny / 2) * dx; };
    ScreenStructure s;
    std::vector<double> radius, angle;
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i)
            if (std::hypot(fx(i), fy(j)) < a) {
                dof[static_cast<std::size_t>(j * g.nx + i)] = s.add_dof(setup.areal_density * dx * dx);
                radius.push_back(std::hypot(fx(i), fy(j)));
                angle.push_back(std::atan2(fy(j), fx(i)));
            }
    auto at = [&](int i, int j) { return dof[static_cast<std::size_t>(j * g.nx + i)]; };
    for (int j = 1; j + 1 < g.ny; ++j)
        for (int i = 1; i + 1 < g.nx; ++i) {
            const int d = at(i, j);
            if (d < 0) continue;
            const int nb[4] = {at(i + 1, j), at(i - 1, j), at(i, j + 1), at(i, j - 1)};
            for (int q = 0; q < 4; ++q) {
                if (nb[q] < 0) s.add_spring(d, -1, setup.tension);
                else if (q % 2 == 0) s.add_spring(d, nb[q], setup.tension);
            }
        }
    static constexpr double bessel_zero[5] = {3.831705970, 5.135622302, 6.380161896, 7.588342435, 8.771483816};
    const std::size_t n = radius.size();
    std::vector<std::vector<double>> weight(5, std::vector<double>(n));
    s.initial_displacement.assign(n, 0.0);
    for (int m = 1; m <= 5; ++m)
        for (std::size_t d = 0; d < n; ++d) {
            weight[static_cast<std::size_t>(m - 1)][d] =
                std::cyl_bessel_j(static_cast<double>(m), bessel_zero[m - 1] * radius[d] / a) * std::cos(m * angle[d]);
            s.initial_displacement[d] += 1e-3 * weight[static_cast<std::size_t>(m - 1)][d];
        }
    TimpaniResult r;
    r.dx = dx;
    const double dt = g.time_step();
    const long steps = static_cast<long>(std::ceil(setup.duration_s / dt));
    auto project = [&](auto&& displacement, std::vector<std::vector<double>>& q) {
        for (int m = 0; m < 5; ++m) {
            double sum = 0.0;
            for (std::size_t d = 0; d < n; ++d) sum += weight[static_cast<std::size_t>(m)][d] * displacement(static_cast<int>(d));
            q[static_cast<std::size_t>(m)].push_back(sum);
        }
    };
    std::vector<std::vector<double>> vac(5), air_q(5);
    {
        StructureStepper vacuum(s, dt);
        const std::vector<double> zero(n, 0.0);
        for (long q = 0; q < steps; ++q) {
            vacuum.step(zero.data());
            project([&](int d) { return vacuum.displacement(d); }, vac);
        }
    }
    {
        AirSolver air(g, s);
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i)
                if (at(i, j) >= 0) air.set_face(i, j, at(i, j));
        air.set_air_loading(setup.air);
        r.cells = static_cast<long>(air.cells());
        for (long q = 0; q < steps; ++q) {
            air.step();
            project([&](int d) { return air.dof_displacement(d); }, air_q);
        }
        r.steps = air.steps();
    }
    const double wave = std::sqrt(setup.tension / setup.areal_density);
    for (int m = 0; m < 5; ++m) {
        const double estimate = bessel_zero[m] * wave / (2.0 * pi * a);
        r.vacuum_hz[m] = peak_frequency(vac[static_cast<std::size_t>(m)], dt, 0.8 * estimate, 1.1 * estimate);
        r.air_hz[m] = peak_frequency(air_q[static_cast<std::size_t>(m)], dt, 0.45 * r.vacuum_hz[m], 1.02 * r.vacuum_hz[m]);
    }
    return r;
}

ReflectionResult layer_reflection(const ReflectionSetup& setup) {
    const double dx = setup.dx;
    const double c = constants::speed_of_sound_air;
    // A soft source: the pulse's derivative added to one cell (no net volume, so no static pressure).
    const Pulse pulse(0.6 * c / dx);
    const int reach = setup.half_cells - 2;   // listeners 2 cells inside the layer
    const double dt = GridSpec{}.courant * dx / c;
    const double window = pulse.end() + (reach * std::sqrt(2.0) + 2.0 * (setup.pml_cells + 2)) * dx / c;
    auto run = [&](int half, std::vector<double>& normal, std::vector<double>& oblique) {
        GridSpec g;
        g.dx = dx;
        g.pml_cells = setup.pml_cells;
        g.pml_reflection = setup.pml_reflection;
        g.nx = g.ny = g.nz = 2 * (half + setup.pml_cells);
        AirSolver air(g);
        const int o = g.nx / 2;
        while (air.time() < window) {
            air.add_pressure(o, o, o, pulse.derivative(air.time()) * pulse.tau);
            air.step();
            normal.push_back(air.cell_pressure(o + reach, o, o));
            oblique.push_back(air.cell_pressure(o + reach, o + reach, o));
        }
        return static_cast<long>(air.cells());
    };
    std::vector<double> n1, o1, n2, o2;
    ReflectionResult r;
    r.cells = run(setup.half_cells, n1, o1);
    // The reference box: its own layer is farther than the window's travel.
    run(static_cast<int>(std::ceil(0.5 * (window * c / dx + reach * std::sqrt(2.0)))) + 2, n2, o2);
    auto worst = [](const std::vector<double>& x, const std::vector<double>& ref) {
        double diff = 0.0, peak = 0.0;
        for (std::size_t q = 0; q < x.size(); ++q) {
            diff = std::max(diff, std::abs(x[q] - ref[q]));
            peak = std::max(peak, std::abs(ref[q]));
        }
        return db(diff / peak);
    };
    r.normal_db = worst(n1, n2);
    r.oblique_db = worst(o1, o2);
    (void)dt;
    return r;
}

}  // namespace ameoto::reference
