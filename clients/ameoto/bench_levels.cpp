// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_levels.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <optional>
#include <stdexcept>
#include <thread>

#include "clients/ameoto/a_weighting.hpp"
#include "clients/ameoto/bench_suite_opening.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/json_text.hpp"
#include "clients/ameoto/number_text.hpp"
#include "clients/ameoto/option_reader.hpp"
#include "engine/render/renderer.hpp"

namespace ameoto::client {

namespace {

constexpr double level_reference_pa = 20e-6;
constexpr double levels_standard_rates[] = {25.0, 50.0, 100.0};

double power_level_db(double mean_square_pa2) {
    return mean_square_pa2 > 0.0 ? 10.0 * std::log10(mean_square_pa2 / (level_reference_pa * level_reference_pa)) : -INFINITY;
}

// Sums a pressure signal's power, A-weighted and not: what levels_of and measure_level read.
class LevelMeter {
public:
    explicit LevelMeter(double sample_rate) : weighting_(sample_rate) {}
    void add(double p) {
        ++count_;
        if (!std::isfinite(p)) {
            finite_ = false;
            return;
        }
        const double a = weighting_.process(p);
        sum_a_ += a * a;
        sum_z_ += p * p;
    }
    LevelReading reading() const {
        LevelReading r;
        const double n = static_cast<double>(std::max(count_, 1L));
        r.laeq_db = power_level_db(sum_a_ / n);
        r.leq_db = power_level_db(sum_z_ / n);
        r.finite = finite_;
        return r;
    }
    // The weighting filter runs through a settling time too, so its own transient is not counted.
    void warm(double p) {
        if (std::isfinite(p)) weighting_.process(p);
        else finite_ = false;
    }

private:
    AWeighting weighting_;
    double sum_a_ = 0.0, sum_z_ = 0.0;
    long count_ = 0;
    bool finite_ = true;
};

// One render to measure: a scene at a rate, and where its reading goes.
struct LevelJob {
    const SceneDescription* scene;
    double rain;
    LevelReading* out;
};

// Runs the jobs on `threads` threads, each taking the next job (renders are independent: each has its own
// Renderer; the engine's shared caches are locked). The first exception is rethrown here.
void run_level_jobs(std::vector<LevelJob>& jobs, double seconds, std::uint64_t seed, int threads) {
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::atomic<bool> failed{false};
    auto worker = [&] {
        for (std::size_t i = next++; i < jobs.size() && !failed; i = next++) {
            try {
                *jobs[i].out = measure_level(*jobs[i].scene, jobs[i].rain, seconds, seed);
            } catch (...) {
                if (!failed.exchange(true)) failure = std::current_exception();
            }
        }
    };
    const int n = std::clamp(threads, 1, static_cast<int>(std::max<std::size_t>(jobs.size(), 1)));
    std::vector<std::thread> pool;
    for (int t = 1; t < n; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
}

void fit_level_slopes(SceneLevels& s) {
    s.slope_a_db_per_decade = slope_db_per_decade(s.levels, true);
    s.slope_z_db_per_decade = slope_db_per_decade(s.levels, false);
}

}  // namespace

std::vector<double> level_rates(double default_rain_mm_per_h) {
    std::vector<double> rates{default_rain_mm_per_h};
    for (double r : levels_standard_rates)
        if (std::fabs(r - default_rain_mm_per_h) > 1e-9) rates.push_back(r);
    std::sort(rates.begin(), rates.end());
    return rates;
}

LevelReading levels_of(const std::vector<double>& pressure_pa, double sample_rate) {
    LevelMeter meter(sample_rate);
    for (double p : pressure_pa) meter.add(p);
    return meter.reading();
}

LevelReading measure_level(const SceneDescription& scene_in, double rain_mm_per_h, double seconds, std::uint64_t seed) {
    if (!(seconds > 0.0)) throw std::invalid_argument("bench levels: seconds must be positive");
    const auto start = std::chrono::steady_clock::now();
    SceneDescription scene = scene_in;
    scene.rain.rate_mm_per_h = rain_mm_per_h;
    // As run_render_scene (render_scene.cpp) and ameotod --offline configure it.
    RendererConfig base;
    base.sample_rate = levels_sample_rate;
    base.channels = 1;
    base.seed = seed;
    base.adaptive_lod = false;
    Renderer renderer(configure_for_scene(base, scene));
    const double full_scale_pa = base.full_scale_pa;

    constexpr int block = 512;
    std::vector<float> buffer(block);
    float* out[1] = {buffer.data()};
    LevelMeter meter(levels_sample_rate);
    const long settle = std::lround(levels_settle_seconds * levels_sample_rate);
    const long total = settle + std::max(1L, std::lround(seconds * levels_sample_rate));
    for (long done = 0; done < total;) {
        const int n = static_cast<int>(std::min<long>(block, total - done));
        renderer.process(n, out);
        for (int i = 0; i < n; ++i) {
            const double p = static_cast<double>(buffer[static_cast<std::size_t>(i)]) * full_scale_pa;
            if (done + i < settle) meter.warm(p);
            else meter.add(p);
        }
        done += n;
    }
    LevelReading r = meter.reading();
    r.rain_mm_per_h = rain_mm_per_h;
    r.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

SceneLevels measure_scene_levels(const SceneDescription& scene, const std::vector<double>& rates, double seconds,
                                 std::uint64_t seed, int threads) {
    SceneLevels s;
    s.scene = scene;
    s.levels.resize(rates.size());
    std::vector<LevelJob> jobs;
    for (std::size_t i = 0; i < rates.size(); ++i) jobs.push_back({&s.scene, rates[i], &s.levels[i]});
    run_level_jobs(jobs, seconds, seed, threads);
    fit_level_slopes(s);
    return s;
}

double slope_db_per_decade(const std::vector<LevelReading>& levels, bool a_weighted) {
    // Least squares of L = a + k log10(R): k = cov(x, L) / var(x).
    double mx = 0.0, my = 0.0;
    int n = 0;
    for (const LevelReading& l : levels) {
        const double y = a_weighted ? l.laeq_db : l.leq_db;
        if (!(l.rain_mm_per_h > 0.0) || !std::isfinite(y)) continue;
        mx += std::log10(l.rain_mm_per_h);
        my += y;
        ++n;
    }
    if (n < 2) return NAN;
    mx /= n;
    my /= n;
    double sxy = 0.0, sxx = 0.0;
    for (const LevelReading& l : levels) {
        const double y = a_weighted ? l.laeq_db : l.leq_db;
        if (!(l.rain_mm_per_h > 0.0) || !std::isfinite(y)) continue;
        const double x = std::log10(l.rain_mm_per_h) - mx;
        sxy += x * (y - my);
        sxx += x * x;
    }
    return sxx > 0.0 ? sxy / sxx : NAN;
}

// ---- the command ---------------------------------------------------------------------------------------

namespace {

struct LevelsOptions {
    double seconds = 20.0;
    std::uint64_t seed = 1;   // ameoto render scene's default
    int threads = 2;
    bool json = false;
    bool markdown = false;
    std::vector<std::string> scenes;   // empty: every built-in scene
};

bool parse_levels_options(const CommandWords& words, LevelsOptions& o, std::string& error, bool& help) {
    OptionReader reader(words);
    for (auto kind = reader.next_word(); kind != OptionReader::Word::end; kind = reader.next_word()) {
        if (kind == OptionReader::Word::positional) {
            if (reader.positional() == "levels") continue;
            error = "unexpected argument '" + reader.positional() + "'";
            return false;
        }
        const std::string& name = reader.name();
        if (name == "--help" || name == "-h") {
            help = true;
            return true;
        }
        if (name == "--json" || name == "--markdown") {
            if (!reader.flag_into(error)) return false;
            (name == "--json" ? o.json : o.markdown) = true;
        } else if (name == "--seconds") {
            const auto v = reader.number_into(0.1, 600.0, "s", error);
            if (!v) return false;
            o.seconds = *v;
        } else if (name == "--threads") {
            const auto v = reader.number_into(1.0, 64.0, "", error);
            if (!v) return false;
            if (*v != std::floor(*v)) {
                error = "--threads: give a whole number, 1..64";
                return false;
            }
            o.threads = static_cast<int>(*v);
        } else if (name == "--seed") {
            std::string value;
            if (!reader.value_into(value, error)) return false;
            char* end = nullptr;
            errno = 0;
            const unsigned long long v = std::strtoull(value.c_str(), &end, 10);
            if (value.empty() || *end != '\0' || errno != 0 || value[0] == '-') {
                error = "--seed: '" + value + "' is not an integer in 0..18446744073709551615";
                return false;
            }
            o.seed = v;
        } else if (name == "--scene") {
            std::string value;
            if (!reader.value_into(value, error)) return false;
            if (!builtin_scene(value)) {
                error = "--scene: '" + value + "' is not a built-in scene (umbrella, pond, tin-roof, forest, street)";
                return false;
            }
            o.scenes.push_back(value);
        } else {
            error = "unknown option '" + name + "'";
            return false;
        }
    }
    if (o.json && o.markdown) {
        error = "--json and --markdown: choose one";
        return false;
    }
    return true;
}

std::string levels_listener_text(const ListenerDescription& l) {
    return "(" + short_number(l.x_m) + ", " + short_number(l.y_m) + ", " + short_number(l.z_m) + ") m";
}

std::string db_text(double v) { return std::isfinite(v) ? fixed(v, 1) : "-"; }

const LevelReading* level_at_rate(const SceneLevels& s, double rate) {
    for (const LevelReading& l : s.levels)
        if (std::fabs(l.rain_mm_per_h - rate) < 1e-9) return &l;
    return nullptr;
}

std::string level_pair_text(const LevelReading* l) { return l ? db_text(l->laeq_db) + " / " + db_text(l->leq_db) : "-"; }

std::string levels_today_utc() {
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char buffer[16];
    std::strftime(buffer, sizeof buffer, "%Y-%m-%d", &tm);
    return buffer;
}

void print_levels_markdown(const std::vector<SceneLevels>& all, const LevelsOptions& o, double wall, const CommandIo& io) {
    io.out << "Measured with `ameoto bench levels --seconds " << short_number(o.seconds) << " --markdown` ("
           << levels_today_utc() << ", seed " << o.seed << ", " << fixed(wall, 0) << " s on " << o.threads
           << " threads): LAeq / Leq in dB re 20 uPa at the listening point (mono: every source summed there), "
           << short_number(o.seconds) << " s at 48 kHz after " << short_number(levels_settle_seconds)
           << " s of settling; slopes by least squares over the four rates.\n\n"
           << "| scene | listener | default rain | at default | 25 mm/h | 50 mm/h | 100 mm/h | slope, dB/decade (A / Z) |\n"
           << "|---|---|---|---|---|---|---|---|\n";
    for (const SceneLevels& s : all)
        io.out << "| " << s.scene.name << " | " << levels_listener_text(s.scene.listener) << " | "
               << short_number(s.scene.rain.rate_mm_per_h) << " mm/h | " << level_pair_text(level_at_rate(s, s.scene.rain.rate_mm_per_h))
               << " | " << level_pair_text(level_at_rate(s, 25.0)) << " | " << level_pair_text(level_at_rate(s, 50.0)) << " | "
               << level_pair_text(level_at_rate(s, 100.0)) << " | " << db_text(s.slope_a_db_per_decade) << " / "
               << db_text(s.slope_z_db_per_decade) << " |\n";
}

void print_levels_json(const std::vector<SceneLevels>& all, const LevelsOptions& o, const CommandIo& io) {
    for (const SceneLevels& s : all) {
        io.out << "{\"scene\":" << json_string(s.scene.name) << ",\"listener_m\":[" << json_number(s.scene.listener.x_m)
               << "," << json_number(s.scene.listener.y_m) << "," << json_number(s.scene.listener.z_m)
               << "],\"default_rain_mm_per_h\":" << json_number(s.scene.rain.rate_mm_per_h)
               << ",\"seconds\":" << json_number(o.seconds) << ",\"seed\":" << o.seed << ",\"levels\":[";
        for (std::size_t i = 0; i < s.levels.size(); ++i) {
            const LevelReading& l = s.levels[i];
            io.out << (i ? "," : "") << "{\"rain_mm_per_h\":" << json_number(l.rain_mm_per_h)
                   << ",\"laeq_db\":" << json_number(l.laeq_db) << ",\"leq_db\":" << json_number(l.leq_db)
                   << ",\"render_seconds\":" << json_number(l.render_seconds) << "}";
        }
        io.out << "],\"slope_a_db_per_decade\":" << json_number(s.slope_a_db_per_decade)
               << ",\"slope_z_db_per_decade\":" << json_number(s.slope_z_db_per_decade) << "}\n";
    }
}

void print_levels_table(const std::vector<SceneLevels>& all, const CommandIo& io) {
    io.out << "scene      listener (m)       rain mm/h   LAeq dB   Leq dB\n";
    for (const SceneLevels& s : all) {
        bool first = true;
        for (const LevelReading& l : s.levels) {
            char line[160];
            std::snprintf(line, sizeof line, "%-10s %-18s %9s%s %8s %8s\n", first ? s.scene.name.c_str() : "",
                          first ? levels_listener_text(s.scene.listener).c_str() : "", short_number(l.rain_mm_per_h).c_str(),
                          std::fabs(l.rain_mm_per_h - s.scene.rain.rate_mm_per_h) < 1e-9 ? "*" : " ",
                          db_text(l.laeq_db).c_str(), db_text(l.leq_db).c_str());
            io.out << line;
            first = false;
        }
        io.out << "           slope, dB per decade:   " << db_text(s.slope_a_db_per_decade) << " (A)  "
               << db_text(s.slope_z_db_per_decade) << " (Z)\n";
    }
    io.out << "(* the scene's default rain; dB re 20 uPa at the listening point)\n";
}

}  // namespace

std::string levels_bench_usage() {
    return "usage: ameoto bench levels [--seconds S] [--scene NAME]... [--seed N] [--threads T] [--json | --markdown]\n"
           "\n"
           "Renders each built-in scene offline with the engine ameotod runs (as ameoto render scene: seed 1,\n"
           "no load-dependent detail) at its default rain, 25, 50 and 100 mm/h, and measures at the listening\n"
           "point (a mono render: every source summed there) the A-weighted LAeq (IEC 61672-1) and the\n"
           "unweighted Leq, dB re 20 uPa, after 1 s of settling, with each scene's slope in dB per decade of\n"
           "rain rate (least squares over its rates). docs/levels.md compares them with measured rain noise.\n"
           "\n"
           "Options:\n"
           "  --seconds S     audio measured per scene and rate, 0.1..600 s (default 20)\n"
           "  --scene NAME    only this built-in scene (umbrella, pond, tin-roof, forest, street); repeatable\n"
           "  --seed N        the rain's seed (default 1, as ameoto render scene)\n"
           "  --threads T     renders at once, 1..64 (default 2)\n"
           "  --json          one JSON object per scene, one per line\n"
           "  --markdown      docs/levels.md's table, with the command and date\n"
           "\n"
           "Exit status: 0 measured; 1 a render failed or gave non-finite samples; 2 usage error.\n"
           "\n"
           "Examples:\n"
           "  ameoto bench levels\n"
           "  ameoto bench levels --scene tin-roof --seconds 5 --json\n";
}

int run_levels_bench(const CommandWords& words, const CommandIo& io) {
    LevelsOptions o;
    if (const auto done = open_bench_suite(words, io, "levels", o, parse_levels_options, levels_bench_usage)) return *done;
    if (o.scenes.empty()) o.scenes = builtin_scene_names();
    const auto start = std::chrono::steady_clock::now();
    std::vector<SceneLevels> all(o.scenes.size());
    std::vector<LevelJob> jobs;
    for (std::size_t i = 0; i < o.scenes.size(); ++i) {
        all[i].scene = *builtin_scene(o.scenes[i]);
        const std::vector<double> rates = level_rates(all[i].scene.rain.rate_mm_per_h);
        all[i].levels.resize(rates.size());
        for (std::size_t j = 0; j < rates.size(); ++j) jobs.push_back({&all[i].scene, rates[j], &all[i].levels[j]});
    }
    // The heaviest renders first, so that two threads finish together.
    std::stable_sort(jobs.begin(), jobs.end(), [](const LevelJob& a, const LevelJob& b) { return a.rain > b.rain; });
    io.err << "ameoto bench levels: " << jobs.size() << " renders of " << short_number(o.seconds + levels_settle_seconds)
           << " s on " << o.threads << " thread(s)...\n";
    try {
        run_level_jobs(jobs, o.seconds, o.seed, o.threads);
    } catch (const std::exception& e) {
        io.err << "ameoto bench levels: " << e.what() << "\n";
        return exit_status::refused;
    }
    bool finite = true;
    for (SceneLevels& s : all) {
        fit_level_slopes(s);
        for (const LevelReading& l : s.levels) finite = finite && l.finite;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.json) print_levels_json(all, o, io);
    else if (o.markdown) print_levels_markdown(all, o, wall, io);
    else print_levels_table(all, io);
    io.err << "ameoto bench levels: " << fixed(wall, 1) << " s\n";
    if (!finite) {
        io.err << "ameoto bench levels: NON-FINITE samples\n";
        return exit_status::refused;
    }
    return exit_status::ok;
}

}  // namespace ameoto::client
