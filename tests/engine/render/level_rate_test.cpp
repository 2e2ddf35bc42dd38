// SPDX-License-Identifier: GPL-3.0-or-later
// Level against rain rate for each kind of surface (engine/render/surface_source.hpp), measured and
// checked against the per-drop energy law the engine uses: independent drops add in power, so the mean
// power over T seconds is the sum over the drops struck of each drop's own output energy e(D), over T.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "engine/models/drop.hpp"
#include "engine/render/surface_source.hpp"
#include "engine/scene/rain_spawner.hpp"
#include "tests/support/timing_scale.hpp"

using namespace ameoto;

namespace {

constexpr double fs = 48000.0;

SurfaceDescription surface(SurfaceKind kind, const char* material, double sx, double sy) {
    SurfaceDescription s;
    s.name = material;
    s.kind = kind;
    s.material = material;
    s.size_x_m = sx;
    s.size_y_m = sy;
    return s;
}

// e(D): the output energy (Pa^2 s at 1 m) of one drop at terminal speed, averaged over `repeats` strikes
// at random points (a plate's modes depend on where it is struck; water's bubbles are random), each on a
// fresh surface, rendered until it has died away.
double drop_energy(const SurfaceDescription& s, double d, int repeats, double seconds) {
    double total = 0.0;
    for (int k = 0; k < repeats; ++k) {
        auto source = make_surface_source(s, fs, 100 + static_cast<std::uint64_t>(k));
        Random rng(1000 + static_cast<std::uint64_t>(k));
        const double u = rng.uniform(), v = rng.uniform();
        source->strike(d, arrival_speed(d, 998.0), 998.0, u, v, rng);
        const int frames = static_cast<int>(seconds * fs);
        for (int i = 0; i < frames; ++i) {
            const double p = source->sample();
            total += p * p / fs;
        }
    }
    return total / repeats;
}

struct Level {
    double measured_db = 0.0, predicted_db = 0.0;
};

Level level_at(const SurfaceDescription& s, double rate, double seconds, const std::vector<double>& grid,
               const std::vector<double>& log_energy) {
    auto source = make_surface_source(s, fs, 7);
    RainSpawner rain(RainSpawner::Config{.area_m2 = source->area_m2()});
    rain.set_rate_now(rate);
    Random rng(11);
    const int frames = static_cast<int>(seconds * fs);
    double power = 0.0, predicted = 0.0;
    auto energy_of = [&](double d) {   // log-log interpolation in the e(D) table
        if (d <= grid.front()) return std::exp(log_energy.front());
        if (d >= grid.back()) return std::exp(log_energy.back());
        std::size_t k = 1;
        while (grid[k] < d) ++k;
        const double t = std::log(d / grid[k - 1]) / std::log(grid[k] / grid[k - 1]);
        return std::exp(log_energy[k - 1] + t * (log_energy[k] - log_energy[k - 1]));
    };
    for (int i = 0; i < frames; ++i) {
        const int n = rain.advance(1.0 / fs, rng);
        for (int a = 0; a < n; ++a) {
            const double d = rain.sample_diameter_m(rng);
            source->strike(d, arrival_speed(d, 998.0), 998.0, rng.uniform(), rng.uniform(), rng);
            predicted += energy_of(d);
        }
        const double p = source->sample();
        power += p * p / fs;
    }
    return {10.0 * std::log10(power / seconds), 10.0 * std::log10(predicted / seconds)};
}

}  // namespace

TEST_CASE("level against rain rate: every surface follows the per-drop energy law") {
    struct Case {
        SurfaceDescription surface;
        int repeats;
        double ring_s, seconds;
    };
    const std::vector<Case> cases = {
        // Water: a drop's energy is mostly its bubble's when it has one, and bubbles are rare above 1.1 mm
        // and loud: many repeats and a long rain, so both sides see enough of them.
        {surface(SurfaceKind::water, "pond", 1.0, 1.0), 600, 0.15, 30.0},
        {surface(SurfaceKind::plate, "glass", 0.8, 0.6), 40, 1.5, 8.0},
        {surface(SurfaceKind::ground, "leaves", 1.0, 1.0), 20, 0.1, 4.0},
        {surface(SurfaceKind::ground, "soil", 1.0, 1.0), 20, 0.1, 4.0},
    };
    for (const Case& c : cases) {
        const std::string name = c.surface.material;
        CAPTURE(name);
        // Under the sanitizers the soil only: the pond's 600 repeats and 30 s of rain cost minutes there,
        // the glass's 40 repeats of 1.5 s rings about 25 s (the plate's code runs under them in
        // tests/engine/models), and leaves run soil's code (SoftGround) with other constants; the
        // Release run checks all four.
        if (ameoto::test::sanitized_build() && name != "soil") continue;
        std::vector<double> grid, log_energy;
        // Sizes on both sides of each entrainment threshold (water: bubbles from 0.8 to 1.1 mm, then
        // rarely, then more often above 2.2 mm): e(D) jumps there, and interpolating across a jump
        // would misprice every drop in between.
        for (double mm : {0.5, 0.6, 0.7, 0.79, 0.81, 0.9, 1.0, 1.09, 1.11, 1.3, 1.6, 1.9, 2.19, 2.21, 2.7, 3.3, 4.0, 5.0, 6.0}) {
            const double d = mm * 1e-3;
            grid.push_back(d);
            log_energy.push_back(std::log(std::max(drop_energy(c.surface, d, c.repeats, c.ring_s), 1e-300)));
        }
        const double rates[] = {1.0, 10.0, 100.0};
        std::vector<Level> levels;
        for (double r : rates) levels.push_back(level_at(c.surface, r, c.seconds, grid, log_energy));
        const double measured_slope = (levels[2].measured_db - levels[0].measured_db) / 2.0;
        const double predicted_slope = (levels[2].predicted_db - levels[0].predicted_db) / 2.0;
        MESSAGE(name << ": " << levels[0].measured_db << " / " << levels[1].measured_db << " / " << levels[2].measured_db
                     << " dB re 1 Pa^2 at 1, 10, 100 mm/h; slope " << measured_slope << " dB per decade (the per-drop law: "
                     << predicted_slope << ")");
        // Tolerance: 1.5 dB per level and per decade: the law holds for drops that do not overlap in phase
        // (they are random), and each e(D) is an average (water's bubbles are drawn per drop).
        for (const Level& l : levels) CHECK(std::abs(l.measured_db - l.predicted_db) < 1.5);
        CHECK(std::abs(measured_slope - predicted_slope) < 1.5);
        CHECK(measured_slope > 9.0);   // at least the 10 dB per decade of a fixed drop mix, less rounding
    }
}
