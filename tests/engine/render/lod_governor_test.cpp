// SPDX-License-Identifier: GPL-3.0-or-later
// The level-of-detail governor (engine/render/lod_governor.hpp): audibility, masking, load shedding.
#include "engine/render/lod_governor.hpp"

#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <cmath>
#include <vector>
#include <initializer_list>

using namespace ameoto;

TEST_CASE("lod: a drop's level follows the impact law over distance") {
    CHECK(LodGovernor::level_db(2e-3, 6.49, 1.0) == doctest::Approx(0.0).epsilon(1e-12).scale(1.0));
    // Twice the diameter: force x4 (+12 dB); twice the speed: x4 (+12 dB); twice the distance: -6 dB.
    CHECK(LodGovernor::level_db(4e-3, 6.49, 1.0) == doctest::Approx(20 * std::log10(4.0)));
    CHECK(LodGovernor::level_db(2e-3, 12.98, 1.0) == doctest::Approx(20 * std::log10(4.0)));
    CHECK(LodGovernor::level_db(2e-3, 6.49, 2.0) == doctest::Approx(-20 * std::log10(2.0)));
}

TEST_CASE("lod: large near drops are full, small or far ones template, buried ones texture") {
    LodGovernor g;
    CHECK(g.choose(5e-3, 9.09, 0.4, 0) == LodTier::full);
    CHECK(g.choose(1e-3, 4.03, 0.4, 0) == LodTier::template_);
    CHECK(g.choose(5e-3, 9.09, 0.4, 16) == LodTier::template_);   // the lattice pool is at its limit
    CHECK(g.choose(1e-3, 4.03, 0.8, 0) == LodTier::template_);      // -18 dB: quiet, but nothing masks it
    CHECK(g.choose(0.5e-3, 2.06, 50.0, 0) == LodTier::texture);      // -78 dB: far and faint
    // Dense rain: 20 000 drops per second for 2 s raise the masking to 23 dB; a small far drop is texture.
    for (int block = 0; block < 1500; ++block) g.end_block(0.0, 20000 * 64 / 48000, 64.0 / 48000.0);
    CHECK(g.masking_db() == doctest::Approx(10 * std::log10(20000.0 / 100.0)).epsilon(0.02));
    CHECK(g.choose(0.5e-3, 2.06, 5.0, 0) == LodTier::texture);
    CHECK(g.choose(5e-3, 9.09, 0.4, 0) == LodTier::full);   // 29 dB at 0.4 m: still stands out
    CHECK(g.counts().full == 2);
    CHECK(g.counts().texture == 2);
}

TEST_CASE("lod: over budget, detail falls at once and recovers slowly; tightening never adds detail") {
    LodGovernor g(LodSettings{.budget = 0.5, .max_full = 16});
    CHECK(g.detail() == 1.0);
    g.end_block(0.75, 0, 64.0 / 48000.0);   // 150 % of the budget
    CHECK(g.detail() == ameoto::test::relative(0.5));
    // A 5 mm drop at 0.4 m (+29 dB) needs 6 + 40 * 0.5 = 26 dB: still full; a 3 mm one (+20 dB) is not.
    CHECK(g.choose(5e-3, 9.09, 0.4, 0) == LodTier::full);
    CHECK(g.choose(3e-3, 8.06, 0.4, 0) == LodTier::template_);
    g.end_block(2.0, 0, 64.0 / 48000.0);
    CHECK(g.detail() == 0.0);
    CHECK(g.choose(5e-3, 9.09, 0.4, 0) == LodTier::template_);
    // Under budget: 0.5 per second back.
    for (int i = 0; i < 375; ++i) g.end_block(0.1, 0, 64.0 / 48000.0);   // 0.5 s
    CHECK(g.detail() == ameoto::test::relative(0.25).epsilon(0.01));
    for (int i = 0; i < 1500; ++i) g.end_block(0.1, 0, 64.0 / 48000.0);
    CHECK(g.detail() == 1.0);
    // The tier is monotonic in the detail: at lower detail no drop gets a richer tier.
    for (double d : {0.5e-3, 1e-3, 2e-3, 3e-3, 5e-3})
        for (double r : {0.3, 1.0, 10.0}) {
            LodGovernor rich, poor;
            poor.end_block(0.8, 0, 64.0 / 48000.0);
            CHECK(static_cast<int>(poor.choose(d, 8.0, r, 0)) >= static_cast<int>(rich.choose(d, 8.0, r, 0)));
        }
}

