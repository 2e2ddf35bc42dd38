// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/grid_membrane.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ameoto {
namespace {

// Rows whose spans are closer than this many cells are stepped as one span: visiting a few empty
// cells (all coefficients zero, they stay at 0) costs less than a loop's start-up and tail.
constexpr int join_gap = 24;

// The state is y = x + (beta/T') d and d = x[n] - x[n-1] (x = y - (beta/T') d). The scheme,
// x[n+1] = x + d + (T'^2 / m) F with F = -K (x + beta v) - alpha M v, becomes
//   d[n+1] = (1 - alpha T') d + sum_j c_ij y_j - cd y     (c = T'^2 k / m, cd = sum of c + anchor)
//   y[n+1] = x[n+1] + (beta/T') d[n+1] = y - (beta/T') d + (1 + beta/T') d[n+1]
// d is updated in place; y[n+1] goes to the other buffer (the neighbours still read y[n]).
// The general stencil: per-link coefficients (zero where there is no link), per-cell diagonal.
template <typename Real>
void stencil_general(Real* __restrict d, const Real* __restrict y, Real* __restrict y_next, const Real* __restrict ce,
                     const Real* __restrict cn, const Real* __restrict cnw, const Real* __restrict cd, Real keep,
                     Real b, Real one_plus_b, std::ptrdiff_t s, std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (std::ptrdiff_t p = begin; p < end; ++p) {
        const Real links = ce[p] * y[p + 1] + ce[p - 1] * y[p - 1] + cn[p] * y[p + s] + cn[p - s] * y[p - s] +
                           cnw[p] * y[p + s - 1] + cnw[p - s + 1] * y[p - s + 1];
        const Real next_d = keep * d[p] + (links - cd[p] * y[p]);
        y_next[p] = (y[p] - b * d[p]) + one_plus_b * next_d;
        d[p] = next_d;
    }
}

// Cells whose every neighbour that is a node is linked to them with the common stiffness: one
// coefficient per cell (c, zero on empty cells) times the sum of the six neighbours' y (empty cells
// and fixed points hold y = 0; a fixed point's spring is in the diagonal cd).
template <typename Real>
void stencil_lattice(Real* __restrict d, const Real* __restrict y, Real* __restrict y_next, const Real* __restrict c,
                     const Real* __restrict cd, Real keep, Real b, Real one_plus_b, std::ptrdiff_t s,
                     std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (std::ptrdiff_t p = begin; p < end; ++p) {
        const Real around = (y[p + 1] + y[p - 1]) + (y[p + s] + y[p - s]) + (y[p + s - 1] + y[p - s + 1]);
        const Real next_d = keep * d[p] + (c[p] * around - cd[p] * y[p]);
        y_next[p] = (y[p] - b * d[p]) + one_plus_b * next_d;
        d[p] = next_d;
    }
}

}  // namespace

template <typename Real>
BasicGridMembrane<Real>::BasicGridMembrane(const GridMembraneBody& body) : body_(body) {
    if (!(body.node_mass > 0.0) || !std::isfinite(body.node_mass)) throw std::invalid_argument("node mass must be positive and finite");
    if (!(body.mass_damping >= 0.0) || !(body.stiffness_damping >= 0.0)) throw std::invalid_argument("damping must be non-negative");
}

template <typename Real>
int BasicGridMembrane<Real>::add_node(int i, int j) {
    if (!node_cell_.empty()) throw std::logic_error("grid membrane: add_node after finalize");
    node_i_.push_back(i);
    node_j_.push_back(j);
    anchor_k_.push_back(0.0);
    return node_count() - 1;
}

