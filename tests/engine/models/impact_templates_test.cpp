// SPDX-License-Identifier: GPL-3.0-or-later
// The template level of detail against the full model (engine/models/impact_templates.hpp).
#include "engine/models/impact_templates.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <vector>

#include "engine/core/fft.hpp"
#include "engine/models/drop.hpp"
#include "tests/support/rt_probe_scope.hpp"
#include "tests/support/relative_approx.hpp"
#include "tests/support/sanitizer_bounds.hpp"

using namespace ameoto;

namespace {

DropOnCanopyConfig scene_config() {
    DropOnCanopyConfig c;
    c.max_diameter = 6.1e-3;
    c.gap_m = 0.0;
    return c;
}

// Power in third-octave bands from 100 Hz to 16 kHz (a direct DFT per band centre would be slow; an
// FFT-free estimate: the signal's energy through each band by summing |X(f)|^2 of a radix-2 FFT).
std::vector<double> band_powers(std::vector<double> x, double rate) {
    std::size_t n = 1;
    while (n < x.size()) n <<= 1;
    std::vector<std::complex<double>> a(n);
    for (std::size_t i = 0; i < x.size(); ++i) a[i] = x[i];
    fft_in_place(a);
    std::vector<double> bands;
    for (double centre = 100.0; centre <= 16000.0; centre *= std::pow(2.0, 1.0 / 3.0)) {
        const double lo = centre / std::pow(2.0, 1.0 / 6.0), hi = centre * std::pow(2.0, 1.0 / 6.0);
        double p = 1e-300;
        for (std::size_t k = 1; k < n / 2; ++k) {
            const double f = rate * static_cast<double>(k) / static_cast<double>(n);
            if (f >= lo && f < hi) p += std::norm(a[k]);
        }
        bands.push_back(p);
    }
    return bands;
}

struct TestDrop {
    double d, x, y;
};

std::vector<double> render_full(const TestDrop& drop, int frames) {
    DropOnCanopy scene(scene_config());
    REQUIRE(scene.drop(drop.d, 0.0, drop.x, drop.y));
    std::vector<double> out;
    float frame[1];
    for (int i = 0; i < frames; ++i) {
        scene.process_frame(frame);
        out.push_back(frame[0]);
    }
    return out;
}

std::vector<double> render_template(const ImpactTemplateTable& t, const TestDrop& drop, int frames) {
    DropOnCanopy scene(scene_config());
    TemplatePool pool;
    const CanopyHit hit = scene.canopy().locate(drop.x, drop.y);
    REQUIRE(pool.add(hit, t, drop.d, 0.0, scene.config().liquid.density));
    std::vector<double> out;
    float frame[1];
    for (int i = 0; i < frames; ++i) {
        pool.emit(t, [&](CanopyHit h, double f) { scene.surface().apply_force(h, f); });
        scene.process_frame(frame);
        out.push_back(frame[0]);
    }
    return out;
}

double lsd_db(const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const double d = 10.0 * std::log10(a[i] / b[i]);
        sum += d * d;
    }
    return std::sqrt(sum / static_cast<double>(a.size()));
}

}  // namespace

// One recording for the whole file (about 1 s of full-model runs).
const ImpactTemplateTable& table() {
    static const ImpactTemplateTable t = record_impact_templates(scene_config());
    return t;
}

