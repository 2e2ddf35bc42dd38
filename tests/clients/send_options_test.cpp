// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/send_command.hpp"

#include <doctest/doctest.h>

#include <map>
#include <sstream>

#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/status_command.hpp"

using namespace ameoto::client;

namespace {
Environment environment(std::map<std::string, std::string> vars = {}) {
    return [vars](const std::string& name) -> std::optional<std::string> {
        const auto it = vars.find(name);
        if (it == vars.end()) return std::nullopt;
        return it->second;
    };
}
}  // namespace

TEST_CASE("send: defaults, options in both spellings, and the words after ADDRESS") {
    const ParsedSend d = parse_send({"/rain/rate", "30"}, environment());
    REQUIRE(d.error.empty());
    CHECK(d.options.target.host == "127.0.0.1");
    CHECK(d.options.target.port == 7770);
    CHECK(d.options.wait_s == 0.5);
    CHECK_FALSE(d.options.types.has_value());
    CHECK(d.options.address == "/rain/rate");
    CHECK(d.options.words == std::vector<std::string>{"30"});

    const ParsedSend p = parse_send({"--host", "::1", "--port=7771", "--types=ffff", "--wait", "2", "/drop", "-3", "--port", "x"},
                                    environment());
    REQUIRE(p.error.empty());
    CHECK(p.options.target.describe() == "[::1]:7771");
    CHECK(*p.options.types == "ffff");
    CHECK(p.options.wait_s == 2.0);
    CHECK(p.options.words == std::vector<std::string>{"-3", "--port", "x"});   // after ADDRESS all are arguments

    CHECK(parse_send({"--", "/x"}, environment()).options.address == "/x");
    CHECK(parse_send({"--help"}, environment()).help);
    CHECK(parse_send({"--port", "1", "-h"}, environment()).help);
}

TEST_CASE("send: the environment gives defaults, options win, and a bad variable is named") {
    const ParsedSend e = parse_send({"/x"}, environment({{"AMEOTO_HOST", "studio"}, {"AMEOTO_PORT", "9000"}}));
    REQUIRE(e.error.empty());
    CHECK(e.options.target.describe() == "studio:9000");
    CHECK(parse_send({"--port", "9001", "/x"}, environment({{"AMEOTO_PORT", "9000"}})).options.target.port == 9001);
    CHECK(parse_send({"/x"}, environment({{"AMEOTO_PORT", ""}})).options.target.port == 7770);
    CHECK(parse_send({"/x"}, environment({{"AMEOTO_PORT", "abc"}})).error == "AMEOTO_PORT needs a UDP port number 1..65535, got 'abc'");
    CHECK(parse_send({"--port", "9001", "/x"}, environment({{"AMEOTO_PORT", "abc"}})).error.empty());
}

TEST_CASE("send: usage errors say what is wrong") {
    auto error = [](std::vector<std::string> words) { return parse_send(words, environment()).error; };
    CHECK(error({}) == "missing ADDRESS (for example /rain/rate)");
    CHECK(error({"rain/rate", "30"}) == "ADDRESS must start with '/', got 'rain/rate'");
    CHECK(error({"--port", "0", "/x"}) == "--port needs a UDP port number 1..65535, got '0'");
    CHECK(error({"--port", "70000", "/x"}) == "--port needs a UDP port number 1..65535, got '70000'");
    CHECK(error({"--port"}) == "--port needs a value");
    CHECK(error({"--wait", "-1", "/x"}) == "--wait needs a number of seconds 0..3600, got '-1'");
    CHECK(error({"--wait", "soon", "/x"}) == "--wait needs a number of seconds 0..3600, got 'soon'");
    CHECK(error({"--verbose", "/x"}) == "unknown option '--verbose'");
    CHECK(error({"-3", "/x"}) == "unknown option '-3'");
}

TEST_CASE("send and status: usage errors exit 2 before anything is sent") {
    std::ostringstream out, err;
    const CommandIo io{environment(), out, err};
    CHECK(run_send({"--types", "fff", "/drop", "3", "0"}, io) == exit_status::usage);
    CHECK(err.str() == "ameoto send: --types 'fff' has 3 types but 2 arguments were given\n(see ameoto send --help)\n");
    err.str("");
    CHECK(run_send({"--types", "f", "/rain/rate", "abc"}, io) == exit_status::usage);
    CHECK(err.str().starts_with("ameoto send: argument 1 'abc': is not a number (type f)\n"));
    err.str("");
    CHECK(run_status({"--json=yes"}, io) == exit_status::usage);
    CHECK(err.str().starts_with("ameoto status: --json takes no value\n"));
    err.str("");
    CHECK(run_status({"extra"}, io) == exit_status::usage);
    CHECK(err.str().starts_with("ameoto status: unexpected argument 'extra'\n"));
    CHECK(out.str().empty());

    CHECK(run_send({"--help"}, io) == exit_status::ok);
    CHECK(out.str().starts_with("usage: ameoto send"));
}