template <typename Real>
void BasicGridMembrane<Real>::add_link(int a, int b, double stiffness) {
    if (a == b || a < 0 || b < 0 || a >= node_count() || b >= node_count())
        throw std::invalid_argument("link must join two distinct existing nodes");
    const int di = node_i_[static_cast<std::size_t>(b)] - node_i_[static_cast<std::size_t>(a)];
    const int dj = node_j_[static_cast<std::size_t>(b)] - node_j_[static_cast<std::size_t>(a)];
    const bool forward = (di == 1 && dj == 0) || (di == 0 && dj == 1) || (di == -1 && dj == 1);
    const bool backward = (di == -1 && dj == 0) || (di == 0 && dj == -1) || (di == 1 && dj == -1);
    if (!forward && !backward) throw std::invalid_argument("grid membrane: a link must join lattice neighbours");
    if (!(stiffness >= 0.0) || !std::isfinite(stiffness)) throw std::invalid_argument("link stiffness must be finite and >= 0");
    // Kept from the node whose neighbour lies in a forward direction (+1, +S, +S-1).
    link_a_.push_back(forward ? a : b);
    link_b_.push_back(forward ? b : a);
    link_k_.push_back(stiffness);
}

template <typename Real>
void BasicGridMembrane<Real>::add_anchor(int a, double stiffness) {
    if (a < 0 || a >= node_count()) throw std::invalid_argument("anchor on a node that does not exist");
    if (!(stiffness >= 0.0) || !std::isfinite(stiffness)) throw std::invalid_argument("anchor stiffness must be finite and >= 0");
    anchor_k_[static_cast<std::size_t>(a)] += stiffness;
}