TEST_CASE("impact templates: the grid, its lookup, and a recording that pushes the membrane down") {
    const ImpactTemplateTable& t = table();
    REQUIRE(t.used.size() == t.diameters_m.size());
    for (int u : t.used) CHECK((u >= 1 && u <= t.length));
    REQUIRE(t.diameters_m.size() >= 50u);   // 0.5..6 mm in 5 % steps: 51 sizes
    CHECK(t.diameters_m.front() == ameoto::test::relative(0.5e-3));
    CHECK(t.diameters_m.back() <= 6e-3 * (1 + 1e-9));
    CHECK(t.nearest(0.1e-3) == 0);
    CHECK(t.nearest(9e-3) == static_cast<int>(t.diameters_m.size()) - 1);
    for (std::size_t k = 0; k + 1 < t.diameters_m.size(); ++k) {
        CHECK(t.nearest(t.diameters_m[k]) == static_cast<int>(k));
        CHECK(t.nearest(t.diameters_m[k] * 1.02) == static_cast<int>(k));   // below the geometric midpoint 1.0247
    }
    // Every recording: the first contact pushes the membrane down (negative along +n), and its impulse
    // is of the order of the drop's momentum m V (between 0.5 and 2.2 m V: an elastic bounce gives 2).
    for (std::size_t k = 0; k < t.diameters_m.size(); k += 10) {
        CAPTURE(t.diameters_m[k]);
        double impulse = 0.0;
        for (int n = 0; n < t.length; ++n) impulse += t.force(static_cast<int>(k), n) / t.sample_rate;
        const double d = t.diameters_m[k];
        const double momentum = t.density * 3.14159265358979 / 6 * d * d * d * t.speeds_m_per_s[k];
        CHECK(-impulse > 0.5 * momentum);
        CHECK(-impulse < 2.2 * momentum);
    }
}

TEST_CASE("impact templates: each recording's CPU time, and the most any block's length of it took") {
    // What the governor's first price of a lattice drop reads (lod_governor.hpp, "The prior"): measured,
    // so the checks are its shape, not its figures.
    const ImpactTemplateTable& t = table();
    REQUIRE(t.cpu_chunks == t.length / ImpactTemplateTable::cpu_chunk);
    REQUIRE(t.cpu_s.size() == t.diameters_m.size() * static_cast<std::size_t>(t.cpu_chunks + 1));
    double total = 0.0;
    for (std::size_t k = 0; k < t.diameters_m.size(); ++k) {
        const double* cum = t.cpu_s.data() + k * static_cast<std::size_t>(t.cpu_chunks + 1);
        CHECK(cum[0] == 0.0);
        for (int c = 0; c < t.cpu_chunks; ++c) CHECK(cum[c + 1] >= cum[c]);   // cumulative
        CHECK(cum[t.cpu_chunks] > 0.0);
        total = std::max(total, cum[t.cpu_chunks]);
    }
    const double w64 = t.worst_cpu_s(64), w256 = t.worst_cpu_s(256), whole = t.worst_cpu_s(t.length);
    MESSAGE("worst CPU in 64 / 256 frames / a whole recording: " << 1e3 * w64 << " / " << 1e3 * w256 << " / " << 1e3 * whole << " ms");
    CHECK(w64 > 0.0);
    CHECK(w64 <= w256);
    CHECK(w256 <= whole);
    CHECK(whole == total);   // a window as long as the recording is the whole run
    CHECK(t.worst_cpu_s(100 * t.length) == total);
    CHECK(t.worst_cpu_s(0) == 0.0);
    CHECK(ImpactTemplateTable{}.worst_cpu_s(64) == 0.0);
    // Per size: the whole table's figure is its costliest size's, and the largest drop (it breaks into
    // hundreds of pieces) costs more than the smallest (one mass). Compared over whole recordings: a
    // single block is one interrupt or page fault away from doubling on a loaded machine (the smallest
    // drop's worst 64 frames are about 0.1 ms; under the sanitizers 0.6).
    const int sizes = static_cast<int>(t.diameters_m.size());
    double largest = 0.0;
    for (int k = 0; k < sizes; ++k) largest = std::max(largest, t.worst_cpu_s(64, k));
    CHECK(largest == w64);
    const double smallest_whole = t.worst_cpu_s(t.length, 0), largest_whole = t.worst_cpu_s(t.length, sizes - 1);
    MESSAGE("worst CPU in 64 frames, smallest / largest drop: " << 1e3 * t.worst_cpu_s(64, 0) << " / " << 1e3 * t.worst_cpu_s(64, sizes - 1)
                                                               << " ms; whole recordings " << 1e3 * smallest_whole << " / " << 1e3 * largest_whole << " ms");
    // It does all the smallest's work (the canopy's) and its pieces', so it costs more on any build; by
    // how much is the normal build's figure (5.3-5.9 x measured, 2026-12-07): under the sanitizers the
    // instrumentation slows the canopy's kernels and the lattice's code by different factors (1.8-4.1 x
    // here) and the CPU's kind moves it further, so the factor is printed there, not asserted.
    CHECK(largest_whole > smallest_whole);
    AMEOTO_CHECK_UNLESS_SANITIZED(largest_whole > 2.0 * smallest_whole);
    CHECK(t.worst_cpu_s(64, -1) == 0.0);
    CHECK(t.worst_cpu_s(64, sizes) == 0.0);
    // The breakup is the costly part: the worst 64 frames cost more than an average 64 frames of the
    // same run (the 20 ms after the impact hold the flight of its pieces too).
    CHECK(w64 > 1.2 * total * 64.0 / t.length);
}

