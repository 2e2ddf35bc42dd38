// SPDX-License-Identifier: GPL-3.0-or-later
// The canopy in air in the frequency domain: see canopy_frequency_response.hpp.
#include "engine/reference/canopy_frequency_response.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"
#include "engine/models/air_loading.hpp"
#include "engine/models/air_loading_helmholtz.hpp"
#include "engine/models/canopy.hpp"

namespace ameoto::reference {

using cd = std::complex<double>;

AirMassAt compressible_air_mass(const Canopy& canopy, double air_density, double speed_of_sound, double step_hz) {
    if (!(step_hz > 0.0)) throw std::invalid_argument("compressible_air_mass: the step must be positive");
    auto cache = std::make_shared<std::map<long, std::vector<Eigen::MatrixXcd>>>();
    auto builder = std::make_shared<CanopyAirImpedanceBuilder>(canopy, air_density, speed_of_sound);
    auto at = [cache, builder, step_hz](long i) -> const std::vector<Eigen::MatrixXcd>& {
        auto it = cache->find(i);
        if (it == cache->end()) it = cache->emplace(i, builder->at(2.0 * constants::pi * step_hz * i).fourier).first;
        return it->second;
    };
    return [at, step_hz](double omega) {
        const double x = omega / (2.0 * constants::pi * step_hz);
        const long i = static_cast<long>(std::floor(x));
        const double t = x - i;
        const auto& a = at(i);
        if (t == 0.0) return a;
        const auto& b = at(i + 1);
        std::vector<Eigen::MatrixXcd> out(a.size());
        for (std::size_t m = 0; m < a.size(); ++m) out[m] = (1.0 - t) * a[m] + t * b[m];
        return out;
    };
}

AirMassAt incompressible_air_mass(const Canopy& canopy, double air_density) {
    const AddedMass a = canopy_added_mass(canopy, air_density);
    const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel();
    std::vector<Eigen::MatrixXcd> fourier(static_cast<std::size_t>(panels), Eigen::MatrixXcd::Zero(nodes, nodes));
    // Block (0, d) of the circulant matrix is block d; mode m is sum_d e^(i theta_m d) block d.
    for (int m = 0; m < panels; ++m)
        for (int d = 0; d < panels; ++d)
            fourier[static_cast<std::size_t>(m)] +=
                std::polar(1.0, 2.0 * constants::pi * m * d / panels) * a.matrix.block(0, d * nodes, nodes, nodes).cast<cd>();
    return [fourier](double) { return fourier; };
}

std::vector<cd> canopy_air_forces(const Canopy& canopy, int panel, int node, double hz, const AirMassAt& air) {
    const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel();
    if (panel < 0 || panel >= panels || node < 0 || node >= nodes) throw std::invalid_argument("canopy_air_forces: no such node");
    const auto& arrays = canopy.panel(0).network.arrays();
    const Eigen::MatrixXcd k = Eigen::MatrixXd(arrays.stiffness_matrix()).cast<cd>();
    const Eigen::MatrixXcd c = Eigen::MatrixXd(arrays.damping_matrix()).cast<cd>();
    const double omega = 2.0 * constants::pi * hz;
    const std::vector<Eigen::MatrixXcd> ma = air(omega);
    // The force e_(panel, node) on the Fourier modes: y_m = (1 / N) e^(-i theta_m panel) e_node; each mode's
    // system is one panel's size.
    std::vector<Eigen::VectorXcd> f_m(static_cast<std::size_t>(panels));
    for (int m = 0; m < panels; ++m) {
        const double theta = 2.0 * constants::pi * m / panels;
        Eigen::MatrixXcd a = k + cd(0.0, omega) * c - omega * omega * ma[static_cast<std::size_t>(m)];
        for (int i = 0; i < nodes; ++i) a(i, i) -= omega * omega * arrays.mass(static_cast<std::size_t>(i));
        Eigen::VectorXcd y = Eigen::VectorXcd::Zero(nodes);
        y[node] = std::polar(1.0 / panels, -theta * panel);
        f_m[static_cast<std::size_t>(m)] = -omega * omega * (ma[static_cast<std::size_t>(m)] * a.partialPivLu().solve(y));
    }
    std::vector<cd> out(static_cast<std::size_t>(panels * nodes));
    for (int p = 0; p < panels; ++p) {
        Eigen::VectorXcd force = Eigen::VectorXcd::Zero(nodes);
        for (int m = 0; m < panels; ++m) force += std::polar(1.0, 2.0 * constants::pi * m * p / panels) * f_m[static_cast<std::size_t>(m)];
        for (int i = 0; i < nodes; ++i) out[static_cast<std::size_t>(p * nodes + i)] = force[i];
    }
    return out;
}

std::complex<double> directional_force(const Canopy& canopy, const std::vector<cd>& forces, double k, double theta, double psi) {
    const double kx = k * std::sin(theta) * std::cos(psi), ky = k * std::sin(theta) * std::sin(psi);
    cd sum = 0.0;
    for (int p = 0; p < canopy.panel_count(); ++p)
        for (int i = 0; i < canopy.nodes_per_panel(); ++i) {
            const Vec3 y = canopy.rest_position(p, i);
            sum += forces[static_cast<std::size_t>(p * canopy.nodes_per_panel() + i)] * std::polar(1.0, kx * y.x + ky * y.y);
        }
    return sum;
}

CanopyFrequencyResponse canopy_frequency_response(const Canopy& canopy, int panel, int node, const std::vector<Vec3>& listeners,
                                                  const std::vector<double>& hz, const AirMassAt& air, double speed_of_sound) {
    if (listeners.empty()) throw std::invalid_argument("canopy_frequency_response: no listener");
    const int panels = canopy.panel_count(), nodes = canopy.nodes_per_panel();
    CanopyFrequencyResponse out;
    out.hz = hz;
    out.pressure.assign(listeners.size(), std::vector<cd>(hz.size()));
    for (std::size_t f = 0; f < hz.size(); ++f) {
        const double wave = 2.0 * constants::pi * hz[f] / speed_of_sound;
        const std::vector<cd> force = canopy_air_forces(canopy, panel, node, hz[f], air);
        for (int p = 0; p < panels; ++p)
            for (int i = 0; i < nodes; ++i) {
                const Vec3 y = canopy.rest_position(p, i), n = canopy.normal(p, i);
                for (std::size_t l = 0; l < listeners.size(); ++l) {
                    const Vec3 d = listeners[l] - y;
                    const double r = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
                    const double cos_theta = (d.x * n.x + d.y * n.y + d.z * n.z) / r;
                    const cd g = std::polar(1.0, -wave * r) * cd(1.0 / (r * r), wave / r) * (cos_theta / (4.0 * constants::pi));
                    out.pressure[l][f] += g * force[static_cast<std::size_t>(p * nodes + i)];
                }
            }
    }
    return out;
}

std::vector<double> band_energies_db(const std::vector<cd>& pressure, const std::vector<cd>& force, const std::vector<double>& hz, double low_hz,
                                     double high_hz, std::vector<double>* centres) {
    std::vector<double> out;
    if (centres) centres->clear();
    for (int b = -30; b <= 20; ++b) {
        const double centre = 1000.0 * std::pow(2.0, b / 3.0);
        if (centre < low_hz * 0.99 || centre > high_hz * 1.01) continue;
        const double lo = centre * std::pow(2.0, -1.0 / 6.0), hi = centre * std::pow(2.0, 1.0 / 6.0);
        double energy = 0.0;
        for (std::size_t f = 0; f < hz.size(); ++f)
            if (hz[f] >= lo && hz[f] < hi) energy += std::norm(pressure[f] * force[f]);
        out.push_back(10.0 * std::log10(energy > 0.0 ? energy : 1e-300));
        if (centres) centres->push_back(centre);
    }
    return out;
}

std::complex<double> raised_cosine_spectrum(double peak_n, double length_s, double hz) {
    // (1 / 2) integral (1 - cos(a t)) e^(-i w t) dt over one period of a = 2 pi / T:
    // (1 - e^(-i w T)) a^2 / (2 i w (a^2 - w^2)), T / 2 at w = 0 and -T / 4 at w = a.
    const double w = 2.0 * constants::pi * hz, a = 2.0 * constants::pi / length_s;
    if (std::abs(w) < 1e-9 * a) return peak_n * length_s / 2.0;
    if (std::abs(w - a) < 1e-9 * a) return -peak_n * length_s / 4.0;
    const cd num = (1.0 - std::polar(1.0, -w * length_s)) * (a * a);
    return peak_n * num / (cd(0.0, 2.0 * w) * (a * a - w * w));
}

}  // namespace ameoto::reference
