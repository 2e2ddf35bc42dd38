// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/score_file.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "clients/ameoto/argument_types.hpp"

namespace ameoto::client {
namespace {

std::uint32_t big_endian_u32(const unsigned char* p) {
    return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
}

bool looks_binary(std::string_view bytes) {
    return bytes.size() >= 12 && std::memcmp(bytes.data() + 4, "#bundle\0", 8) == 0;
}

ScoreFile parse_binary(std::string_view bytes, const std::string& name) {
    ScoreFile s;
    s.binary = true;
    std::size_t at = 0;
    for (int bundle = 1; at < bytes.size(); ++bundle) {
        const std::string here = name + ": bundle " + std::to_string(bundle) + " (byte " + std::to_string(at) + ")";
        // ameotod writes a take as it plays: one killed mid-write ends in part of a bundle, which is no error.
        const bool take = !s.messages.empty() && s.messages.front().message.address == "/take/start";
        if (take && (bytes.size() - at < 4 ||
                     big_endian_u32(reinterpret_cast<const unsigned char*>(bytes.data() + at)) > bytes.size() - at - 4)) {
            s.cut_bytes = bytes.size() - at;
            break;
        }
        if (bytes.size() - at < 4) {
            s.error = here + ": " + std::to_string(bytes.size() - at) + " bytes left, not a size (4 bytes)";
            return s;
        }
        const std::uint32_t size = big_endian_u32(reinterpret_cast<const unsigned char*>(bytes.data() + at));
        at += 4;
        if (size > bytes.size() - at) {
            s.error = here + ": its size says " + std::to_string(size) + " bytes but " + std::to_string(bytes.size() - at) +
                      " are left (a cut file?)";
            return s;
        }
        const protocol::DecodedPacket p = protocol::decode_packet(bytes.data() + at, size);
        if (!p.error.empty()) {
            s.error = here + ": " + p.error;
            return s;
        }
        int index = 0;
        for (const protocol::DecodedMessage& m : p.messages) {
            ScoreMessage sm;
            sm.seconds = m.bundled ? score_seconds(m.timetag) : 0.0;
            sm.message = m;
            sm.where = name + ": bundle " + std::to_string(bundle) + ", message " + std::to_string(++index);
            s.messages.push_back(std::move(sm));
        }
        at += size;
    }
    return s;
}

// One line's words: quoted words are strings, the rest are inferred; `#` outside quotes ends the line.
bool split_words(std::string_view line, std::vector<std::pair<std::string, bool>>& words, std::string& error) {
    std::size_t i = 0;
    while (i < line.size()) {
        const char c = line[i];
        if (c == ' ' || c == '\t' || c == '\r') { ++i; continue; }
        if (c == '#') break;
        if (c == '"') {
            std::string text;
            ++i;
            bool closed = false;
            while (i < line.size()) {
                const char d = line[i++];
                if (d == '"') { closed = true; break; }
                if (d == '\\' && i < line.size() && (line[i] == '"' || line[i] == '\\')) text += line[i++];
                else text += d;
            }
            if (!closed) {
                error = "a quoted string is not closed";
                return false;
            }
            words.emplace_back(std::move(text), true);
            continue;
        }
        std::size_t end = i;
        while (end < line.size() && line[end] != ' ' && line[end] != '\t' && line[end] != '\r' && line[end] != '#') ++end;
        words.emplace_back(std::string(line.substr(i, end - i)), false);
        i = end;
    }
    return true;
}

ScoreFile parse_text(std::string_view bytes, const std::string& name) {
    ScoreFile s;
    std::size_t start = 0;
    for (int number = 1; start <= bytes.size(); ++number) {
        std::size_t end = bytes.find('\n', start);
        if (end == std::string_view::npos) end = bytes.size();
        const std::string_view line = bytes.substr(start, end - start);
        start = end + 1;
        const std::string where = name + ":" + std::to_string(number);
        std::vector<std::pair<std::string, bool>> words;
        std::string error;
        if (!split_words(line, words, error)) {
            s.error = where + ": " + error;
            return s;
        }
        if (words.empty()) continue;
        double seconds = 0.0;
        const std::string& time = words[0].first;
        const auto r = std::from_chars(time.data(), time.data() + time.size(), seconds);
        if (words[0].second || r.ec != std::errc() || r.ptr != time.data() + time.size() || !std::isfinite(seconds) || seconds < 0.0) {
            s.error = where + ": '" + time + "' is not a time (seconds from the start, a number >= 0)";
            return s;
        }
        if (words.size() < 2 || words[1].second || !words[1].first.starts_with("/")) {
            s.error = where + ": an OSC address (starting with '/') must follow the time";
            return s;
        }
        ScoreMessage m;
        m.seconds = seconds;
        m.where = where;
        m.message.address = words[1].first;
        m.message.bundled = true;
        m.message.timetag = score_timetag(seconds);
        for (std::size_t w = 2; w < words.size(); ++w) {
            const protocol::OscArgument a = words[w].second ? protocol::OscArgument::from_string(words[w].first) : infer_argument(words[w].first);
            m.message.args.push_back(a);
            m.message.types += a.type;
        }
        s.messages.push_back(std::move(m));
        if (end == bytes.size()) break;
    }
    return s;
}

}  // namespace

protocol::Timetag score_timetag(double seconds) {
    protocol::Timetag t;
    const double whole = std::floor(seconds);
    t.seconds = static_cast<std::uint32_t>(whole);
    t.fraction = static_cast<std::uint32_t>(std::min(4294967295.0, std::round((seconds - whole) * 4294967296.0)));
    return t;
}

double score_seconds(protocol::Timetag timetag) {
    if (timetag.immediate()) return 0.0;   // scsynth plays "immediately" at the start
    return static_cast<double>(timetag.seconds) + static_cast<double>(timetag.fraction) / 4294967296.0;
}

ScoreFile parse_score(std::string_view bytes, const std::string& name) {
    ScoreFile s = looks_binary(bytes) ? parse_binary(bytes, name) : parse_text(bytes, name);
    if (!s.error.empty()) s.messages.clear();
    std::stable_sort(s.messages.begin(), s.messages.end(), [](const ScoreMessage& a, const ScoreMessage& b) { return a.seconds < b.seconds; });
    return s;
}

ScoreFile read_score_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        ScoreFile s;
        s.error = path + ": cannot read";
        return s;
    }
    std::ostringstream text;
    text << in.rdbuf();
    return parse_score(text.str(), path);
}

}  // namespace ameoto::client
