// SPDX-License-Identifier: GPL-3.0-or-later
// AmbiX encoding and bus rotation: see ambisonics.hpp for the conventions and sources.
#include "engine/models/ambisonics.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"
#include "engine/models/panning.hpp"

namespace ameoto {

int ambix_order(int channels) {
    for (int n = 1; n <= max_ambix_order; ++n)
        if (ambix_channels(n) == channels) return n;
    return -1;
}

std::array<double, max_ambix_channels> ambix_gains(double azimuth, double elevation, int order) {
    if (order < 0 || order > max_ambix_order) throw std::invalid_argument("ambisonic order must be 0 to 3");
    std::array<double, max_ambix_channels> g{};
    const double x = std::sin(elevation), s = std::cos(elevation);   // P_n^m's argument, and sqrt(1 - x^2)
    // p[n][m]: P_n^m(x) without the Condon-Shortley phase (A&S 8.6.x recurrences, phase dropped).
    double p[max_ambix_order + 1][max_ambix_order + 1] = {};
    double pmm = 1.0;
    for (int m = 0; m <= order; ++m) {
        if (m > 0) pmm *= (2.0 * m - 1.0) * s;   // P_m^m = (2m - 1)!! (1 - x^2)^(m/2)
        p[m][m] = pmm;
        if (m + 1 <= order) p[m + 1][m] = x * (2.0 * m + 1.0) * pmm;
        for (int n = m + 2; n <= order; ++n) p[n][m] = ((2.0 * n - 1.0) * x * p[n - 1][m] - (n + m - 1.0) * p[n - 2][m]) / (n - m);
    }
    for (int n = 0; n <= order; ++n) {
        for (int m = -n; m <= n; ++m) {
            const int a = m < 0 ? -m : m;
            // SN3D: sqrt((2 - delta_m0) (n - |m|)! / (n + |m|)!)
            double ratio = 1.0;
            for (int k = n - a + 1; k <= n + a; ++k) ratio /= k;
            const double norm_n = std::sqrt((a == 0 ? 1.0 : 2.0) * ratio);
            const double angular = m >= 0 ? std::cos(m * azimuth) : std::sin(a * azimuth);
            g[static_cast<std::size_t>(n * n + n + m)] = norm_n * p[n][a] * angular;
        }
    }
    return g;
}

std::array<double, max_ambix_channels> ambix_gains(Vec3 d, int order) {
    const double horizontal = std::hypot(d.x, d.y);
    if (horizontal == 0.0 && d.z == 0.0) {
        std::array<double, max_ambix_channels> g{};
        g[0] = 1.0;   // no direction (the listener at the source): omnidirectional
        return g;
    }
    return ambix_gains(std::atan2(d.y, d.x), std::atan2(d.z, horizontal), order);
}

std::string ambix_channel_name(int acn) {
    // The first-order letters (B-format's W, Y, Z, X in ACN order); higher channels by degree and order.
    static const char* const letters[] = {"W", "Y", "Z", "X", "V", "T", "R", "S", "U", "Q", "O", "M", "K", "L", "N", "P"};
    if (acn < 0 || acn >= max_ambix_channels) throw std::invalid_argument("ACN must be 0 to 15");
    return "ACN " + std::to_string(acn) + " " + letters[acn];
}

std::array<double, max_ambix_channels> direction_gains(double azimuth, double elevation, int channels, bool ambisonic) {
    if (!ambisonic) {
        const auto p = pan_gains(azimuth, channels);
        std::array<double, max_ambix_channels> g{};
        for (int c = 0; c < channels && c < max_ambix_channels; ++c) g[static_cast<std::size_t>(c)] = p[static_cast<std::size_t>(c)];
        return g;
    }
    const int order = ambix_order(channels);
    if (order < 1) throw std::invalid_argument("an Ambisonic bus has 4, 9 or 16 channels");
    return ambix_gains(azimuth, elevation, order);
}

std::array<double, 9> head_rotation(double yaw, double pitch, double roll) {
    // H = Rz(yaw) Ry(-pitch) Rx(roll): the right-hand rotation about +y (left) lowers the nose, so the
    // pitch that raises it is its negative (header).
    const double cy = std::cos(yaw), sy = std::sin(yaw), cp = std::cos(-pitch), sp = std::sin(-pitch), cr = std::cos(roll),
                 sr = std::sin(roll);
    const Eigen::Matrix3d rz{{cy, -sy, 0}, {sy, cy, 0}, {0, 0, 1}};
    const Eigen::Matrix3d ry{{cp, 0, sp}, {0, 1, 0}, {-sp, 0, cp}};
    const Eigen::Matrix3d rx{{1, 0, 0}, {0, cr, -sr}, {0, sr, cr}};
    const Eigen::Matrix3d h = rz * ry * rx;
    std::array<double, 9> out{};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) out[static_cast<std::size_t>(3 * r + c)] = h(r, c);
    return out;
}

