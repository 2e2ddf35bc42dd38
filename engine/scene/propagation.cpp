// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/scene/propagation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "engine/core/physical_constants.hpp"

namespace ameoto {
namespace {


// ---- Windowed-sinc fractional delay (header) ----
constexpr int kSincHalf = 16;                 // M: taps j = -(M-1)..M around the read point
constexpr int kSincTaps = 2 * kSincHalf;
constexpr int kSincPhases = 256;              // P
constexpr double kKaiserBeta = 8.0;

double bessel_i0(double x) {
    double sum = 1.0, term = 1.0;
    for (int k = 1; k < 60; ++k) {
        term *= (x / (2.0 * k)) * (x / (2.0 * k));
        sum += term;
        if (term < 1e-17 * sum) break;
    }
    return sum;
}

// (P + 1) rows of 2M taps; row p reads at fraction p / P. Built once per process (magic static: the first
// Propagation's constructor, never the audio thread).
const std::vector<double>& sinc_table() {
    static const std::vector<double> table = [] {
        std::vector<double> t(static_cast<std::size_t>((kSincPhases + 1) * kSincTaps));
        const double i0_beta = bessel_i0(kKaiserBeta);
        for (int p = 0; p <= kSincPhases; ++p) {
            const double frac = static_cast<double>(p) / kSincPhases;
            double sum = 0.0;
            for (int idx = 0; idx < kSincTaps; ++idx) {
                const double tau = (idx - (kSincHalf - 1)) - frac;
                const double u = tau / kSincHalf;
                const double window = std::abs(u) >= 1.0 ? 0.0 : bessel_i0(kKaiserBeta * std::sqrt(1.0 - u * u)) / i0_beta;
                // sinc is exactly 0 at non-zero integers (sin(pi j) in floating point is not).
                const double sinc = tau == 0.0 ? 1.0 : (tau == std::round(tau) ? 0.0 : std::sin(constants::pi * tau) / (constants::pi * tau));
                const double h = sinc * window;
                t[static_cast<std::size_t>(p * kSincTaps + idx)] = h;
                sum += h;
            }
            for (int idx = 0; idx < kSincTaps; ++idx) t[static_cast<std::size_t>(p * kSincTaps + idx)] /= sum;
        }
        return t;
    }();
    return table;
}

// ---- The air filter: a mix of two clipped, sampled Gaussians (header) ----
const double kTapFloor = std::exp(-8.0);

// Taps g[0..K] (symmetric) of one clipped Gaussian, normalised to unit DC gain; K = floor(4 sigma).
// Returns K. g must hold at least K + 1 entries.
int gaussian_taps(double sigma, double* g, int capacity) {
    if (!(sigma > 0.0)) {
        g[0] = 1.0;
        return 0;
    }
    const int k_max = std::min(static_cast<int>(std::floor(4.0 * sigma)), capacity - 1);
    // exp(-k^2 / 2 sigma^2) by the recurrence e_k = e_{k-1} q^(2k-1), q = exp(-1 / 2 sigma^2).
    const double q = std::exp(-0.5 / (sigma * sigma)), q2 = q * q;
    double e = 1.0, m = q, sum = 0.0;
    for (int k = 0; k <= k_max; ++k) {
        if (k > 0) {
            e *= m;
            m *= q2;
        }
        g[k] = std::max(0.0, e - kTapFloor);
        sum += k == 0 ? g[k] : 2.0 * g[k];
    }
    for (int k = 0; k <= k_max; ++k) g[k] /= sum;
    return k_max;
}

constexpr int kFitTapCapacity = 512;
constexpr double kSigmaRatioCap = 3.0;
constexpr double kSaturationDb = 60.0;
constexpr double kFirstDistance = 0.5;   // m; table distances 0, 0.5, 0.5 * 2^(1/3), ...
constexpr int kPerOctave = 3;

// Taps t[0..K] (symmetric) of the mix (1 - beta) G(sigma_a) + beta G(sigma_b); returns K (t and scratch
// must hold capacity entries; K < capacity).
int mix_taps(double sigma_a, double sigma_b, double beta, double* t, double* scratch, int capacity) {
    double* gb = scratch;
    const int ka = gaussian_taps(sigma_a, t, capacity);
    const int kb = gaussian_taps(sigma_b, gb, capacity);
    for (int k = 0; k <= std::max(ka, kb); ++k) {
        const auto i = static_cast<std::size_t>(k);
        t[i] = (k <= ka ? (1.0 - beta) * t[i] : 0.0) + (k <= kb ? beta * gb[i] : 0.0);
    }
    return std::max(ka, kb);
}

// Attenuation (dB, >= 0 where the filter cuts) of symmetric taps t[0..K] at w (rad/sample).
double taps_attenuation_db(const double* t, int k_max, double w) {
    // cos(k w) by the Chebyshev recurrence.
    const double c1 = std::cos(w);
    double c_prev = 1.0, c_k = c1, h = t[0];
    for (int k = 1; k <= k_max; ++k) {
        h += 2.0 * t[k] * c_k;
        const double c_next = 2.0 * c1 * c_k - c_prev;
        c_prev = c_k;
        c_k = c_next;
    }
    return h <= 1e-6 ? 120.0 : -20.0 * std::log10(h);
}

// Nelder-Mead (Nelder & Mead 1965) on a 3-parameter cost, from x0 with initial steps dx.
template <typename F>
std::array<double, 3> nelder_mead(F&& cost, std::array<double, 3> x0, std::array<double, 3> dx, int iterations) {
    std::array<std::array<double, 3>, 4> p{};
    std::array<double, 4> v{};
    p[0] = x0;
    for (int i = 0; i < 3; ++i) {
        p[static_cast<std::size_t>(i + 1)] = x0;
        p[static_cast<std::size_t>(i + 1)][static_cast<std::size_t>(i)] += dx[static_cast<std::size_t>(i)];
    }
    for (int i = 0; i < 4; ++i) v[static_cast<std::size_t>(i)] = cost(p[static_cast<std::size_t>(i)]);
    auto lerp = [](const std::array<double, 3>& a, const std::array<double, 3>& b, double t) {
        return std::array<double, 3>{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
    };
    for (int it = 0; it < iterations; ++it) {
        std::array<int, 4> o{0, 1, 2, 3};
        std::sort(o.begin(), o.end(), [&](int a, int b) { return v[static_cast<std::size_t>(a)] < v[static_cast<std::size_t>(b)]; });
        const auto pp = p;
        const auto vv = v;
        for (int i = 0; i < 4; ++i) {
            p[static_cast<std::size_t>(i)] = pp[static_cast<std::size_t>(o[static_cast<std::size_t>(i)])];
            v[static_cast<std::size_t>(i)] = vv[static_cast<std::size_t>(o[static_cast<std::size_t>(i)])];
        }
        if (v[3] - v[0] <= 1e-12 * (1.0 + std::abs(v[0]))) break;
        std::array<double, 3> centroid{};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) centroid[static_cast<std::size_t>(j)] += p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] / 3.0;
        const auto xr = lerp(centroid, p[3], -1.0);
        const double fr = cost(xr);
        if (fr < v[0]) {
            const auto xe = lerp(centroid, p[3], -2.0);
            const double fe = cost(xe);
            if (fe < fr) {
                p[3] = xe, v[3] = fe;
            } else {
                p[3] = xr, v[3] = fr;
            }
        } else if (fr < v[2]) {
            p[3] = xr, v[3] = fr;
        } else {
            const auto xc = lerp(centroid, p[3], 0.5);
            const double fc = cost(xc);
            if (fc < v[3]) {
                p[3] = xc, v[3] = fc;
            } else {
                for (int i = 1; i < 4; ++i) {
                    p[static_cast<std::size_t>(i)] = lerp(p[0], p[static_cast<std::size_t>(i)], 0.5);
                    v[static_cast<std::size_t>(i)] = cost(p[static_cast<std::size_t>(i)]);
                }
            }
        }
    }
    const auto best = std::min_element(v.begin(), v.end()) - v.begin();
    return p[static_cast<std::size_t>(best)];
}

}  // namespace