TEST_CASE("lod: with no measured load the choice depends only on the drops (offline renders)") {
    LodGovernor a, b;
    for (int block = 0; block < 100; ++block) {
        a.end_block(0.0, 40, 0.01);
        b.end_block(0.0, 40, 0.01);
        CHECK(a.choose(1e-3 + 4e-5 * block, 5.0, 0.5 + 0.1 * block, block % 20) ==
              b.choose(1e-3 + 4e-5 * block, 5.0, 0.5 + 0.1 * block, block % 20));
    }
    CHECK(a.detail() == 1.0);
}

TEST_CASE("lod: a lattice drop is priced from measured load: its mean cost and its spawn-and-breakup block") {
    constexpr double block = 64.0 / 48000.0;
    LodGovernor g(LodSettings{.budget = 0.4, .max_full = 4, .peak_budget = 0.6});
    // Before any load is seen (offline, or the first blocks) nothing is priced.
    CHECK_FALSE(g.lattice_price().known);
    CHECK(g.lattice_affordable());
    // 1 s with no lattice drop at 20 % load: the base.
    for (int i = 0; i < 750; ++i) g.observe_load(0.20, LatticeActivity{0, false}, block);
    CHECK(g.lattice_price().base == ameoto::test::relative(0.20));
    CHECK(g.lattice_affordable());
    // One drop awake costs 8 % a block (5 s: the 0.25 s mean has settled), its spawn block 0.35 above base.
    g.observe_load(0.55, LatticeActivity{1, true}, block);
    for (int i = 0; i < 3750; ++i) g.observe_load(0.28, LatticeActivity{1, false}, block);
    CHECK(g.lattice_price().mean == ameoto::test::relative(0.08).epsilon(0.01));
    CHECK(g.lattice_price().recent == ameoto::test::relative(0.28).epsilon(0.01));
    // Decayed by exp(-5 s / 120 s) since: 0.35 * 0.96 = 0.34. recent + event = 0.62 > 0.6: not yet.
    CHECK(g.lattice_price().event == ameoto::test::relative(0.35 * std::exp(-5.0 / 120.0)).epsilon(0.01));
    CHECK_FALSE(g.lattice_affordable());
    // 10 s more at 22 %: 0.35 * exp(-15 / 120) = 0.31; recent + event = 0.53 <= 0.6: affordable.
    for (int i = 0; i < 7500; ++i) g.observe_load(0.22, LatticeActivity{1, false}, block);
    CHECK(g.lattice_price().event == ameoto::test::relative(0.35 * std::exp(-15.0 / 120.0)).epsilon(0.01));
    CHECK(g.lattice_affordable());
    for (int i = 0; i < 750; ++i) g.observe_load(0.28, LatticeActivity{1, false}, block);
    CHECK(g.choose(5e-3, 9.09, 0.4, 1) == LodTier::full);
    // A heavier shatter: 0.55 above the base with another drop awake (0.55 - 0.08 = 0.47 its own). Now
    // recent + event = 0.28 + 0.47 > 0.6: a loud near drop becomes a template, counted as priced out.
    g.observe_load(0.75, LatticeActivity{2, true}, block);
    CHECK(g.lattice_price().event == ameoto::test::relative(0.47).epsilon(0.01));
    CHECK_FALSE(g.lattice_affordable());
    CHECK(g.choose(5e-3, 9.09, 0.4, 1) == LodTier::template_);
    CHECK(g.counts().priced_out == 1);
    // The memory fades over minutes (120 s), not seconds: 3 s later at 25 % load it still does not fit;
    // 30 s later (0.47 * exp(-0.25) = 0.37), at 20 % load, it does.
    for (int i = 0; i < 2250; ++i) g.observe_load(0.25, LatticeActivity{0, false}, block);
    CHECK(g.lattice_price().event == ameoto::test::relative(0.47 * std::exp(-3.0 / 120.0)).epsilon(0.02));
    CHECK_FALSE(g.lattice_affordable());
    for (int i = 0; i < 20250; ++i) g.observe_load(0.20, LatticeActivity{0, false}, block);
    CHECK(g.lattice_price().event == ameoto::test::relative(0.47 * std::exp(-30.0 / 120.0)).epsilon(0.02));
    CHECK(g.lattice_affordable());
    // The mean budget: a load near the budget leaves no room for one more drop's 8 %.
    for (int i = 0; i < 750; ++i) g.observe_load(0.35, LatticeActivity{0, false}, block);
    CHECK_FALSE(g.lattice_affordable());
    CHECK(g.choose(5e-3, 9.09, 0.4, 0) == LodTier::template_);
}

