// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for engine/models/liquid: presets, lookup by name, validation of custom liquids.
#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

#include <limits>
#include <stdexcept>
#include <string>

#include "engine/models/liquid.hpp"

using ameoto::Liquid;

TEST_CASE("liquid: presets carry the seed's water and cited milk and heavy oil") {
    const Liquid& water = ameoto::liquids::water();
    CHECK(water.name == "water");
    CHECK(water.surface_tension == 7.49e-2);   // seed section 5.1.1, exactly
    CHECK(water.viscosity == 1.52e-3);         // seed section 5.1.1, exactly
    CHECK(water.density == 998.0);
    CHECK(water.kinematic_viscosity() == ameoto::test::relative(1.52e-3 / 998.0).epsilon(1e-15));

    const Liquid& milk = ameoto::liquids::milk();   // Walstra et al. 2006; J. Dairy Res. 50:259 (1983)
    CHECK(milk.density == 1030.0);
    CHECK(milk.surface_tension == ameoto::test::relative(0.052));
    CHECK(milk.viscosity == ameoto::test::relative(2.0e-3));
    // The cited fit gamma(T) = 1.8e-4 T^2 - 0.163 T + 55.6 mN/m at 20 C: 52.4 mN/m (preset to 1 %).
    CHECK(milk.surface_tension == ameoto::test::relative((1.8e-4 * 400.0 - 0.163 * 20.0 + 55.6) * 1e-3).epsilon(0.01));

    const Liquid& oil = ameoto::liquids::heavy_oil();   // IFO 380 at 50 C: 380 mm^2/s * 960 kg/m^3
    CHECK(oil.viscosity == ameoto::test::relative(380e-6 * 960.0).epsilon(1e-12));
    CHECK(oil.kinematic_viscosity() == ameoto::test::relative(380e-6).epsilon(1e-12));

    CHECK(ameoto::liquids::presets().size() == 3);
    for (const Liquid& l : ameoto::liquids::presets()) CHECK(ameoto::validate(l).empty());
}

TEST_CASE("liquid: presets are found by name; unknown names are not") {
    for (const char* name : {"water", "milk", "heavy_oil"}) {
        CAPTURE(std::string(name));   // doctest prints a char pointer as its address
        const auto found = ameoto::find_liquid(name);
        REQUIRE(found.has_value());
        CHECK(found->name == name);
    }
    CHECK(ameoto::find_liquid("Water") == std::nullopt);   // exact, lower case
    CHECK(ameoto::find_liquid("mercury") == std::nullopt);
    CHECK(ameoto::find_liquid("") == std::nullopt);
}

TEST_CASE("liquid: validation names the field and its range") {
    const Liquid ok = ameoto::make_liquid("glycerol", 1261.0, 0.063, 1.41);
    CHECK(ok.name == "glycerol");
    CHECK(ameoto::validate(ok).empty());

    struct Case {
        Liquid liquid;
        const char* field;
        const char* range;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Case cases[] = {
        {{"g/cm3", 1.0, 0.07, 1e-3}, "density", "100..20000 kg/m^3"},
        {{"heavy", 25000.0, 0.07, 1e-3}, "density", "100..20000 kg/m^3"},
        {{"mN/m", 998.0, 72.8, 1e-3}, "surface tension", "0.0001..1 N/m"},
        {{"none", 998.0, 0.0, 1e-3}, "surface tension", "0.0001..1 N/m"},
        {{"cP", 998.0, 0.07, 1e4}, "viscosity", "1e-06..1000 Pa s"},
        {{"negative", 998.0, 0.07, -1.0}, "viscosity", "1e-06..1000 Pa s"},
        {{"nan", nan, 0.07, 1e-3}, "density", "100..20000 kg/m^3"},
    };
    for (const auto& c : cases) {
        CAPTURE(c.liquid.name);
        const std::string why = ameoto::validate(c.liquid);
        MESSAGE(why);
        CHECK(why.rfind(c.field, 0) == 0);   // starts with the field
        CHECK(why.find(c.range) != std::string::npos);
        CHECK_THROWS_AS(ameoto::make_liquid(c.liquid.name, c.liquid.density, c.liquid.surface_tension, c.liquid.viscosity),
                        std::invalid_argument);
    }
    // The limits themselves are accepted.
    CHECK(ameoto::validate({"low", 100.0, 1e-4, 1e-6}).empty());
    CHECK(ameoto::validate({"high", 20000.0, 1.0, 1e3}).empty());
}