template <typename Real>
void BasicGridMembrane<Real>::finalize(double time_step_s) {
    if (node_i_.empty()) throw std::invalid_argument("grid membrane has no nodes");
    if (!(time_step_s > 0.0)) throw std::invalid_argument("time step must be positive");
    const std::size_t n = node_i_.size();
    const double m = body_.node_mass;

    // Stability, as TransverseNetwork::finalize: Gershgorin on M^-1 K and M^-1 C, row i bounded by
    // (anchor + 2 * sum of links at i) / m; C = alpha M + beta K, so gamma = alpha + beta omega^2.
    std::vector<double> k_sum(anchor_k_);
    for (std::size_t l = 0; l < link_k_.size(); ++l) {
        k_sum[static_cast<std::size_t>(link_a_[l])] += 2.0 * link_k_[l];
        k_sum[static_cast<std::size_t>(link_b_[l])] += 2.0 * link_k_[l];
    }
    const double k_max = *std::max_element(k_sum.begin(), k_sum.end());
    stability_.omega_max_bound = std::sqrt(k_max / m);
    stability_.gamma_max_bound = body_.mass_damping + body_.stiffness_damping * k_max / m;
    stability_.time_step = time_step_s;
    stability_.sub_steps = 1;
    while (stability_.margin() >= 0.9) {
        if (stability_.sub_steps >= 4096)
            throw std::invalid_argument("grid membrane too stiff: needs more than 4096 sub-steps per sample");
        ++stability_.sub_steps;
    }
    sub_dt_ = time_step_s / stability_.sub_steps;
    const double dt = sub_dt_;
    stability_.message = "grid membrane, explicit Verlet: " + std::to_string(stability_.sub_steps) +
                         " sub-step(s) per sample, Gershgorin omega_max T' = " + std::to_string(stability_.omega_max_bound * dt);

    // Grid: the nodes' bounding box in axial coordinates plus a halo cell on every side.
    const int i_min = *std::min_element(node_i_.begin(), node_i_.end());
    const int i_max = *std::max_element(node_i_.begin(), node_i_.end());
    const int j_min = *std::min_element(node_j_.begin(), node_j_.end());
    const int j_max = *std::max_element(node_j_.begin(), node_j_.end());
    stride_ = i_max - i_min + 3;
    const std::size_t rows = static_cast<std::size_t>(j_max - j_min + 3);
    const std::size_t cells = rows * static_cast<std::size_t>(stride_);
    node_cell_.assign(n, 0);
    std::vector<int> owner(cells, -1);
    for (std::size_t k = 0; k < n; ++k) {
        const int c = (node_j_[k] - j_min + 1) * stride_ + (node_i_[k] - i_min + 1);
        if (owner[static_cast<std::size_t>(c)] >= 0) throw std::invalid_argument("grid membrane: two nodes at the same lattice point");
        owner[static_cast<std::size_t>(c)] = static_cast<int>(k);
        node_cell_[k] = c;
    }

    // Coefficients c = T'^2 k / m per forward link; the diagonal cd sums them over all six directions
    // plus the anchor (F_i = sum_j k_ij (y_j - y_i) - k_anchor,i y_i).
    std::vector<double> ce(cells, 0.0), cn(cells, 0.0), cnw(cells, 0.0), cd(cells, 0.0);
    std::vector<int> links_at(cells, 0);
    std::vector<bool> other_links(cells, false);   // a link of another stiffness, or two on one pair
    std::vector<unsigned char> directions(cells, 0);   // forward directions linked so far
    const double scale = dt * dt / m;
    const double k_common = link_k_.empty() ? 0.0 : link_k_.front();
    for (std::size_t l = 0; l < link_k_.size(); ++l) {
        const auto a = static_cast<std::size_t>(node_cell_[static_cast<std::size_t>(link_a_[l])]);
        const auto b = static_cast<std::size_t>(node_cell_[static_cast<std::size_t>(link_b_[l])]);
        const double c = scale * link_k_[l];
        // stride - 1 is the third direction: add_link accepted only the three forward ones.
        const int direction = b - a == 1 ? 0 : b - a == static_cast<std::size_t>(stride_) ? 1 : 2;
        (direction == 0 ? ce : direction == 1 ? cn : cnw)[a] += c;
        const auto bit = static_cast<unsigned char>(1u << direction);
        if ((directions[a] & bit) || link_k_[l] != k_common) other_links[a] = other_links[b] = true;
        directions[a] |= bit;
        cd[a] += c;
        cd[b] += c;
        ++links_at[a];
        ++links_at[b];
    }
    anchor_cell_.clear();
    anchor_force_k_.clear();
    for (std::size_t k = 0; k < n; ++k) {
        const auto c = static_cast<std::size_t>(node_cell_[k]);
        cd[c] += scale * anchor_k_[k];
        if (anchor_k_[k] > 0.0) {
            anchor_cell_.push_back(static_cast<std::int32_t>(c));
            anchor_force_k_.push_back(anchor_k_[k]);
        }
    }
    // The lattice loop serves a node when every neighbour that is a node is linked to it once, with
    // the common stiffness: then sum_j c (y_j - y_i) is c times the sum over all six cells (empty
    // ones hold 0) minus the diagonal.
    const std::ptrdiff_t offsets[6] = {1, -1, stride_, -stride_, stride_ - 1, -stride_ + 1};
    std::vector<bool> lattice(cells, false);
    for (std::size_t k = 0; k < n; ++k) {
        const auto c = static_cast<std::size_t>(node_cell_[k]);
        int neighbours = 0;
        for (const std::ptrdiff_t o : offsets) neighbours += owner[static_cast<std::size_t>(static_cast<std::ptrdiff_t>(c) + o)] >= 0;
        lattice[c] = !other_links[c] && links_at[c] == neighbours;
    }
    // Cells that are not nodes keep every coefficient zero: they stay at 0.
    const double beta_over_dt = body_.stiffness_damping / dt, alpha_dt = body_.mass_damping * dt;
    std::vector<double> cl(cells, 0.0);
    for (std::size_t c = 0; c < cells; ++c)
        if (lattice[c]) cl[c] = scale * k_common;
    auto to_real = [](const std::vector<double>& v) { return std::vector<Real>(v.begin(), v.end()); };
    c_e_ = to_real(ce);
    c_n_ = to_real(cn);
    c_nw_ = to_real(cnw);
    c_x_ = to_real(cd);
    c_lattice_ = to_real(cl);
    d_.assign(cells, Real(0));
    y_.assign(cells, Real(0));
    y_next_.assign(cells, Real(0));
    velocity_sum_ = 0.0;
    external_.assign(cells, 0.0);
    listed_.assign(cells, 0);
    touched_.assign(n, 0);
    touched_count_ = 0;
    beta_over_dt_ = beta_over_dt;
    alpha_dt_ = alpha_dt;
    force_scale_ = scale;

    // Spans: each row from its first node to its last, cut where the loop changes (empty cells go
    // with the run they are in); a span joins the previous one, of the same loop, across a gap of at
    // most join_gap empty cells.
    struct Span {
        int begin, end;
        bool lattice;
    };
    std::vector<Span> spans;
    auto add = [&](int b, int e, bool is_lattice) {
        if (!spans.empty() && spans.back().lattice == is_lattice && b - spans.back().end <= join_gap) spans.back().end = e;
        else spans.push_back({b, e, is_lattice});
    };
    for (std::size_t r = 1; r + 1 < rows; ++r) {
        const int row_start = static_cast<int>(r) * stride_;
        int begin = -1, last = -1;
        bool kind = false;
        for (int c = row_start; c < row_start + stride_; ++c) {
            const auto u = static_cast<std::size_t>(c);
            if (owner[u] < 0) continue;
            if (begin < 0) {
                begin = c;
                kind = lattice[u];
            } else if (lattice[u] != kind) {
                add(begin, c, kind);
                begin = c;
                kind = lattice[u];
            }
            last = c;
        }
        if (begin >= 0) add(begin, last + 1, kind);
    }
    general_begin_.clear();
    general_end_.clear();
    lattice_begin_.clear();
    lattice_end_.clear();
    for (const Span& span : spans) {
        (span.lattice ? lattice_begin_ : general_begin_).push_back(span.begin);
        (span.lattice ? lattice_end_ : general_end_).push_back(span.end);
    }
}

