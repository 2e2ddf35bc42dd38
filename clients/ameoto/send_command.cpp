// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/send_command.hpp"

#include <charconv>
#include <chrono>
#include <cmath>

#include "clients/ameoto/argument_types.hpp"
#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/expected_reply.hpp"
#include "clients/ameoto/option_reader.hpp"
#include "clients/ameoto/reply_format.hpp"
#include "clients/ameoto/reply_wait.hpp"
#include "clients/ameoto/target_options.hpp"
#include "clients/ameoto/open_and_send.hpp"
#include "clients/ameoto/udp_client.hpp"
#include "clients/ameoto/usage.hpp"

namespace ameoto::client {
namespace {

constexpr const char* send_error_prefix = "ameoto send: ";

std::optional<double> parse_seconds(const std::string& text) {
    double v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v, std::chars_format::general);
    if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v) || v < 0 ||
        v > max_send_wait_s)
        return std::nullopt;
    return v;
}

std::string seconds_text(double s) {
    return shortest_double(s) + " s";
}

}  // namespace

ParsedSend parse_send(const CommandWords& words, const Environment& environment) {
    ParsedSend p;
    auto fail = [&p](const std::string& message) {
        p.error = message;
        return p;
    };
    TargetOptions target(environment);
    OptionReader r(words);
    std::string error;
    while (r.next_option()) {
        if (r.is("--help") || r.is("-h")) {
            p.help = true;
            return p;
        }
        if (target.take(r, error)) {
            if (!error.empty()) return fail(error);
            continue;
        }
        if (r.is("--tcp")) {
            if (!r.flag()) return fail(r.error());
            p.options.tcp = true;
            continue;
        }
        if (!r.is("--types") && !r.is("--wait")) return fail(r.unknown());
        const auto value = r.value();
        if (!value) return fail(r.error());
        if (r.is("--types")) {
            p.options.types = *value;
        } else {
            const auto seconds = parse_seconds(*value);
            if (!seconds) return fail("--wait needs a number of seconds 0.." + shortest_double(max_send_wait_s) + ", got '" + *value + "'");
            p.options.wait_s = *seconds;
        }
    }
    if (auto e = target.finish()) return fail(*e);
    p.options.target = target.target();
    std::vector<std::string> rest = r.rest();
    if (rest.empty()) return fail("missing ADDRESS (for example /rain/rate)");
    p.options.address = rest.front();
    if (p.options.address.empty() || p.options.address[0] != '/')
        return fail("ADDRESS must start with '/', got '" + p.options.address + "'");
    p.options.words.assign(rest.begin() + 1, rest.end());
    return p;
}

int run_send(const CommandWords& words, const CommandIo& io) {
    const ParsedSend p = parse_send(words, io.environment);
    if (p.help) {
        io.out << send_usage();
        return exit_status::ok;
    }
    if (!p.error.empty()) {
        io.err << send_error_prefix << p.error << "\n" << "(see ameoto send --help)\n";
        return exit_status::usage;
    }
    const SendOptions& o = p.options;
    const TypedArguments typed = o.types ? typed_arguments(*o.types, o.words) : inferred_arguments(o.words);
    if (!typed.error.empty()) {
        io.err << send_error_prefix << typed.error << "\n" << "(see ameoto send --help)\n";
        return exit_status::usage;
    }

    auto client = open_and_send(o.target, o.tcp ? Transport::tcp : Transport::udp,
                                protocol::encode_message(o.address, typed.arguments), io, send_error_prefix);
    if (!client) return exit_status::not_sent;
    if (o.wait_s <= 0) return exit_status::ok;

    bool got_fail = false;
    bool got_expected = false;
    const auto expected = expected_reply(o.address);
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(o.wait_s));
    const WaitResult w = wait_for_replies(
        *client, deadline,
        [&](const protocol::DecodedMessage& m) {
            io.out << format_message(m) << std::endl;   // flushed: a script may read line by line
            if (m.address == "/fail") got_fail = true;
            const bool ends = ends_wait(o.address, typed.arguments, m);
            if (ends && m.address != "/fail") got_expected = true;
            return ends;
        },
        [&](const std::string& problem) { io.err << send_error_prefix << problem << "\n"; });

    switch (w.ending) {
        case WaitResult::Ending::refused:
            if (o.tcp) {
                io.err << send_error_prefix << "the server closed the connection (" << o.target.describe() << ")\n";
                return got_fail ? exit_status::refused : exit_status::not_sent;
            }
            io.err << send_error_prefix << "nothing is listening on " << o.target.describe()
                   << " (connection refused): is ameotod running?\n";
            return exit_status::not_sent;
        case WaitResult::Ending::error:
            io.err << send_error_prefix << "cannot read replies from " << o.target.describe() << ": " << w.error << "\n";
            return exit_status::not_sent;
        case WaitResult::Ending::timed_out:
            if (expected && !got_fail && !got_expected)
                io.err << send_error_prefix << "no " << *expected << " from " << o.target.describe() << " within "
                       << seconds_text(o.wait_s) << "\n";
            break;
        case WaitResult::Ending::stopped: break;
    }
    return got_fail ? exit_status::refused : exit_status::ok;
}

}  // namespace ameoto::client
