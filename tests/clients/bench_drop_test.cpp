// SPDX-License-Identifier: GPL-3.0-or-later
// Tests for clients/ameoto/bench_drop: what `ameoto bench drop --json` prints (its fields present,
// finite, positive and consistent with each other as docs/bench.md defines them), and that its bad
// options are refused. It times two short rounds and one; no figure is held to a speed except that drops
// cost something and the canopy alone keeps up with real time (docs/bench.md: 9-15 % of a core).
#include "clients/ameoto/bench_drop.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "clients/ameoto/bench_command.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "tests/support/timing_scale.hpp"

using namespace ameoto::client;

namespace {

constexpr double period_ns = 1e9 / 48000.0;   // the sample period the percentages and drops at once refer to

// One flat JSON object's fields as their raw text ("\"1 drop\"", "8", "null"); the bench prints no
// nested values and no commas inside its strings.
std::map<std::string, std::string> fields_of(const std::string& line) {
    std::map<std::string, std::string> fields;
    REQUIRE(line.starts_with("{"));
    REQUIRE(line.ends_with("}"));
    std::istringstream body(line.substr(1, line.size() - 2));
    for (std::string pair; std::getline(body, pair, ',');) {
        const auto colon = pair.find("\":");
        REQUIRE_MESSAGE((pair.starts_with("\"") && colon != std::string::npos), pair);
        fields[pair.substr(1, colon - 1)] = pair.substr(colon + 2);
    }
    return fields;
}

// A number field: present, and a finite number (json_number prints NaN and Inf as null).
double number(const std::map<std::string, std::string>& fields, const std::string& name) {
    const auto it = fields.find(name);
    REQUIRE_MESSAGE(it != fields.end(), "no field " << name);
    std::size_t used = 0;
    const double v = std::stod(it->second, &used);
    REQUIRE_MESSAGE(used == it->second.size(), name << " is " << it->second);
    REQUIRE(std::isfinite(v));
    return v;
}

// Equal to the 6 significant digits json_number prints (a relative error up to 5e-6), allowing for the
// figures `computed` came from having been printed so too: `of` is the largest of them, in its units.
bool printed_equal(double printed, double computed, double of) {
    return std::abs(printed - computed) <= 1e-5 * (std::abs(printed) + std::abs(computed) + std::abs(of));
}

struct Run {
    int status;
    std::string out, err;
};

Run bench(const CommandWords& words) {
    std::ostringstream out, err;
    const CommandIo io{[](const std::string&) { return std::optional<std::string>(); }, out, err};
    const int status = run_bench(words, io);
    return {status, out.str(), err.str()};
}

}  // namespace

