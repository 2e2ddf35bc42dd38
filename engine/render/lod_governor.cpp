// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/lod_governor.hpp"

#include <algorithm>
#include <cmath>

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
        if (lattice_admissible(full_active)) {
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
    if (std::isfinite(event) && event >= 0.0) price_.prior = event;
}

bool LodGovernor::lattice_admissible(int full_active) const {
    if (!price_.known) return lattice_affordable();   // offline (no prior): reproducible, no spacing
    if (since_full_s_ < settings_.full_spacing_s) return false;
    if (measured_full_s_ < learning_s && full_active > 0) return false;
    return lattice_affordable();
}

bool LodGovernor::lattice_affordable() const {
    const LatticePrice& p = price_;
    const double peak = std::max(settings_.peak_budget, settings_.budget);
    const double event = std::max(p.event, p.prior);
    if (!p.known) return event <= peak;   // offline: no prior, nothing measured
    return p.recent + p.mean <= settings_.budget && p.recent + event <= peak;
}

}  // namespace ameoto
