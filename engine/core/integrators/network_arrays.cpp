// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/integrators/network_arrays.hpp"

namespace ameoto {

namespace {

// Restrict-qualified parameters, so GCC vectorises the mass loops (explicit_verlet.cpp explains).
void mass_terms(std::size_t n, const double* __restrict x, const double* __restrict v, const double* __restrict ext,
                const double* __restrict ka, const double* __restrict zg, double* __restrict f) {
    if (ext != nullptr && v != nullptr) {
        for (std::size_t i = 0; i < n; ++i) f[i] = ext[i] - ka[i] * x[i] - zg[i] * v[i];
    } else if (ext != nullptr) {
        for (std::size_t i = 0; i < n; ++i) f[i] = ext[i] - ka[i] * x[i];
    } else if (v != nullptr) {
        for (std::size_t i = 0; i < n; ++i) f[i] = -ka[i] * x[i] - zg[i] * v[i];
    } else {
        for (std::size_t i = 0; i < n; ++i) f[i] = -ka[i] * x[i];
    }
}

// Links: gather/scatter, equal and opposite (scalar: links share masses).
void link_terms(std::size_t links, const std::int32_t* __restrict la, const std::int32_t* __restrict lb,
                const double* __restrict lk, const double* __restrict lz, const double* __restrict x,
                const double* __restrict v, double* __restrict f) {
    if (v != nullptr) {
        for (std::size_t l = 0; l < links; ++l) {
            const auto a = static_cast<std::size_t>(la[l]), b = static_cast<std::size_t>(lb[l]);
            const double force = -lk[l] * (x[a] - x[b]) - lz[l] * (v[a] - v[b]);
            f[a] += force;
            f[b] -= force;
        }
    } else {
        for (std::size_t l = 0; l < links; ++l) {
            const auto a = static_cast<std::size_t>(la[l]), b = static_cast<std::size_t>(lb[l]);
            const double force = -lk[l] * (x[a] - x[b]);
            f[a] += force;
            f[b] -= force;
        }
    }
}

}  // namespace

void NetworkArrays::forces(const double* x, const double* v, const double* ext, double* f) const {
    mass_terms(mass_count(), x, v, ext, anchor_stiffness.data(), ground_damping.data(), f);
    link_terms(link_count(), link_a.data(), link_b.data(), link_stiffness.data(), link_damping.data(), x, v, f);
}

double NetworkArrays::energy(const double* x, const double* v) const {
    double e = 0.0;
    const std::size_t n = mass_count();
    for (std::size_t i = 0; i < n; ++i) {
        e += 0.5 * anchor_stiffness[i] * x[i] * x[i];
        if (v != nullptr) e += 0.5 * mass_kg[i] * v[i] * v[i];
    }
    for (std::size_t l = 0; l < link_count(); ++l) {
        const double s = x[static_cast<std::size_t>(link_a[l])] - x[static_cast<std::size_t>(link_b[l])];
        e += 0.5 * link_stiffness[l] * s * s;
    }
    return e;
}

namespace {

Eigen::SparseMatrix<double> assemble(const NetworkArrays& a, const std::vector<double>& diagonal,
                                     const std::vector<double>& per_link) {
    const auto n = static_cast<Eigen::Index>(a.mass_count());
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(a.mass_count() + 4 * a.link_count());
    for (Eigen::Index i = 0; i < n; ++i) t.emplace_back(i, i, diagonal[static_cast<std::size_t>(i)]);
    for (std::size_t l = 0; l < a.link_count(); ++l) {
        const Eigen::Index i = a.link_a[l], j = a.link_b[l];
        const double k = per_link[l];
        t.emplace_back(i, i, k);
        t.emplace_back(j, j, k);
        t.emplace_back(i, j, -k);
        t.emplace_back(j, i, -k);
    }
    Eigen::SparseMatrix<double> m(n, n);
    m.setFromTriplets(t.begin(), t.end());   // duplicates are summed
    return m;
}

}  // namespace

Eigen::SparseMatrix<double> NetworkArrays::stiffness_matrix() const {
    return assemble(*this, anchor_stiffness, link_stiffness);
}

Eigen::SparseMatrix<double> NetworkArrays::damping_matrix() const {
    return assemble(*this, ground_damping, link_damping);
}

}  // namespace ameoto