double iso9613_attenuation_db_per_m(double f, double temperature_c, double rh_pct, double pressure_kpa) {
    // ISO 9613-1:1993 eq. (3)-(5) and Annex B (saturation vapour pressure).
    const double t = temperature_c + 273.15, t0 = 293.15, t01 = 273.16, pr = 101.325;
    const double pa_pr = pressure_kpa / pr;
    const double psat_pr = std::pow(10.0, -6.8346 * std::pow(t01 / t, 1.261) + 4.6151);
    const double h = rh_pct * psat_pr / pa_pr;   // molar concentration of water vapour, %
    const double fr_o = pa_pr * (24.0 + 4.04e4 * h * (0.02 + h) / (0.391 + h));
    const double fr_n = pa_pr * std::pow(t / t0, -0.5) * (9.0 + 280.0 * h * std::exp(-4.170 * (std::pow(t / t0, -1.0 / 3.0) - 1.0)));
    return 8.686 * f * f *
           (1.84e-11 / pa_pr * std::sqrt(t / t0) +
            std::pow(t / t0, -2.5) * (0.01275 * std::exp(-2239.1 / t) / (fr_o + f * f / fr_o) +
                                      0.1068 * std::exp(-3352.0 / t) / (fr_n + f * f / fr_n)));
}

