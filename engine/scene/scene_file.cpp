// SPDX-License-Identifier: GPL-3.0-or-later
// The scene file: reading one (parse_scene: every field checked, an error names the file, line and
// field) and writing one (format_scene: numbers that read back exactly). The format is docs/scenes.md;
// the checks shared with OSC are scene_fields.hpp and validate_scene (scene_description.cpp).
#include "engine/scene/scene_description.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

#include "engine/scene/output_format.hpp"
#include "engine/scene/scene_fields.hpp"

namespace ameoto {

namespace scene_fields {
namespace {

struct Line {
    int number = 0;
    std::string word;                              // first word
    std::string argument;                          // `name X`, `surface NAME`: the second word
    std::vector<std::pair<std::string, std::string>> pairs;
};

class Reader {
public:
    Reader(const std::string& file, const Line& line) : file_(file), line_(line) {
        for (const auto& [k, v] : line.pairs) {
            if (values_.count(k)) fail(k, "given twice");
            values_[k] = v;
        }
    }
    [[noreturn]] void fail(const std::string& field, const std::string& reason) const {
        throw SceneFileError(file_, line_.number, field, reason);
    }
    bool has(const std::string& key) const { return values_.count(key) != 0; }
    std::string text(const std::string& key, const std::string& fallback, bool required = false) {
        const auto it = values_.find(key);
        if (it == values_.end()) {
            if (required) fail(key, "missing (" + line_.word + " needs it)");
            return fallback;
        }
        used_.insert(key);
        return it->second;
    }
    double number(const std::string& key, double fallback, Range range, const char* unit, bool required = false) {
        const auto it = values_.find(key);
        if (it == values_.end()) {
            if (required) fail(key, "missing (" + line_.word + " needs it)");
            return fallback;
        }
        used_.insert(key);
        return parse(key, it->second, range, unit);
    }
    double parse(const std::string& key, const std::string& value, Range range, const char* unit) const {
        // strtod, not stod: stod throws on underflow, so a subnormal such as 9.3e-313 (which format_scene
        // writes for a value that small; found by the fuzzer, tests/fuzz/crashes/crash-9019f465...)
        // would not read back. Overflow gives +-HUGE_VAL, which the range check refuses.
        char* end = nullptr;
        const double v = std::strtod(value.c_str(), &end);
        if (value.empty() || end != value.c_str() + value.size()) fail(key, "'" + value + "' is not a number");
        if (!in(range, v)) fail(key, scene_fields::number(v) + (unit[0] ? std::string(" ") + unit : "") + " is outside " + range_text(range));
        return v;
    }
    void finish() const {
        for (const auto& [k, v] : line_.pairs)
            if (!used_.count(k)) fail(k, "unknown key for '" + line_.word + "'");
    }

private:
    const std::string& file_;
    const Line& line_;
    std::map<std::string, std::string> values_;
    std::set<std::string> used_;
};

std::vector<std::string> words_of(const std::string& line) {
    std::vector<std::string> words;
    std::istringstream in(line);
    for (std::string w; in >> w;) words.push_back(w);
    return words;
}

}  // namespace
}  // namespace scene_fields

SceneDescription parse_scene(std::string_view text, const std::string& file) {
    using namespace scene_fields;
    if (text.size() > max_scene_file_bytes)
        throw SceneFileError(file, 0, "", "file of " + std::to_string(text.size()) + " bytes is larger than 64 KiB");
    SceneDescription s;
    s.name = "";
    bool have_header = false, have_name = false;
    std::set<std::string> seen;   // rain, listener, lod, accuracy: once each
    int number = 0, file_version = 1;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        std::string raw(text.substr(start, end - start));
        start = end + 1;
        ++number;
        if (!raw.empty() && raw.back() == '\r') raw.pop_back();
        if (raw.size() > max_scene_line)
            throw SceneFileError(file, number, "", "line longer than " + std::to_string(max_scene_line) + " characters");
        if (raw.find('\0') != std::string::npos) throw SceneFileError(file, number, "", "a NUL byte: not a text file");
        const auto words = words_of(raw);
        if (words.empty() || words[0][0] == '#') {
            if (end == text.size()) break;
            continue;
        }
        if (!have_header) {
            if (words[0] != "ameoto-scene")
                throw SceneFileError(file, number, "", "not an ameoto scene file (it must start with 'ameoto-scene 1')");
            if (words.size() != 2) throw SceneFileError(file, number, "version", "'ameoto-scene' takes one version number");
            int version = 0;
            try {
                std::size_t used = 0;
                version = std::stoi(words[1], &used);
                if (used != words[1].size()) throw std::invalid_argument("trailing");
            } catch (const std::exception&) {
                throw SceneFileError(file, number, "version", "'" + words[1] + "' is not a version number");
            }
            if (version > scene_format_version)
                throw SceneFileError(file, number, "version",
                                     "version " + std::to_string(version) + " needs a newer ameoto (this one reads versions 1 to " + std::to_string(scene_format_version) + ")");
            if (version < 1) throw SceneFileError(file, number, "version", "version " + std::to_string(version) + " does not exist");
            have_header = true;
            file_version = version;
            if (end == text.size()) break;
            continue;
        }
        Line line;
        line.number = number;
        line.word = words[0];
        static const std::set<std::string> known{"name", "rain", "listener", "lod", "surface", "accuracy", "output"};
        if (!known.count(line.word))
            throw SceneFileError(file, number, line.word, "unknown line (expected name, rain, listener, lod, surface, accuracy or output)");
        if (line.word == "output" && file_version < 2)
            throw SceneFileError(file, number, line.word, "the output line needs version 2 (start the file with 'ameoto-scene 2')");
        if (line.word == "accuracy" && file_version < 2)
            throw SceneFileError(file, number, line.word, "the accuracy line needs version 2 (start the file with 'ameoto-scene 2')");
        std::size_t first_pair = 1;
        if (line.word == "name" || line.word == "surface") {
            if (words.size() < 2 || words[1].find('=') != std::string::npos)
                throw SceneFileError(file, number, line.word, "'" + line.word + "' needs a name first");
            line.argument = words[1];
            first_pair = 2;
        }
        for (std::size_t i = first_pair; i < words.size(); ++i) {
            const std::size_t eq = words[i].find('=');
            if (eq == std::string::npos || eq == 0 || eq + 1 == words[i].size())
                throw SceneFileError(file, number, words[i], "expected key=value");
            line.pairs.emplace_back(words[i].substr(0, eq), words[i].substr(eq + 1));
        }
        Reader r(file, line);
        if (line.word == "name") {
            if (have_name) r.fail("name", "given twice");
            if (!line.pairs.empty() || words.size() > 2) r.fail("name", "takes one word");
            if (!is_scene_name(line.argument)) r.fail("name", "'" + line.argument + "' is not 1-32 of A-Z a-z 0-9 - _");
            s.name = line.argument;
            have_name = true;
        } else if (line.word == "rain" || line.word == "listener" || line.word == "lod") {
            if (!seen.insert(line.word).second) r.fail(line.word, "given twice");
            if (line.word == "rain") {
                RainDescription& rain = s.rain;
                rain.rate_mm_per_h = r.number("rate", rain.rate_mm_per_h, rate_range, "mm/h");
                rain.dsd = r.text("dsd", rain.dsd);
                if (std::find(dsd_names().begin(), dsd_names().end(), rain.dsd) == dsd_names().end())
                    r.fail("dsd", "'" + rain.dsd + "' is not one of marshall-palmer, joss-drizzle, joss-thunderstorm, gamma");
                rain.gamma_mu = r.number("mu", rain.gamma_mu, mu_range, "");
                rain.gamma_lambda_per_mm = r.number("lambda", rain.gamma_lambda_per_mm, lambda_range, "1/mm");
                rain.wind_m_per_s = r.number("wind", rain.wind_m_per_s, wind_range, "m/s");
                rain.wind_direction_rad = r.number("direction", rain.wind_direction_rad / degrees, {-720, 720}, "deg") * degrees;
                rain.gustiness = r.number("gust", rain.gustiness, gust_range, "");
            } else if (line.word == "listener") {
                ListenerDescription& l = s.listener;
                l.x_m = r.number("x", l.x_m, position_range, "m");
                l.y_m = r.number("y", l.y_m, position_range, "m");
                l.z_m = r.number("z", l.z_m, position_range, "m");
                l.facing_rad = r.number("facing", l.facing_rad / degrees, {-720, 720}, "deg") * degrees;
            } else {
                s.lod.budget_percent = r.number("budget", s.lod.budget_percent, budget_range, "%");
                const double full = r.number("full", s.lod.max_full, full_range, "drops");
                if (full != std::floor(full)) r.fail("full", "is not a whole number of drops");
                s.lod.max_full = static_cast<int>(full);
            }
        } else if (line.word == "output") {
            if (!seen.insert(line.word).second) r.fail(line.word, "given twice");
            s.gain_db = r.number("gain", s.gain_db, gain_range, "dB");
            if (r.has("format")) {
                if (file_version < 4) r.fail("format", "the format key needs version 4 (start the file with 'ameoto-scene 4')");
                s.output_format = r.text("format", "");
                std::string why;
                if (!parse_output_format(s.output_format, why)) r.fail("format", why);
            }
        } else if (line.word == "accuracy") {
            if (!seen.insert(line.word).second) r.fail(line.word, "given twice");
            if (r.has("cents") == r.has("db")) r.fail("accuracy", "give one of cents=C (frequency error) or db=D (spectral distance)");
            const bool cents = r.has("cents");
            const double value = cents ? r.number("cents", 0.0, {AccuracyLimits::cents_min, AccuracyLimits::cents_max}, "cents")
                                       : r.number("db", 0.0, {AccuracyLimits::decibels_min, AccuracyLimits::decibels_max}, "dB");
            s.accuracy = AccuracyBudget{cents ? AccuracyMeasure::cents : AccuracyMeasure::decibels, value};
        } else {   // surface
            if (s.surfaces.size() == static_cast<std::size_t>(max_scene_surfaces))
                r.fail("surface", "more than " + std::to_string(max_scene_surfaces) + " surfaces");
            SurfaceDescription f;
            f.name = line.argument;
            if (!is_scene_name(f.name)) r.fail("surface", "name '" + f.name + "' is not 1-32 of A-Z a-z 0-9 - _");
            const std::string kind = r.text("kind", "", true);
            const auto k = surface_kind(kind);
            if (!k) r.fail("kind", "'" + kind + "' is not one of umbrella, water, plate, ground");
            f.kind = *k;
            f.material = r.text("material", "", true);
            const std::string size = r.text("size", "", true);
            const std::size_t by = size.find('x');
            f.size_x_m = r.parse("size", size.substr(0, by), size_range, "m");
            f.size_y_m = by == std::string::npos ? f.size_x_m : r.parse("size", size.substr(by + 1), size_range, "m");
            f.x_m = r.number("x", 0.0, position_range, "m");
            f.y_m = r.number("y", 0.0, position_range, "m");
            f.z_m = r.number("z", 0.0, position_range, "m");
            if (f.kind == SurfaceKind::umbrella) {
                const double panels = r.number("panels", 8, panels_range, "");
                if (panels != std::floor(panels)) r.fail("panels", "is not a whole number");
                f.panels = static_cast<int>(panels);
                const std::string air = r.text("air", file_version >= scene_air_default_version ? "on" : "off");
                if (air != "on" && air != "off") r.fail("air", "'" + air + "' is not on or off");
                f.air = air == "on";
                const std::string impact = r.text("impact", "wet");
                const std::optional<ImpactModel> model = find_impact_model(impact);
                if (!model) r.fail("impact", "'" + impact + "' is not wet or seed");
                f.impact = *model;
            }
            if (r.has("node") && file_version < 3) r.fail("node", "the node key needs version 3 (start the file with 'ameoto-scene 3')");
            const double node = r.number("node", 1, node_range, "");
            if (node != std::floor(node)) r.fail("node", "is not a whole number");
            f.node = static_cast<int>(node);
            for (const auto& other : s.surfaces)
                if (other.name == f.name) r.fail("surface", "a second surface named '" + f.name + "'");
            s.surfaces.push_back(f);
        }
        r.finish();
        if (end == text.size()) break;
    }
    if (!have_header) throw SceneFileError(file, 0, "", "empty: no 'ameoto-scene 1' line");
    if (!have_name) s.name = "untitled";
    if (const std::string why = validate_scene(s); !why.empty()) throw SceneFileError(file, 0, "", why);
    return s;
}