TEST_CASE("lod: the prior keeps out a lattice drop whose breakup cannot fit, before and after loads are measured, and does not fade") {
    constexpr double block = 64.0 / 48000.0;
    LodGovernor g(LodSettings{.budget = 0.4, .max_full = 4, .peak_budget = 0.5});
    // A loud near drop, with nothing measured: admitted (offline) until a prior says its breakup takes
    // 1.3 periods (what the recordings measured on the canopy in air, 64-frame blocks: 130-140 %).
    CHECK(g.lattice_affordable());
    g.set_lattice_prior(1.3);
    CHECK(g.lattice_price().prior == 1.3);
    CHECK_FALSE(g.lattice_price().known);
    CHECK_FALSE(g.lattice_affordable());
    CHECK(g.choose(5e-3, 9.09, 0.4, 0) == LodTier::template_);
    CHECK(g.counts().priced_out == 1);
    // Ten minutes of light load later it still does not fit: the prior is the drop's own work.
    for (int i = 0; i < 600 * 750; ++i) g.observe_load(0.05, LatticeActivity{0, false}, block);
    CHECK(g.lattice_price().prior == 1.3);
    CHECK_FALSE(g.lattice_affordable());
    CHECK(g.choose(5e-3, 9.09, 0.4, 0) == LodTier::template_);
    // A longer period (the same drop's prior over 1024 frames: 0.21) fits at once.
    g.set_lattice_prior(0.21);
    CHECK(g.lattice_affordable());
    CHECK(g.choose(5e-3, 9.09, 0.4, 0) == LodTier::full);
    // A measured breakup above the prior counts, and fades back down to the prior, not below it.
    g.observe_load(0.05 + 0.6, LatticeActivity{1, true}, block);
    CHECK(g.lattice_price().event == ameoto::test::relative(0.6).epsilon(0.01));
    CHECK_FALSE(g.lattice_affordable());
    for (int i = 0; i < 600 * 750; ++i) g.observe_load(0.05, LatticeActivity{0, false}, block);
    CHECK(g.lattice_price().event < 0.01);
    CHECK(g.lattice_affordable());
    g.set_lattice_prior(0.47);   // recent 0.05 + 0.47 > 0.5
    CHECK_FALSE(g.lattice_affordable());
    // Nonsense is ignored.
    g.set_lattice_prior(std::nan(""));
    g.set_lattice_prior(-1.0);
    CHECK(g.lattice_price().prior == 0.47);
}

TEST_CASE("lod: the prior per size admits the drops whose breakup fits and keeps out those whose does not") {
    constexpr double block = 64.0 / 48000.0;
    LodGovernor g(LodSettings{.budget = 0.4, .max_full = 4, .peak_budget = 0.5});
    // The shape of the recordings on the 2-CPU VM at 64 frames: a 1 mm drop 6 %, 3 mm 37 %, 5 mm 122 %.
    const double d[3] = {1e-3, 3e-3, 5e-3}, e[3] = {0.06, 0.37, 1.22};
    g.set_lattice_prior(d, e, 3);
    CHECK(g.lattice_price().prior == 1.22);   // the costliest size's
    CHECK_FALSE(g.lattice_affordable());      // without a size: the costliest
    CHECK(g.lattice_affordable(1e-3));
    CHECK(g.lattice_affordable(3.2e-3));
    CHECK_FALSE(g.lattice_affordable(4.5e-3));
    // The nearest size in log D: 3 and 5 mm meet at sqrt(15) = 3.873 mm; below 0.5 mm the smallest, above
    // 6 mm the largest.
    CHECK(g.lattice_affordable(3.86e-3));
    CHECK_FALSE(g.lattice_affordable(3.89e-3));
    CHECK(g.lattice_affordable(0.1e-3));
    CHECK_FALSE(g.lattice_affordable(8e-3));
    // Before the first measured callback (live: the stream's cold start) no lattice drop, even one whose
    // prior fits; after it, a loud 5 mm drop is a template and a loud 1.5 mm one a lattice drop.
    CHECK(g.choose(5e-3, 9.09, 0.4, 0) == LodTier::template_);
    CHECK(g.choose(1.5e-3, 5.5, 0.05, 0) == LodTier::template_);
    g.observe_load(0.05, LatticeActivity{0, false}, block);
    CHECK(g.choose(5e-3, 9.09, 0.4, 0) == LodTier::template_);
    CHECK(g.choose(1.5e-3, 5.5, 0.05, 0) == LodTier::full);
    // At a measured 20 % load the 3 mm drop's breakup (0.2 + 0.37) no longer fits under the 50 % limit.
    for (int i = 0; i < 750; ++i) g.observe_load(0.20, LatticeActivity{0, false}, block);
    CHECK_FALSE(g.lattice_affordable(3e-3));
    CHECK(g.lattice_affordable(1e-3));
    // A table that is not one (sizes out of order, a negative figure, NaN) leaves the prior as it was.
    const double backwards[3] = {5e-3, 3e-3, 1e-3}, negative[3] = {0.06, -0.1, 1.22}, nan[3] = {0.06, std::nan(""), 1.22};
    g.set_lattice_prior(backwards, e, 3);
    g.set_lattice_prior(d, negative, 3);
    g.set_lattice_prior(d, nan, 3);
    CHECK(g.lattice_price().prior == 1.22);
    CHECK(g.lattice_affordable(1e-3));
    // More sizes than the governor holds: their largest for every size.
    std::vector<double> many_d, many_e;
    for (int k = 0; k < LodGovernor::max_prior_sizes + 1; ++k) {
        many_d.push_back(0.5e-3 * std::pow(1.03, k));
        many_e.push_back(k == LodGovernor::max_prior_sizes ? 0.9 : 0.01);
    }
    g.set_lattice_prior(many_d.data(), many_e.data(), static_cast<int>(many_d.size()));
    CHECK(g.lattice_price().prior == 0.9);
    CHECK_FALSE(g.lattice_affordable(0.5e-3));
    // One figure for every size replaces the table.
    g.set_lattice_prior(0.1);
    CHECK(g.lattice_affordable(5e-3));
}