TEST_CASE("impact templates: the template sounds like the full model (log-spectral distance within 3 dB)") {
    // The tolerance: 3 dB of log-spectral distance between the tiers for the same drops, in
    // third-octave bands 100 Hz..16 kHz, over 0.1 s after each impact (the first impact and splash; the
    // pieces thrown up fall back later and are left out of the template by design).
    const ImpactTemplateTable& t = table();
    const std::vector<TestDrop> drops{{1.0e-3, 0.2, 0.05}, {2.0e-3, -0.15, 0.2}, {2.9e-3, 0.3, -0.1}, {4.1e-3, 0.1, 0.3},
                                  {5.0e-3, -0.3, -0.2}};
    std::vector<double> full_total, template_total;
    for (const TestDrop& drop : drops) {
        CAPTURE(drop.d);
        const auto a = band_powers(render_full(drop, 4800), 48000.0);
        const auto b = band_powers(render_template(t, drop, 4800), 48000.0);
        const double lsd = lsd_db(a, b);
        MESSAGE("D = " << drop.d * 1e3 << " mm: log-spectral distance template vs full " << lsd << " dB");
        CHECK(lsd < 3.0 * 2);   // each drop alone: twice the tolerance (one lattice's splash is erratic)
        if (full_total.empty()) {
            full_total = a;
            template_total = b;
        } else {
            for (std::size_t i = 0; i < a.size(); ++i) {
                full_total[i] += a[i];
                template_total[i] += b[i];
            }
        }
    }
    const double lsd = lsd_db(full_total, template_total);
    MESSAGE("all drops: log-spectral distance template vs full " << lsd << " dB");
    CHECK(lsd < 3.0);
}

TEST_CASE("impact templates: replay never allocates and a full pool refuses") {
    const ImpactTemplateTable& t = table();
    DropOnCanopy scene(scene_config());
    TemplatePool pool;
    const CanopyHit hit = scene.canopy().locate(0.2, 0.0);
    ameoto::test::RtAudit audit;
    {
        ameoto::test::RtAudit::Scope scope;
        for (int i = 0; i < TemplatePool::capacity; ++i) CHECK(pool.add(hit, t, 2e-3, 0.0, 998.0));
        CHECK_FALSE(pool.add(hit, t, 2e-3, 0.0, 998.0));
        float frame[2];
        for (int i = 0; i < 100; ++i) {
            pool.emit(t, [&](CanopyHit h, double f) { scene.surface().apply_force(h, f); });
            scene.process_frame(frame);
        }
    }
    CHECK(audit.violations() == 0);
    CHECK_FALSE(pool.add(CanopyHit{}, t, 2e-3, 0.0, 998.0));   // off the canopy
    CHECK_FALSE(TemplatePool{}.add(hit, ImpactTemplateTable{}, 2e-3, 0.0, 998.0));   // no table
}