TEST_CASE("bench drop: `--json` prints the canopy, 1 drop, 8 drops and drops at once, each field consistent with the others") {
    const Run r = bench({"drop", "--json", "--runs", "2"});
    REQUIRE(r.status == exit_status::ok);
    std::vector<std::map<std::string, std::string>> lines;
    std::istringstream text(r.out);
    for (std::string line; std::getline(text, line);) lines.push_back(fields_of(line));
    REQUIRE(lines.size() == 4);
    for (const auto& f : lines) CHECK(f.at("suite") == "\"drop\"");
    const auto &canopy = lines[0], &one = lines[1], &eight = lines[2], &at_once = lines[3];
    CHECK(canopy.at("measurement") == "\"canopy (no drop)\"");
    CHECK(one.at("measurement") == "\"1 drop\"");
    CHECK(eight.at("measurement") == "\"8 drops\"");
    CHECK(at_once.at("measurement") == "\"drops at once in real time\"");

    const int drops[] = {0, 1, 8};
    for (int i = 0; i < 3; ++i) {
        const auto& f = lines[static_cast<std::size_t>(i)];
        CHECK(number(f, "drops") == drops[i]);
        CHECK(number(f, "diameter_mm") == 5);
        CHECK(number(f, "sample_rate_hz") == 48000);
        const double ns = number(f, "ns_per_sample");
        CHECK(ns > 0);
        CHECK(ns <= number(f, "ns_per_sample_median"));   // the least of the runs, then their median
        CHECK(printed_equal(number(f, "percent_core"), 100.0 * ns / period_ns, 0.0));
    }
    CHECK(canopy.at("ns_per_drop_per_sample") == "null");   // no drop: nothing to divide by
    CHECK(canopy.at("ns_per_drop_per_sample_median") == "null");

    // docs/bench.md: per drop = (time with drops - baseline) / drops, from the least of the runs and from
    // their medians alike; drops cost something.
    for (const std::string estimator : {"", "_median"}) {
        INFO("estimator: ns_per_sample" << estimator);
        const double base = number(canopy, "ns_per_sample" + estimator);
        const double with_one = number(one, "ns_per_sample" + estimator), with_eight = number(eight, "ns_per_sample" + estimator);
        MESSAGE("canopy " << base << " ns/sample, 1 drop " << with_one << ", 8 drops " << with_eight);
        CHECK(with_one > base);
        CHECK(with_eight > with_one);
        const double per_drop_1 = number(one, "ns_per_drop_per_sample" + estimator);
        const double per_drop_8 = number(eight, "ns_per_drop_per_sample" + estimator);
        CHECK(per_drop_1 > 0);
        CHECK(per_drop_8 > 0);
        CHECK(printed_equal(per_drop_1, with_one - base, with_one));
        CHECK(printed_equal(per_drop_8, (with_eight - base) / 8.0, with_eight));
        // Drops at once = (period - baseline) / per drop (8-drop figure), against the 16.
        const std::string field = estimator.empty() ? "drops" : "drops_median";
        CHECK(printed_equal(number(at_once, field), (period_ns - base) / per_drop_8, base / per_drop_8));
    }
    CHECK(number(at_once, "target") == 16);
    CHECK(number(at_once, "runs") == 2);
    // The canopy in air (the built-in scenes'), same rounds: drops at once from its own baseline and per drop.
    const double base_air = number(at_once, "canopy_ns_per_sample_air"), per_drop_air = number(at_once, "ns_per_drop_per_sample_air");
    CHECK(base_air > 0);
    CHECK(per_drop_air > 0);
    CHECK(printed_equal(number(at_once, "drops_air"), (period_ns - base_air) / per_drop_air, base_air / per_drop_air));
    MESSAGE("in air: canopy " << base_air << " ns/sample, " << per_drop_air << " ns per drop, " << number(at_once, "drops_air") << " drops at once");
    // Each round's own figure: the two rounds' lowest and highest.
    CHECK(number(at_once, "drops_round_low") <= number(at_once, "drops_round_high"));
    MESSAGE("drops at once " << number(at_once, "drops") << " (medians " << number(at_once, "drops_median") << ", rounds "
                             << number(at_once, "drops_round_low") << " to " << number(at_once, "drops_round_high") << ")");
    if (ameoto::test::sanitized_build()) {
        MESSAGE("ASan build: the canopy alone is not held to real time");
    } else {
        CHECK(number(canopy, "ns_per_sample") < period_ns);   // the canopy alone keeps up (9-15 % of a core), so some drops fit
        CHECK(number(at_once, "drops") > 0);
    }
    CHECK(r.err.find("timing the canopy alone, 1 and 8 drops (2 rounds)") != std::string::npos);   // progress on stderr only
}

TEST_CASE("bench drop: one round gives one figure: its least and its median are the same run") {
    const Run r = bench({"drop", "--json", "--runs", "1"});
    REQUIRE(r.status == exit_status::ok);
    std::vector<std::map<std::string, std::string>> lines;
    std::istringstream text(r.out);
    for (std::string line; std::getline(text, line);) lines.push_back(fields_of(line));
    REQUIRE(lines.size() == 4);
    for (int i = 0; i < 3; ++i)
        CHECK(number(lines[static_cast<std::size_t>(i)], "ns_per_sample") == number(lines[static_cast<std::size_t>(i)], "ns_per_sample_median"));
    const auto& at_once = lines[3];
    CHECK(number(at_once, "drops") == number(at_once, "drops_median"));
    CHECK(printed_equal(number(at_once, "drops_round_low"), number(at_once, "drops"), 0.0));
    CHECK(printed_equal(number(at_once, "drops_round_high"), number(at_once, "drops"), 0.0));
}

TEST_CASE("bench drop: bad options are refused with a reason and exit status 2, before anything is timed") {
    const std::pair<CommandWords, std::string> bad[] = {
        {{"drop", "--runs", "0"}, "--runs '0': give the number of timed runs, 1..101"},
        {{"drop", "--runs", "102"}, "--runs '102'"},
        {{"drop", "--runs"}, "--runs needs a value"},
        {{"drop", "--json=yes"}, "--json takes no value"},
        {{"drop", "--fast"}, "unknown option '--fast'"},
        {{"drop", "extra"}, "unexpected argument 'extra'"},
        {{"drop", "--seconds", "1"}, "--seconds does not apply to bench drop (it takes --json --runs)"},   // engine's and scene's
        {{"drop", "--sizes", "55"}, "--sizes does not apply to bench drop"},
    };
    for (const auto& [words, reason] : bad) {
        const Run r = bench(words);
        INFO(r.err);
        CHECK(r.status == exit_status::usage);
        CHECK(r.out.empty());
        CHECK(r.err.starts_with("ameoto bench: " + reason));
        CHECK(r.err.find("timing") == std::string::npos);
    }
}