TEST_CASE("lod: bad measured loads are ignored by the price") {
    LodGovernor g;
    g.observe_load(std::nan(""), LatticeActivity{0, false}, 0.001);
    g.observe_load(-1.0, LatticeActivity{0, false}, 0.001);
    g.observe_load(0.3, LatticeActivity{0, false}, 0.0);
    CHECK_FALSE(g.lattice_price().known);
    CHECK(g.lattice_affordable());
}

TEST_CASE("lod: live, lattice drops are admitted 0.1 s apart, and one at a time until the price is learned") {
    constexpr double block = 64.0 / 48000.0;   // 1.33 ms
    LodGovernor g(LodSettings{.budget = 0.4, .max_full = 4, .peak_budget = 0.6});
    // Offline (nothing measured): no spacing, the choice depends on the drops alone.
    CHECK(g.choose(5e-3, 9.09, 0.4, 0) == LodTier::full);
    CHECK(g.choose(5e-3, 9.09, 0.4, 1) == LodTier::full);
    LodGovernor live(LodSettings{.budget = 0.4, .max_full = 4, .peak_budget = 0.6});
    for (int i = 0; i < 750; ++i) live.observe_load(0.20, LatticeActivity{0, false}, block);   // base 20 %
    // Learning: the first drop is admitted; while it is in the scene no second one, even 0.1 s later.
    CHECK(live.choose(5e-3, 9.09, 0.4, 0) == LodTier::full);
    for (int i = 0; i < 60; ++i) live.observe_load(0.25, LatticeActivity{1, i == 0}, block);   // 80 ms awake
    CHECK(live.choose(5e-3, 9.09, 0.4, 1) == LodTier::template_);
    CHECK(live.counts().priced_out == 1);
    // The drop has gone (40 ms with none awake): the next one may teach; learning is 0.1 s of measured
    // awake time in all, and 80 ms have been measured.
    for (int i = 0; i < 30; ++i) live.observe_load(0.20, LatticeActivity{0, false}, block);
    CHECK(live.choose(5e-3, 9.09, 0.4, 0) == LodTier::full);
    for (int i = 0; i < 90; ++i) live.observe_load(0.25, LatticeActivity{1, false}, block);   // 200 ms in all
    // Learned (event 0.05 above base, mean 0.05): a second drop while one is awake is admitted, but only
    // once 0.1 s has passed since the last admission.
    CHECK(live.choose(5e-3, 9.09, 0.4, 1) == LodTier::full);
    CHECK(live.choose(5e-3, 9.09, 0.4, 2) == LodTier::template_);   // the same instant: too close
    for (int i = 0; i < 70; ++i) live.observe_load(0.25, LatticeActivity{2, false}, block);   // 93 ms
    CHECK(live.choose(5e-3, 9.09, 0.4, 2) == LodTier::template_);
    for (int i = 0; i < 6; ++i) live.observe_load(0.25, LatticeActivity{2, false}, block);    // 101 ms
    CHECK(live.choose(5e-3, 9.09, 0.4, 2) == LodTier::full);
    CHECK(live.counts().priced_out == 3);
}