double speed_of_sound_m_per_s(double temperature_c) {
    return constants::speed_of_sound_air * std::sqrt((temperature_c + 273.15) / 293.15);
}

struct Propagation::AirTable {
    std::vector<AirFit> fits;   // fits[0]: r = 0 (no filter); fits[1]: kFirstDistance; then 3 per octave
    int k_max = 0;

    AirFit at(double r) const {
        if (!(r > 0.0)) return {0.0, 0.0, 0.0, 0.0};
        const AirFit& first = fits[1];
        if (r <= first.distance_m) {
            // A Gaussian's attenuation in dB grows as sigma^2 and the target as r: sigma ~ sqrt(r).
            const double t = std::sqrt(r / first.distance_m);
            return {r, t * first.sigma_a, t * first.sigma_b, first.beta};
        }
        const double pos = std::log(r / first.distance_m) * kPerOctave / std::log(2.0) + 1.0;
        const auto last = static_cast<double>(fits.size() - 1);
        if (pos >= last) return fits.back();
        const auto i = static_cast<std::size_t>(pos);
        const double t = pos - static_cast<double>(i);
        const AirFit& a = fits[i];
        const AirFit& b = fits[i + 1];
        return {r, a.sigma_a + t * (b.sigma_a - a.sigma_a), a.sigma_b + t * (b.sigma_b - a.sigma_b), a.beta + t * (b.beta - a.beta)};
    }

    static AirTable build(const PropagationConfig& cfg) {
        AirTable table;
        // The fit frequencies: nominal 1/3-octave centres 50 Hz .. 20 kHz (IEC 61260), up to 0.45 fs.
        static constexpr double centres[] = {50,   63,   80,   100,  125,  160,  200,  250,  315,  400,   500,   630,   800,  1000,
                                             1250, 1600, 2000, 2500, 3150, 4000, 5000, 6300, 8000, 10000, 12500, 16000, 20000};
        std::vector<double> w, alpha;
        for (double f : centres) {
            if (f > 0.45 * cfg.sample_rate) break;
            w.push_back(2.0 * constants::pi * f / cfg.sample_rate);
            alpha.push_back(iso9613_attenuation_db_per_m(f, cfg.temperature_c, cfg.relative_humidity_pct, cfg.pressure_kpa));
        }
        table.fits.push_back({0.0, 0.0, 0.0, 0.0});
        std::array<double, 3> x{0.25, 0.3, 0.1};
        for (int j = 0;; ++j) {
            const double r = kFirstDistance * std::pow(2.0, static_cast<double>(j) / kPerOctave);
            auto cost = [&](const std::array<double, 3>& p) {
                const double sa = p[0], sb = p[1], beta = p[2];
                if (!(sa >= 0.0 && sb >= sa && sb <= kSigmaRatioCap * sa + 1e-12 && beta >= 0.0 && beta <= 1.0 && sb < 100.0))
                    return 1e30;
                std::array<double, kFitTapCapacity> t, scratch;
                const int k = mix_taps(sa, sb, beta, t.data(), scratch.data(), kFitTapCapacity);
                double sum = 0.0;
                for (std::size_t b = 0; b < w.size(); ++b) {
                    const double e = std::min(taps_attenuation_db(t.data(), k, w[b]), kSaturationDb) -
                                     std::min(r * alpha[b], kSaturationDb);
                    sum += e * e;
                }
                return sum;
            };
            // Warm start from the previous distance (the optimum moves smoothly with r), then a restart
            // from the result, the usual cure for Nelder-Mead's early collapse.
            x[1] = std::max(x[1], x[0]);
            for (int pass = 0; pass < 2; ++pass)
                x = nelder_mead(cost, x, {0.05 + 0.1 * x[0], 0.05 + 0.1 * x[1], 0.1}, 400);
            table.fits.push_back({r, x[0], x[1], x[2]});
            table.k_max = std::max(table.k_max, static_cast<int>(std::floor(4.0 * x[1])));
            if (r >= cfg.max_distance_m) break;
        }
        return table;
    }
};