AmbixRotation AmbixRotation::identity(int order) {
    // Order 0 (W alone, which no rotation changes) is what a stream of another format is handed with
    // /listener/orientation: the renderer turns its panning from the command's angles instead.
    if (order < 0 || order > max_ambix_order) throw std::invalid_argument("ambisonic order must be 0 to 3");
    AmbixRotation r;
    r.order = order;
    for (int k = 0; k < ambix_channels(order); ++k) r.m[static_cast<std::size_t>(k * max_ambix_channels + k)] = 1.0;
    return r;
}

AmbixRotation AmbixRotation::from_orientation(double yaw, double pitch, double roll, int order) {
    AmbixRotation r = identity(order);
    if (order == 0) return r;
    const std::array<double, 9> h = head_rotation(yaw, pitch, roll);
    // 64 directions of a Fibonacci lattice (golden-angle spiral, equal areas): enough for the 7 x 7
    // third-order block to be well determined.
    constexpr int points = 64;
    const int channels = ambix_channels(order);
    Eigen::MatrixXd a(channels, points), b(channels, points);
    const double golden = constants::pi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < points; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / points, rho = std::sqrt(1.0 - z * z), phi = golden * i;
        const Vec3 v{rho * std::cos(phi), rho * std::sin(phi), z};
        // H^T v: the direction the turned head hears v from.
        const Vec3 heard{h[0] * v.x + h[3] * v.y + h[6] * v.z, h[1] * v.x + h[4] * v.y + h[7] * v.z, h[2] * v.x + h[5] * v.y + h[8] * v.z};
        const auto ya = ambix_gains(v, order), yb = ambix_gains(heard, order);
        for (int k = 0; k < channels; ++k) {
            a(k, i) = ya[static_cast<std::size_t>(k)];
            b(k, i) = yb[static_cast<std::size_t>(k)];
        }
    }
    for (int n = 1; n <= order; ++n) {   // order 0 (W) is invariant: 1
        const int first = n * n, size = 2 * n + 1;
        const Eigen::MatrixXd an = a.middleRows(first, size), bn = b.middleRows(first, size);
        // R_n = B_n A_n^T (A_n A_n^T)^-1, solved without forming the inverse.
        const Eigen::MatrixXd rn = (an * an.transpose()).ldlt().solve(an * bn.transpose()).transpose();
        for (int i = 0; i < size; ++i)
            for (int j = 0; j < size; ++j)
                r.m[static_cast<std::size_t>((first + i) * max_ambix_channels + first + j)] = rn(i, j);
    }
    return r;
}

void AmbixRotation::apply(const double* in, double* out) const {
    out[0] = in[0];
    for (int n = 1; n <= order; ++n) {
        const int first = n * n, last = first + 2 * n + 1;
        for (int i = first; i < last; ++i) {
            const double* row = m.data() + static_cast<std::size_t>(i * max_ambix_channels);
            double sum = 0.0;
            for (int j = first; j < last; ++j) sum += row[j] * in[j];
            out[i] = sum;
        }
    }
}

bool AmbixRotation::is_identity() const { return *this == identity(order); }

}  // namespace ameoto