template <typename Real>
int BasicGridMembrane<Real>::updated_cells() const {
    int total = 0;
    for (std::size_t s = 0; s < general_begin_.size(); ++s) total += general_end_[s] - general_begin_[s];
    return total + lattice_cells();
}

template <typename Real>
int BasicGridMembrane<Real>::lattice_cells() const {
    int total = 0;
    for (std::size_t s = 0; s < lattice_begin_.size(); ++s) total += lattice_end_[s] - lattice_begin_[s];
    return total;
}

template <typename Real>
void BasicGridMembrane<Real>::apply_force(int node, double newtons) {
    const std::size_t c = cell(node);
    // The first force on a cell since the last step lists it (at most every node: no allocation).
    if (!listed_[c]) {
        listed_[c] = 1;
        touched_[touched_count_++] = static_cast<std::int32_t>(c);
    }
    external_[c] += newtons;
}

template <typename Real>
double BasicGridMembrane<Real>::sub_step() {
    Real* __restrict d = d_.data();
    const Real* __restrict y = y_.data();
    Real* __restrict y_next = y_next_.data();
    const std::ptrdiff_t s = stride_;
    const auto keep = static_cast<Real>(1.0 - alpha_dt_), b = static_cast<Real>(beta_over_dt_),
               one_plus_b = static_cast<Real>(1.0 + beta_over_dt_);

    // Net force (N) before the update: the links cancel in pairs, leaving the anchors' springs and
    // dampers, -k_a (x + beta v) = -k_a y, and the ground dampers, -alpha m sum v.
    double part[4] = {};   // four chains: the sum is not one long dependency
    const std::size_t anchor_count = anchor_cell_.size();
    for (std::size_t a = 0; a < anchor_count; ++a)
        part[a % 4] += anchor_force_k_[a] * static_cast<double>(y[static_cast<std::size_t>(anchor_cell_[a])]);
    const double anchors = (part[0] + part[1]) + (part[2] + part[3]);
    const double net = -anchors - body_.mass_damping * body_.node_mass * velocity_sum_ / sub_dt_;

    for (std::size_t k = 0; k < general_begin_.size(); ++k)
        stencil_general(d, y, y_next, c_e_.data(), c_n_.data(), c_nw_.data(), c_x_.data(), keep, b, one_plus_b, s,
                        general_begin_[k], general_end_[k]);
    for (std::size_t k = 0; k < lattice_begin_.size(); ++k)
        stencil_lattice(d, y, y_next, c_lattice_.data(), c_x_.data(), keep, b, one_plus_b, s, lattice_begin_[k],
                        lattice_end_[k]);
    // sum d follows from the same sum: the link terms cancel, so
    // sum d[n+1] = (1 - alpha T') sum d - (T'^2 / m) sum k_a y  (+ the external pushes below).
    velocity_sum_ += -force_scale_ * anchors - alpha_dt_ * velocity_sum_;
    // External forces on the masses they were applied to: x and d += T'^2 f / m, so y += (1 + b) that.
    for (std::size_t t = 0; t < touched_count_; ++t) {
        const auto c = static_cast<std::size_t>(touched_[t]);
        const double push = force_scale_ * external_[c];
        d[c] += static_cast<Real>(push);
        y_next[c] += static_cast<Real>((1.0 + beta_over_dt_) * push);
        velocity_sum_ += push;
    }
    y_.swap(y_next_);
    return net;
}