std::string format_scene(const SceneDescription& s) {
    using namespace scene_fields;
    std::ostringstream out;
    // Older readers load what needs nothing new: version 3 only for surfaces on other nodes, 2 for accuracy
    // or a gain. An umbrella's air is written whenever it is on (the default of versions 1-4 is off), so
    // no file written here needs version 5.
    const bool nodes = std::any_of(s.surfaces.begin(), s.surfaces.end(), [](const SurfaceDescription& f) { return f.node != 1; });
    out << "ameoto-scene " << (!s.output_format.empty() ? 4 : nodes ? 3 : s.accuracy || s.gain_db != 0.0 ? 2 : 1) << "\n";
    out << "# written by ameoto; units: rate mm/h, wind m/s, direction and facing degrees, sizes and positions m,\n";
    out << "# budget % of the block period, gain dB (docs/scenes.md)\n";
    out << "name " << s.name << "\n";
    const RainDescription& r = s.rain;
    out << "rain rate=" << number(r.rate_mm_per_h) << " dsd=" << r.dsd << " mu=" << number(r.gamma_mu)
        << " lambda=" << number(r.gamma_lambda_per_mm) << " wind=" << number(r.wind_m_per_s)
        << " direction=" << degrees_text(r.wind_direction_rad) << " gust=" << number(r.gustiness) << "\n";
    out << "listener x=" << number(s.listener.x_m) << " y=" << number(s.listener.y_m) << " z=" << number(s.listener.z_m)
        << " facing=" << degrees_text(s.listener.facing_rad) << "\n";
    out << "lod budget=" << number(s.lod.budget_percent) << " full=" << s.lod.max_full << "\n";
    for (const SurfaceDescription& f : s.surfaces) {
        out << "surface " << f.name << " kind=" << surface_kind_name(f.kind) << " material=" << f.material
            << " size=" << number(f.size_x_m) << "x" << number(f.size_y_m) << " x=" << number(f.x_m)
            << " y=" << number(f.y_m) << " z=" << number(f.z_m);
        if (f.kind == SurfaceKind::umbrella) out << " panels=" << f.panels;
        if (f.node != 1) out << " node=" << f.node;
        if (f.kind == SurfaceKind::umbrella && f.air) out << " air=on";   // off is versions 1-4's default
        if (f.kind == SurfaceKind::umbrella && f.impact != ImpactModel::wet) out << " impact=" << impact_model_name(f.impact);
        out << "\n";
    }
    if (s.gain_db != 0.0 || !s.output_format.empty()) {
        out << "output";
        if (s.gain_db != 0.0) out << " gain=" << number(s.gain_db);
        if (!s.output_format.empty()) out << " format=" << s.output_format;
        out << "\n";
    }
    if (s.accuracy) out << "accuracy " << accuracy_measure_name(s.accuracy->measure) << "=" << number(s.accuracy->value) << "\n";
    return out.str();
}

}  // namespace ameoto
