// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Reads a subcommand's options off the front of its words: "--name VALUE", "--name=VALUE" and
// flags, up to the first word that is not an option (or "--"). Options end there so that what
// follows (an OSC address and its arguments, which may be negative numbers) is never mistaken
// for an option.
//
// Interface:
//   OptionReader r(words);
//   while (r.next_option()) {
//       if (r.is("--json")) { if (!r.flag()) return usage(r.error()); json = true; }
//       else if (r.is("--port")) { auto v = r.value(); if (!v) return usage(r.error()); ... }
//       else return usage(r.unknown());
//   }
//   std::vector<std::string> rest = r.rest();
//
// For commands whose options may come before or after their words (`bench engine --json`,
// `render drop --diameter 3`), read word by word instead:
//   for (auto w = r.next_word(); w != OptionReader::Word::end; w = r.next_word())
//       if (w == OptionReader::Word::positional) use(r.positional()); else handle(r.name()) as above.
//   auto seconds = r.number_into(0.01, 60.0, "s", error);   // a checked number, or the message

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ameoto::client {

class OptionReader {
public:
    explicit OptionReader(std::vector<std::string> words);

    bool next_option();                   // consumes the next word if it is an option

    enum class Word { option, positional, end };
    Word next_word();                     // the next word, option or not (options anywhere)
    const std::string& name() const { return name_; }              // the current option ("" for a word)
    const std::string& positional() const { return positional_; }  // the current non-option word
    bool is(std::string_view name) const { return name_ == name; }
    std::optional<std::string> value();   // the option's value; nullopt (and error()) when missing
    bool flag();                          // false (and error()) when a value was given: "--json=1"
    std::string unknown() const;          // the message for an option nobody asked for
    // The same two checks for parsers that keep the value and the message in their own variables.
    bool value_into(std::string& out, std::string& error);
    bool flag_into(std::string& error);
    // The option's value as a finite number within [low, high]; nullopt with the message (naming the
    // option, the value, the range and `unit`) in error otherwise.
    std::optional<double> number_into(double low, double high, const std::string& unit, std::string& error);
    const std::string& error() const { return error_; }
    std::vector<std::string> rest() const;

private:
    std::vector<std::string> words_;
    std::size_t next_ = 0;
    std::string name_;
    std::string positional_;
    std::optional<std::string> inline_value_;
    std::string error_;
};

}  // namespace ameoto::client
