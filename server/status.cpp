// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/status.hpp"

#include "engine/render/output_stage.hpp"

namespace ameoto {
namespace {

// OSC's i is 32 bits; a counter past that reports the largest value instead of wrapping negative.
std::int32_t saturate_int32(std::uint64_t v) { return v > 2147483647u ? 2147483647 : static_cast<std::int32_t>(v); }

}  // namespace

std::vector<protocol::OscArgument> StatusReport::arguments() {
    using protocol::OscArgument;
    const AudioSnapshot s = bridge_.snapshot();
    const std::uint64_t late = s.late_commands;
    return {OscArgument::from_float(static_cast<float>(s.cpu_average_percent)),
            OscArgument::from_float(static_cast<float>(bridge_.take_cpu_peak_percent())),
            OscArgument::from_float(static_cast<float>(drops_per_second_.load())),
            OscArgument::from_int(s.active_full_drops),   // full tier: lattice drops
            OscArgument::from_int(s.active_impacts),      // template tier: recorded impacts replayed
            OscArgument::from_int(s.active_grains),       // texture tier: noise grains
            OscArgument::from_int(saturate_int32(backend_.xruns())),
            OscArgument::from_int(saturate_int32(late)),
            OscArgument::from_float(static_cast<float>(bridge_.sample_rate())),
            OscArgument::from_int(backend_.block_size()),
            // Seconds, as a float every OSC client reads (Pd 0.53 and sclang 3.13 cannot read int64).
            OscArgument::from_float(static_cast<float>(static_cast<double>(s.frames) / bridge_.sample_rate())),
            OscArgument::from_float(static_cast<float>(s.rain_rate_mm_per_h)),
            OscArgument::from_string(backend_.name()),
            // The audio clock against the wall clock (JACK: its loop's period; the null backend: 0).
            OscArgument::from_float(static_cast<float>(s.clock_ppm)),
            OscArgument::from_int(saturate_int32(s.clipped_samples)),
            // What 0 dBFS is at the listener now, dB SPL (1.0 = full_scale_pa, less the level gain and the gain).
            OscArgument::from_float(static_cast<float>(full_scale_spl_db(bridge_.config().full_scale_pa, s.output_gain_db)))};
}

void StatusReport::measure_rate() {
    const AudioSnapshot s = bridge_.snapshot();
    if (s.frames > rate_frames_) {
        drops_per_second_ = static_cast<double>(s.drops - rate_drops_) * backend_.sample_rate() / static_cast<double>(s.frames - rate_frames_);
        rate_drops_ = s.drops;
        rate_frames_ = s.frames;
    }
}

}  // namespace ameoto
