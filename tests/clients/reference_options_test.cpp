// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for clients/ameoto/reference_command: `ameoto reference` command lines, parsed and checked
// (the validations themselves: tests/engine/reference, tests/engine/models/air_canopy_test.cpp).
#include "clients/ameoto/reference_command.hpp"

#include <doctest/doctest.h>

using namespace ameoto::client;

TEST_CASE("reference options: the defaults leave the choice to run_reference") {
    ReferenceOptions o;
    std::string error;
    REQUIRE(parse_reference_options({}, o, error) == ReferenceParse::run);
    CHECK(o.validations.empty());
    CHECK(o.dx_m == 0.0);
    CHECK_FALSE(o.json);
}

TEST_CASE("reference options: every validation by name, in the order given, with --dx and --json") {
    ReferenceOptions o;
    std::string error;
    REQUIRE(parse_reference_options({"canopy-drop", "piston", "disc", "timpani", "reflection", "canopy", "canopy-bands", "--dx", "0.0075", "--json"},
                                    o, error) == ReferenceParse::run);
    CHECK(o.validations == std::vector<std::string>{"canopy-drop", "piston", "disc", "timpani", "reflection", "canopy", "canopy-bands"});
    CHECK(o.dx_m == 0.0075);
    CHECK(o.json);
    ReferenceOptions equals;
    REQUIRE(parse_reference_options({"--dx=0.01", "canopy-drop"}, equals, error) == ReferenceParse::run);
    CHECK(equals.dx_m == 0.01);
}

TEST_CASE("reference options: refusals name what is wrong") {
    ReferenceOptions o;
    std::string error;
    CHECK(parse_reference_options({"canopy-drops"}, o, error) == ReferenceParse::error);
    CHECK(error.find("unknown validation 'canopy-drops'") != std::string::npos);
    CHECK(error.find("canopy-drop)") != std::string::npos);   // the list names every validation
    for (const char* dx : {"0.0005", "0.2", "-1", "nan", "ten"}) {
        CAPTURE(dx);
        ReferenceOptions bad;
        std::string why;
        CHECK(parse_reference_options({"canopy", "--dx", dx}, bad, why) == ReferenceParse::error);
        CHECK_FALSE(why.empty());
    }
    CHECK(parse_reference_options({"--frobnicate"}, o, error) == ReferenceParse::error);
    CHECK(parse_reference_options({"--help"}, o, error) == ReferenceParse::help);
}

TEST_CASE("reference options: the help names every validation it accepts") {
    const std::string help = reference_usage();
    for (const char* v : {"piston", "disc", "timpani", "reflection", "canopy", "canopy-bands", "canopy-drop"}) {
        CAPTURE(v);
        CHECK(help.find(std::string("  ") + v + " ") != std::string::npos);
    }
}
