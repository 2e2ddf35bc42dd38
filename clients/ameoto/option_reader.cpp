// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/option_reader.hpp"

#include "clients/ameoto/number_text.hpp"

namespace ameoto::client {

OptionReader::OptionReader(std::vector<std::string> words) : words_(std::move(words)) {}

bool OptionReader::next_option() {
    name_.clear();
    inline_value_.reset();
    if (next_ >= words_.size()) return false;
    const std::string& word = words_[next_];
    if (word == "--") {
        ++next_;
        return false;
    }
    if (word.size() < 2 || word[0] != '-') return false;
    ++next_;
    const auto equals = word.find('=');
    if (word.starts_with("--") && equals != std::string::npos) {
        name_ = word.substr(0, equals);
        inline_value_ = word.substr(equals + 1);
    } else {
        name_ = word;
    }
    return true;
}

OptionReader::Word OptionReader::next_word() {
    positional_.clear();
    if (next_option()) return Word::option;
    if (next_ >= words_.size()) return Word::end;
    positional_ = words_[next_++];
    return Word::positional;
}

std::optional<std::string> OptionReader::value() {
    if (inline_value_) return inline_value_;
    if (next_ >= words_.size()) {
        error_ = name_ + " needs a value";
        return std::nullopt;
    }
    return words_[next_++];
}

bool OptionReader::flag() {
    if (!inline_value_) return true;
    error_ = name_ + " takes no value";
    return false;
}

bool OptionReader::value_into(std::string& out, std::string& error) {
    const auto v = value();
    if (!v) {
        error = error_;
        return false;
    }
    out = *v;
    return true;
}

std::optional<double> OptionReader::number_into(double low, double high, const std::string& unit, std::string& error) {
    std::string text;
    if (!value_into(text, error)) return std::nullopt;
    const auto v = parse_number(text);
    if (!v) {
        error = name_ + ": '" + text + "' is not a number";
        return std::nullopt;
    }
    if (*v < low || *v > high) {
        error = name_ + ": " + text + " " + unit + " is outside " + short_number(low) + ".." + short_number(high) + " " + unit;
        return std::nullopt;
    }
    return v;
}

bool OptionReader::flag_into(std::string& error) {
    if (flag()) return true;
    error = error_;
    return false;
}

std::string OptionReader::unknown() const { return "unknown option '" + name_ + "'"; }

std::vector<std::string> OptionReader::rest() const {
    return {words_.begin() + static_cast<std::ptrdiff_t>(next_), words_.end()};
}

}  // namespace ameoto::client
