// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for clients/ameoto/reference_command: `ameoto reference` command lines, parsed and checked
// (the validations themselves: tests/engine/reference, tests/engine/models/air_canopy_test.cpp).
#include "clients/ameoto/reference_command.hpp"

#include <doctest/doctest.h>

using namespace ameoto::client;

namespace {

struct ReferenceParsed {
    ReferenceParse result;
    ReferenceOptions options;
    std::string error;
};

ReferenceParsed parse_words(const CommandWords& words) {
    ReferenceParsed p;
    p.result = parse_reference_options(words, p.options, p.error);
    return p;
}

}  // namespace

TEST_CASE("reference options: the defaults leave the choice to run_reference") {
    const ReferenceParsed p = parse_words({});
    REQUIRE(p.result == ReferenceParse::run);
    CHECK(p.options.validations.empty());
    CHECK(p.options.dx_m == 0.0);
    CHECK_FALSE(p.options.json);
}

TEST_CASE("reference options: every validation by name, in the order given, with --dx and --json") {
    const ReferenceParsed p = parse_words({"canopy-drop", "piston", "disc", "timpani", "reflection", "canopy", "canopy-bands", "--dx", "0.0075", "--json"});
    REQUIRE(p.result == ReferenceParse::run);
    CHECK(p.options.validations ==
          std::vector<std::string>{"canopy-drop", "piston", "disc", "timpani", "reflection", "canopy", "canopy-bands"});
    CHECK(p.options.dx_m == 0.0075);
    CHECK(p.options.json);
    CHECK(parse_words({"--dx=0.01", "canopy-drop"}).options.dx_m == 0.01);
}

TEST_CASE("reference options: refusals name what is wrong") {
    const ReferenceParsed unknown = parse_words({"canopy-drops"});
    CHECK(unknown.result == ReferenceParse::error);
    CHECK(unknown.error.find("unknown validation 'canopy-drops'") != std::string::npos);
    CHECK(unknown.error.find("canopy-drop)") != std::string::npos);   // the list names every validation
    for (const char* dx : {"0.0005", "0.2", "-1", "nan", "ten"}) {
        CAPTURE(dx);
        const ReferenceParsed p = parse_words({"canopy", "--dx", dx});
        CHECK(p.result == ReferenceParse::error);
        CHECK_FALSE(p.error.empty());
    }
    CHECK(parse_words({"--frobnicate"}).result == ReferenceParse::error);
    CHECK(parse_words({"--help"}).result == ReferenceParse::help);
}

TEST_CASE("reference options: the help names every validation it accepts") {
    const std::string help = reference_usage();
    for (const char* v : {"piston", "disc", "timpani", "reflection", "canopy", "canopy-bands", "canopy-drop"}) {
        CAPTURE(v);
        CHECK(help.find(std::string("  ") + v + " ") != std::string::npos);
    }
}
