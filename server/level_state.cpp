// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/level_state.hpp"

#include <cstdio>

namespace ameoto {

std::string describe_level(const LevelState& level, const std::string& scene, double default_rain_mm_per_h, double gain_db) {
    char text[480];
    const double spl = full_scale_spl_db(level.full_scale_pa, level.level_gain_db + gain_db);
    if (!level.automatic) {
        std::snprintf(text, sizeof text,
                      "level physical: 1.0 = %.0f Pa at the listener; gain %+.2f dB; 0 dBFS = %.2f dB SPL; limiter %s",
                      level.full_scale_pa, gain_db, spl, level.limiter ? "on" : "off");
    } else if (!std::isfinite(level.measured_lufs)) {
        std::snprintf(text, sizeof text,
                      "level auto: scene '%s' (default rain %g mm/h) is silent at its default rain: level gain %+.2f dB; "
                      "gain %+.2f dB; 0 dBFS = %.2f dB SPL; limiter %s",
                      scene.c_str(), default_rain_mm_per_h, level.level_gain_db, gain_db, spl, level.limiter ? "on" : "off");
    } else {
        // What the choice gave beyond target - measured makes up for the limiter (level_choice.hpp).
        const double share = level.level_gain_db - (level.target_lufs - level.measured_lufs);
        char made_up[80] = "";
        if (share > 0.005) std::snprintf(made_up, sizeof made_up, " (%+.2f dB of it making up for the limiter)", share);
        std::snprintf(text, sizeof text,
                      "level auto: scene '%s' (default rain %g mm/h) measures %.2f LUFS at the physical scale (1.0 = %.0f Pa); "
                      "target %.1f LUFS: level gain %+.2f dB%s; gain %+.2f dB; 0 dBFS = %.2f dB SPL; limiter %s",
                      scene.c_str(), default_rain_mm_per_h, level.measured_lufs, level.full_scale_pa, level.target_lufs,
                      level.level_gain_db, made_up, gain_db, spl, level.limiter ? "on" : "off");
    }
    return text;
}

}  // namespace ameoto
