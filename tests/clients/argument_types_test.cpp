// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/argument_types.hpp"

#include <doctest/doctest.h>
#include "tests/support/relative_approx.hpp"

using ameoto::client::infer_argument;
using ameoto::client::typed_arguments;

TEST_CASE("integer literals are inferred as i, and as h when they do not fit 32 bits") {
    CHECK(infer_argument("30").type == 'i');
    CHECK(infer_argument("30").integer == 30);
    CHECK(infer_argument("-2").integer == -2);
    CHECK(infer_argument("+7").integer == 7);
    CHECK(infer_argument("0").type == 'i');
    CHECK(infer_argument("2147483647").type == 'i');
    CHECK(infer_argument("2147483648").type == 'h');
    CHECK(infer_argument("2147483648").integer == 2147483648LL);
    CHECK(infer_argument("-2147483649").type == 'h');
    // Past 64 bits it is still a number to the user.
    CHECK(infer_argument("123456789012345678901234").type == 'd');
}

TEST_CASE("numbers with a point or an exponent are inferred as f") {
    for (const char* word : {"0.2", "-0.2", ".5", "3.", "1e3", "1E-3", "+2.5", "2.5e+1"}) {
        INFO(word);
        CHECK(infer_argument(word).type == 'f');
    }
    CHECK(infer_argument("0.2").number == ameoto::test::relative(0.2));
    CHECK(infer_argument("1e3").number == 1000.0);
    // Too big for a float: sent as d so the server sees the value, not inf.
    CHECK(infer_argument("1e50").type == 'd');
}

TEST_CASE("true and false are booleans, anything else is a string") {
    CHECK(infer_argument("true").type == 'T');
    CHECK(infer_argument("false").type == 'F');
    for (const char* word : {"umbrella", "True", "1.2.3", "0x10", "inf", "nan", "1e", "-", "", "12abc", "e5", "infinite"}) {
        INFO("'" << word << "'");
        const auto a = infer_argument(word);
        CHECK(a.type == 's');
        CHECK(a.text == word);
    }
}

TEST_CASE("--types sets every argument's type") {
    const auto t = typed_arguments("fffs", {"3", "0", "0.2", "umbrella"});
    REQUIRE(t.error.empty());
    REQUIRE(t.arguments.size() == 4);
    CHECK(t.arguments[0].type == 'f');
    CHECK(t.arguments[0].number == 3.0);
    CHECK(t.arguments[2].number == ameoto::test::relative(0.2));
    CHECK(t.arguments[3].type == 's');
    CHECK(t.arguments[3].text == "umbrella");

    const auto all = typed_arguments(",ihdsTF", {"-4", "5000000000", "0.1", "7", "true", "false"});
    REQUIRE(all.error.empty());
    CHECK(all.arguments[0].integer == -4);
    CHECK(all.arguments[1].type == 'h');
    CHECK(all.arguments[1].integer == 5000000000LL);
    CHECK(all.arguments[2].type == 'd');
    CHECK(all.arguments[3].type == 's');
    CHECK(all.arguments[3].text == "7");   // a surface named "7" is reachable this way
    CHECK(all.arguments[4].type == 'T');
    CHECK(all.arguments[5].type == 'F');

    CHECK(typed_arguments("", {}).error.empty());
}

TEST_CASE("--types refuses a count mismatch and values that are not of their type") {
    auto error = [](std::string_view types, std::vector<std::string> words) {
        const auto t = typed_arguments(types, words);
        CHECK(t.arguments.empty());
        return t.error;
    };
    CHECK(error("fff", {"1", "2"}) == "--types 'fff' has 3 types but 2 arguments were given");
    CHECK(error("f", {"1", "2"}) == "--types 'f' has 1 type but 2 arguments were given");
    CHECK(error("ff", {"1"}) == "--types 'ff' has 2 types but 1 argument was given");
    CHECK(error("f", {"abc"}) == "argument 1 'abc': is not a number (type f)");
    CHECK(error("fi", {"1", "2.5"}) == "argument 2 '2.5': is not an integer (type i)");
    CHECK(error("i", {"3000000000"}) == "argument 1 '3000000000': does not fit a 32-bit integer (type i; use h for 64 bits)");
    CHECK(error("f", {"1e50"}) == "argument 1 '1e50': does not fit a 32-bit float (type f; use d for 64 bits)");
    CHECK(error("f", {""}) == "argument 1 '': is not a number (type f)");
    CHECK(error("T", {"false"}) == "argument 1 'false': type T needs the word true");
    CHECK(error("x", {"1"}) == "argument 1 '1': unsupported type 'x' (use i h f d s T F)");
    CHECK(error("S", {"a"}) == "argument 1 'a': unsupported type 'S' (use i h f d s T F)");
}