namespace {

// Fits are shared between paths with the same climate, sample rate and range (a scene with many sources
// builds the table once). Guarded by a mutex: constructors run on control threads only.
std::shared_ptr<const Propagation::AirTable> shared_air_table(const PropagationConfig& cfg) {
    using Key = std::tuple<double, double, double, double, double>;
    static std::mutex mutex;
    static std::map<Key, std::shared_ptr<const Propagation::AirTable>> cache;
    const Key key{cfg.sample_rate, cfg.max_distance_m, cfg.temperature_c, cfg.relative_humidity_pct, cfg.pressure_kpa};
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (auto it = cache.find(key); it != cache.end()) return it->second;
    }
    auto table = std::make_shared<const Propagation::AirTable>(Propagation::AirTable::build(cfg));
    std::lock_guard<std::mutex> lock(mutex);
    return cache.emplace(key, std::move(table)).first->second;
}

std::size_t power_of_two_at_least(std::size_t n) {
    std::size_t p = 1;
    while (p < n) p <<= 1;
    return p;
}

}  // namespace

Propagation::Propagation(const PropagationConfig& config) : config_(config) {
    if (!(config.sample_rate >= 8000.0 && config.sample_rate <= 768000.0)) throw std::invalid_argument("sample rate must be 8 to 768 kHz");
    if (!(config.max_distance_m > 0.0 && config.max_distance_m <= 5000.0)) throw std::invalid_argument("max distance must be 0 to 5000 m");
    if (!(config.min_distance_m > 0.0)) throw std::invalid_argument("min distance must be positive");
    if (!(config.relative_humidity_pct >= 0.0 && config.relative_humidity_pct <= 100.0)) throw std::invalid_argument("humidity must be 0 to 100 %");
    if (!(config.temperature_c >= -40.0 && config.temperature_c <= 60.0)) throw std::invalid_argument("temperature must be -40 to 60 C");
    if (!(config.pressure_kpa > 10.0 && config.pressure_kpa < 200.0)) throw std::invalid_argument("pressure must be 10 to 200 kPa");
    if (!(config.glide_s >= 0.0)) throw std::invalid_argument("glide time must not be negative");
    c_ = speed_of_sound_m_per_s(config.temperature_c);
    (void)sinc_table();
    air_ = shared_air_table(config);
    k_max_ = air_->k_max;
    const auto max_line_delay = static_cast<std::size_t>(std::ceil(config.max_distance_m * config.sample_rate / c_));
    line_.assign(power_of_two_at_least(max_line_delay + kSincTaps + 4), 0.0);
    line_mask_ = line_.size() - 1;
    fir_in_.assign(power_of_two_at_least(static_cast<std::size_t>(2 * k_max_ + 2)), 0.0);
    fir_mask_ = fir_in_.size() - 1;
    taps_.assign(static_cast<std::size_t>(k_max_ + 1), 0.0);
    scratch_.assign(taps_.size(), 0.0);
    r_ = r_target_ = norm(source_ - listener_);
    update_from_distance();
}

double Propagation::min_delay_samples() const { return (kSincHalf - 1) + k_max_; }

Propagation::AirFit Propagation::fit_at(double distance_m) const { return air_->at(std::min(distance_m, config_.max_distance_m)); }

double Propagation::air_attenuation_db(double distance_m, double frequency_hz) const {
    const AirFit f = fit_at(distance_m);
    std::array<double, kFitTapCapacity> t, scratch;
    const int k = mix_taps(f.sigma_a, f.sigma_b, f.beta, t.data(), scratch.data(), kFitTapCapacity);
    return taps_attenuation_db(t.data(), k, 2.0 * constants::pi * frequency_hz / config_.sample_rate);
}