TEST_CASE("impact templates: recorded on several threads, the table is the one recorded on one, bit for bit") {
    // The sizes are independent runs (impact_templates.cpp): threads change only who records which row.
    // A short grid keeps this quick: 9 sizes, 5 ms each.
    TemplateGrid grid;
    grid.min_diameter_m = 2e-3;
    grid.max_diameter_m = 3e-3;
    grid.seconds = 0.005;
    const ImpactTemplateTable one = record_impact_templates(scene_config(), grid, 1);
    const ImpactTemplateTable three = record_impact_templates(scene_config(), grid, 3);
    REQUIRE(one.diameters_m.size() == 9u);
    CHECK(three.diameters_m == one.diameters_m);
    CHECK(three.speeds_m_per_s == one.speeds_m_per_s);
    CHECK(three.used == one.used);
    CHECK(three.length == one.length);
    CHECK(three.forces == one.forces);   // exact: the same arithmetic in the same order per row
    double largest = 0.0;
    for (double f : one.forces) largest = std::max(largest, std::abs(f));
    CHECK(largest > 0.0);   // the rows recorded something
}

TEST_CASE("impact templates: a canopy built once (here or by the caller) and copied per size records the table a canopy built per size does, bit for bit") {
    // record_impact_templates builds the canopy once and gives each size's scene a copy of it
    // (CanopyBuild::shared, the default); per_size builds one per size, as each scene did before. Every
    // double is compared by its bits (memcmp: a -0.0 or a NaN payload would count too).
    TemplateGrid grid;
    grid.min_diameter_m = 2e-3;
    grid.max_diameter_m = 3e-3;
    grid.seconds = 0.005;
    DropOnCanopyConfig c = scene_config();
    c.geometry.curvature_radius_m = 1.2;   // the default cap is flat: a curved one tests the rest normals too
    for (const DropOnCanopyConfig& scene : {scene_config(), c}) {
        const ImpactTemplateTable fresh = record_impact_templates(scene, grid, 1, CanopyBuild::per_size);
        for (int threads : {1, 3}) {
            CAPTURE(threads);
            const ImpactTemplateTable shared = record_impact_templates(scene, grid, threads, CanopyBuild::shared);
            REQUIRE(shared.diameters_m.size() == 9u);
            REQUIRE(shared.forces.size() == fresh.forces.size());
            CHECK(shared.used == fresh.used);
            CHECK(shared.length == fresh.length);
            CHECK(std::memcmp(shared.forces.data(), fresh.forces.data(), fresh.forces.size() * sizeof(double)) == 0);
            CHECK(std::memcmp(shared.diameters_m.data(), fresh.diameters_m.data(), 9 * sizeof(double)) == 0);
            CHECK(std::memcmp(shared.speeds_m_per_s.data(), fresh.speeds_m_per_s.data(), 9 * sizeof(double)) == 0);
            // The caller's canopy (UmbrellaScene's: built from the scene's own configuration, whose output
            // and listener differ from the recording's) gives the same table.
            const ImpactTemplateTable given = record_impact_templates(scene, DropOnCanopy::fresh_canopy(scene), grid, threads);
            REQUIRE(given.forces.size() == fresh.forces.size());
            CHECK(given.used == fresh.used);
            CHECK(std::memcmp(given.forces.data(), fresh.forces.data(), fresh.forces.size() * sizeof(double)) == 0);
        }
        double largest = 0.0;
        for (double f : fresh.forces) largest = std::max(largest, std::abs(f));
        CHECK(largest > 0.0);   // the rows recorded something
    }
}

TEST_CASE("impact templates: a configuration DropOnCanopy refuses is refused on any number of threads") {
    DropOnCanopyConfig bad = scene_config();
    bad.sample_rate = -1.0;
    TemplateGrid grid;
    grid.min_diameter_m = 2e-3;
    grid.max_diameter_m = 3e-3;
    grid.seconds = 0.005;
    CHECK_THROWS(record_impact_templates(bad, grid, 1));
    CHECK_THROWS(record_impact_templates(bad, grid, 3));
}
