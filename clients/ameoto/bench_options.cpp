// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_options.hpp"

#include "clients/ameoto/number_text.hpp"
#include "clients/ameoto/option_reader.hpp"
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace ameoto::client {
namespace {

std::optional<long> parse_integer(const std::string& text) {
    if (text.empty() || text[0] == '+' || text[0] == '-' || text[0] == ' ') return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (errno != 0 || end != text.c_str() + text.size()) return std::nullopt;
    return v;
}

// The options each suite reads (bench_command.cpp's usage lines); one given to a suite that would
// ignore it is refused rather than silently dropped, so no one reads a figure as measured with it.
std::vector<std::string> options_of(const std::string& suite) {
    if (suite == "drop") return {"--json", "--runs"};
    if (suite == "scene" || suite == "formats") return {"--json", "--seconds"};
    return {"--json", "--seconds", "--sizes", "--runs", "--no-faust"};
}

}  // namespace

std::optional<std::vector<int>> parse_sizes(const std::string& text) {
    std::vector<int> sizes;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        const auto n = parse_integer(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (!n || *n < 1 || *n > 200000) return std::nullopt;
        sizes.push_back(static_cast<int>(*n));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (sizes.size() > 16) return std::nullopt;
    return sizes;
}

BenchParse parse_bench_options(const CommandWords& words, BenchOptions& options, std::string& error) {
    OptionReader reader(words);
    std::vector<std::string> given;   // the options named, for the suite's check at the end
    for (auto kind = reader.next_word(); kind != OptionReader::Word::end; kind = reader.next_word()) {
        // The word as typed for the messages below: the option's name, or the positional word.
        const std::string word = kind == OptionReader::Word::positional ? reader.positional() : reader.name();
        const std::string& name = reader.name();
        std::string value;
        auto take_value = [&] { return reader.value_into(value, error); };
        auto no_value = [&] { return reader.flag_into(error); };
        if (kind != OptionReader::Word::positional) given.push_back(name);
        if (name == "--help" || name == "-h") {
            return BenchParse::help;
        } else if (name == "--json") {
            if (!no_value()) return BenchParse::error;
            options.json = true;
        } else if (name == "--no-faust") {
            if (!no_value()) return BenchParse::error;
            options.faust = false;
        } else if (name == "--seconds") {
            if (!take_value()) return BenchParse::error;
            const auto v = parse_number(value);
            if (!v || *v < 0.01 || *v > 600.0) {
                error = "--seconds '" + value + "': give the seconds per measurement, 0.01..600";
                return BenchParse::error;
            }
            options.seconds = *v;
        } else if (name == "--sizes") {
            if (!take_value()) return BenchParse::error;
            const auto v = parse_sizes(value);
            if (!v) {
                error = "--sizes '" + value + "': give up to 16 mass counts 1..200000, separated by commas (55,1000,10000)";
                return BenchParse::error;
            }
            options.sizes = *v;
        } else if (name == "--runs") {
            if (!take_value()) return BenchParse::error;
            const auto v = parse_integer(value);
            if (!v || *v < 1 || *v > 101) {
                error = "--runs '" + value + "': give the number of timed runs, 1..101";
                return BenchParse::error;
            }
            options.runs = static_cast<int>(*v);
        } else if (word.starts_with("-")) {
            error = "unknown option '" + name + "'";
            return BenchParse::error;
        } else if (options.suite.empty()) {
            options.suite = word;
        } else {
            error = "unexpected argument '" + word + "'";
            return BenchParse::error;
        }
    }
    if (options.suite.empty()) {
        error = "which suite? (ameoto bench engine | drop | scene | formats)";
        return BenchParse::error;
    }
    if (options.suite != "engine" && options.suite != "drop" && options.suite != "scene" && options.suite != "formats") {
        error = "unknown suite '" + options.suite + "' (the suites: engine, drop, scene, formats)";
        return BenchParse::error;
    }
    const auto accepted = options_of(options.suite);
    for (const std::string& option : given) {
        if (std::find(accepted.begin(), accepted.end(), option) != accepted.end()) continue;
        error = option + " does not apply to bench " + options.suite + " (it takes";
        for (const auto& a : accepted) error += " " + a;
        error += ")";
        return BenchParse::error;
    }
    return BenchParse::run;
}

}  // namespace ameoto::client
