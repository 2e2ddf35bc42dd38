// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/lod_governor.hpp"

#include <algorithm>
#include <cmath>

#include "engine/core/nearest_in_log.hpp"

namespace ameoto {

namespace {
constexpr double reference_diameter_m = 2e-3;
constexpr double reference_speed_m_per_s = 6.49;   // Gunn & Kinzer's terminal speed at 2 mm
constexpr double unmasked_rate_per_s = 100.0;
constexpr double rate_smoothing_s = 0.5;
constexpr double recovery_per_s = 0.5;
// Lattice pricing (header): time constants of what it learns.
constexpr double base_smoothing_s = 0.5;
constexpr double mean_smoothing_s = 0.25;
// 120 s, not 10 s: a 64-frame soak's per-block trace (docs/bench.md, "Slow blocks") showed the governor
// re-admitting a lattice drop every 5-10 s as a 10 s memory let a spawn-and-breakup block of 70-150 % of
// the period fall under the peak limit again; each such drop gave 2-5 blocks over half the period.
constexpr double event_memory_s = 120.0;
constexpr double recent_smoothing_s = 0.1;
constexpr double learning_s = 0.1;   // measured awake time after which a lattice drop's price counts as learned

double one_pole(double block_seconds, double time_constant_s) { return 1.0 - std::exp(-block_seconds / time_constant_s); }
}  // namespace

double LodGovernor::level_db(double diameter_m, double speed_m_per_s, double distance_m) {
    const double v = speed_m_per_s / reference_speed_m_per_s, d = diameter_m / reference_diameter_m;
    const double r = std::max(distance_m, 0.05);   // closer than 5 cm: the drop's own size
    return 20.0 * std::log10(std::max(v * v * d * d / r, 1e-12));
}

LodTier LodGovernor::choose(double diameter_m, double speed_m_per_s, double distance_m, int full_active) {
    const double level = level_db(diameter_m, speed_m_per_s, distance_m);
    const double shed = 1.0 - detail_;
    if (full_active < settings_.max_full && level >= settings_.full_level_db + masking_db_ + 40.0 * shed) {
        if (lattice_admissible(full_active, diameter_m)) {
            ++counts_.full;
            if (price_.known) since_full_s_ = 0.0;
            return LodTier::full;
        }
        ++counts_.priced_out;   // heard as a template instead
    }
    if (level >= masking_db_ - settings_.texture_margin_db + 30.0 * shed) {
        ++counts_.template_;
        return LodTier::template_;
    }
    ++counts_.texture;
    return LodTier::texture;
}

void LodGovernor::end_block(double measured_load, int drops, double block_seconds) {
    if (block_seconds <= 0.0) return;
    // Drop rate, smoothed with a one-pole of time constant rate_smoothing_s.
    const double a = 1.0 - std::exp(-block_seconds / rate_smoothing_s);
    rate_per_s_ += a * (drops / block_seconds - rate_per_s_);
    masking_db_ = 10.0 * std::log10(std::max(1.0, rate_per_s_ / unmasked_rate_per_s));
    // Load: fast attack, slow release.
    if (measured_load > settings_.budget) {
        detail_ = std::max(0.0, detail_ - (measured_load / settings_.budget - 1.0));
    } else {
        detail_ = std::min(1.0, detail_ + recovery_per_s * block_seconds);
    }
}

void LodGovernor::observe_load(double measured_load, const LatticeActivity& activity, double block_seconds) {
    if (!(block_seconds > 0.0) || !std::isfinite(measured_load) || measured_load < 0.0) return;
    LatticePrice& p = price_;
    if (!p.known) {
        p.known = true;
        p.recent = measured_load;
    }
    p.recent += one_pole(block_seconds, recent_smoothing_s) * (measured_load - p.recent);
    since_full_s_ += block_seconds;
    if (activity.awake > 0 && base_seen_) measured_full_s_ += block_seconds;
    if (activity.awake <= 0) {
        if (!base_seen_) p.base = measured_load;
        base_seen_ = true;
        p.base += one_pole(block_seconds, base_smoothing_s) * (measured_load - p.base);
    } else if (base_seen_) {
        const double above = std::max(0.0, measured_load - p.base);
        if (activity.event) {
            p.event = std::max(p.event, std::max(0.0, above - (activity.awake - 1) * p.mean));
        } else {
            p.mean += one_pole(block_seconds, mean_smoothing_s) * (above / activity.awake - p.mean);
        }
    }
    p.event *= std::exp(-block_seconds / event_memory_s);
}

void LodGovernor::set_lattice_prior(double event) {
    if (!(std::isfinite(event) && event >= 0.0)) return;
    price_.prior = event;
    prior_sizes_ = 0;
}

void LodGovernor::set_lattice_prior(const double* diameters_m, const double* events, int sizes) {
    // All or nothing: a size or figure that is not finite and positive (non-negative for the events), or
    // diameters out of order, leave the prior as it was.
    double largest = 0.0;
    for (int k = 0; k < sizes; ++k) {
        if (!(std::isfinite(diameters_m[k]) && diameters_m[k] > 0.0 && std::isfinite(events[k]) && events[k] >= 0.0)) return;
        if (k > 0 && !(diameters_m[k] > diameters_m[k - 1])) return;
        largest = std::max(largest, events[k]);
    }
    price_.prior = largest;
    if (sizes <= 0 || sizes > max_prior_sizes) {
        prior_sizes_ = 0;   // their largest for every size
        return;
    }
    std::copy(diameters_m, diameters_m + sizes, prior_diameters_.begin());
    std::copy(events, events + sizes, prior_events_.begin());
    prior_sizes_ = sizes;
}

double LodGovernor::prior_for(double diameter_m) const {
    if (prior_sizes_ == 0 || !(diameter_m > 0.0)) return price_.prior;
    return prior_events_[static_cast<std::size_t>(nearest_in_log(prior_diameters_.data(), prior_sizes_, diameter_m))];
}

bool LodGovernor::lattice_admissible(int full_active, double diameter_m) const {
    if (!price_.known) {
        // Live before the first measured callback: none (header, "The prior"). Offline (no prior): the
        // rules alone, reproducible, no spacing.
        if (price_.prior > 0.0) return false;
        return lattice_affordable(diameter_m);
    }
    if (since_full_s_ < settings_.full_spacing_s) return false;
    if (measured_full_s_ < learning_s && full_active > 0) return false;
    return lattice_affordable(diameter_m);
}

bool LodGovernor::lattice_affordable() const { return lattice_affordable(0.0); }

bool LodGovernor::lattice_affordable(double diameter_m) const {
    const LatticePrice& p = price_;
    const double peak = std::max(settings_.peak_budget, settings_.budget);
    const double event = std::max(p.event, prior_for(diameter_m));
    if (!p.known) return event <= peak;   // offline: no prior, nothing measured
    return p.recent + p.mean <= settings_.budget && p.recent + event <= peak;
}

}  // namespace ameoto