void Propagation::update_from_distance() {
    gain_ = 1.0 / std::max(r_, config_.min_distance_m);
    const double r = std::min(r_, config_.max_distance_m);
    // The air filter delays by exactly K samples (linear phase); the line gives the rest.
    const double line_delay = std::max(r * config_.sample_rate / c_ - k_max_, static_cast<double>(kSincHalf - 1));
    delay_ = line_delay + k_max_;
    read_integer_ = static_cast<std::size_t>(line_delay);
    read_phase_ = (line_delay - static_cast<double>(read_integer_)) * kSincPhases;
    const AirFit f = air_->at(r);
    // Taps of the two Gaussians, mixed; every tap is continuous in sigma (header), so in r. Interpolated
    // sigmas never exceed the table's largest, so K <= k_max_.
    const int k = mix_taps(f.sigma_a, f.sigma_b, f.beta, taps_.data(), scratch_.data(), k_max_ + 1);
    std::fill(taps_.begin() + k + 1, taps_.end(), 0.0);
}

void Propagation::set_listener(Vec3 position) {
    listener_ = position;
    r_target_ = norm(source_ - listener_);
    glide_step_ = 0.0;   // computed in process(), as the rain's ramp
}

void Propagation::set_source(Vec3 position) {
    source_ = position;
    r_target_ = norm(source_ - listener_);
    glide_step_ = 0.0;
}

void Propagation::set_positions_now(Vec3 listener, Vec3 source) {
    listener_ = listener;
    source_ = source;
    r_ = r_target_ = norm(source_ - listener_);
    glide_step_ = 0.0;
    update_from_distance();
}

void Propagation::reset() {
    std::fill(line_.begin(), line_.end(), 0.0);
    std::fill(fir_in_.begin(), fir_in_.end(), 0.0);
}

double Propagation::process(double x) {
    line_[write_] = x;
    if (r_ != r_target_) {
        const double gap = std::abs(r_target_ - r_);
        if (glide_step_ == 0.0) glide_step_ = config_.glide_s > 0.0 ? gap / (config_.glide_s * config_.sample_rate) : gap;
        if (gap <= glide_step_) {
            r_ = r_target_;
        } else {
            r_ += r_ < r_target_ ? glide_step_ : -glide_step_;
        }
        update_from_distance();
    }
    // Windowed-sinc read at read_integer_ + fraction: taps j = -(M-1)..M, sample n - I - j.
    const auto& table = sinc_table();
    const auto phase = std::min(static_cast<int>(read_phase_), kSincPhases - 1);
    const double a = read_phase_ - phase;
    const double* row0 = table.data() + static_cast<std::size_t>(phase) * kSincTaps;
    const double* row1 = row0 + kSincTaps;
    const std::size_t base = write_ + line_.size() - read_integer_ + (kSincHalf - 1);   // index of j = -(M-1)
    double s = 0.0;
    for (int idx = 0; idx < kSincTaps; ++idx) {
        const double h = row0[idx] + a * (row1[idx] - row0[idx]);
        s += h * line_[(base - static_cast<std::size_t>(idx)) & line_mask_];
    }
    write_ = (write_ + 1) & line_mask_;
    // Air filter: symmetric FIR centred K samples back.
    fir_in_[fir_write_] = s;
    const std::size_t centre = (fir_write_ + fir_in_.size() - static_cast<std::size_t>(k_max_)) & fir_mask_;
    double y = taps_[0] * fir_in_[centre];
    for (int k = 1; k <= k_max_; ++k) {
        const double t = taps_[static_cast<std::size_t>(k)];
        if (t == 0.0) break;   // taps vanish beyond 4 sigma_b, and only there
        y += t * (fir_in_[(centre + fir_in_.size() - static_cast<std::size_t>(k)) & fir_mask_] +
                  fir_in_[(centre + static_cast<std::size_t>(k)) & fir_mask_]);
    }
    fir_write_ = (fir_write_ + 1) & fir_mask_;
    return gain_ * y;
}

void Propagation::process(std::span<const double> in, std::span<double> out) {
    const std::size_t n = std::min(in.size(), out.size());
    for (std::size_t i = 0; i < n; ++i) out[i] = process(in[i]);
}

}  // namespace ameoto