template <typename Real>
double BasicGridMembrane<Real>::step() {
    double external_total = 0.0;
    for (std::size_t t = 0; t < touched_count_; ++t) external_total += external_[static_cast<std::size_t>(touched_[t])];
    double total = 0.0;
    for (int k = 0; k < stability_.sub_steps; ++k) total += sub_step();
    for (std::size_t t = 0; t < touched_count_; ++t) {
        external_[static_cast<std::size_t>(touched_[t])] = 0.0;
        listed_[static_cast<std::size_t>(touched_[t])] = 0;
    }
    touched_count_ = 0;
    return total / stability_.sub_steps + external_total;
}

template <typename Real>
void BasicGridMembrane<Real>::reset() {
    std::fill(d_.begin(), d_.end(), Real(0));
    std::fill(y_.begin(), y_.end(), Real(0));
    std::fill(y_next_.begin(), y_next_.end(), Real(0));
    std::fill(external_.begin(), external_.end(), 0.0);
    std::fill(listed_.begin(), listed_.end(), 0);
    touched_count_ = 0;
    velocity_sum_ = 0.0;
}

template <typename Real>
bool BasicGridMembrane<Real>::finite() const {
    Real sum = 0;
    for (const Real v : y_) sum += v;
    for (const Real v : d_) sum += v;
    return std::isfinite(sum);
}

template <typename Real>
double BasicGridMembrane<Real>::position(int node) const {
    const std::size_t c = cell(node);
    return static_cast<double>(y_[c]) - beta_over_dt_ * static_cast<double>(d_[c]);
}

template <typename Real>
double BasicGridMembrane<Real>::velocity(int node) const {
    return static_cast<double>(d_[cell(node)]) / sub_dt_;
}

template class BasicGridMembrane<float>;
template class BasicGridMembrane<double>;

std::vector<AxialIndex> axial_coordinates(const TriangularLattice& lattice) {
    // Relative to node 0: y = y0 + j row, x = x0 + (i + j / 2) h (triangular_lattice.cpp's layout).
    const double h = lattice.spacing, row = h * std::sqrt(3.0) / 2.0;
    std::vector<AxialIndex> axial;
    axial.reserve(lattice.nodes.size());
    if (lattice.nodes.empty()) return axial;
    const Point2 origin = lattice.nodes.front();
    for (const Point2& p : lattice.nodes) {
        const double j = std::round((p.y - origin.y) / row);
        const double i = std::round((p.x - origin.x) / h - 0.5 * j);
        axial.push_back({static_cast<int>(i), static_cast<int>(j)});
    }
    return axial;
}

template <typename Real>
BasicGridMembrane<Real> grid_membrane_over(const TriangularLattice& lattice, double areal_density, double tension,
                                           double alpha, double beta, double time_step_s) {
    if (lattice.nodes.empty()) throw std::invalid_argument("grid membrane over an empty lattice");
    // As build_membrane: node mass s A, k = T / sqrt 3 (T A lap(u) on the six-neighbour lattice).
    const double k = tension / std::sqrt(3.0);
    BasicGridMembrane<Real> grid(GridMembraneBody{areal_density * lattice.node_area, alpha, beta});
    for (const AxialIndex& a : axial_coordinates(lattice)) grid.add_node(a.i, a.j);
    for (std::size_t n = 0; n < lattice.nodes.size(); ++n)
        if (lattice.anchor_links[n] > 0) grid.add_anchor(static_cast<int>(n), k * lattice.anchor_links[n]);
    for (const auto& link : lattice.links) grid.add_link(link.a, link.b, k);
    grid.finalize(time_step_s);
    return grid;
}

template BasicGridMembrane<float> grid_membrane_over<float>(const TriangularLattice&, double, double, double, double, double);
template BasicGridMembrane<double> grid_membrane_over<double>(const TriangularLattice&, double, double, double, double, double);

}  // namespace ameoto
