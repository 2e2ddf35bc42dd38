// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/status_command.hpp"

#include <chrono>

#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/option_reader.hpp"
#include "clients/ameoto/reply_format.hpp"
#include "clients/ameoto/reply_wait.hpp"
#include "clients/ameoto/status_report.hpp"
#include "clients/ameoto/target_options.hpp"
#include "clients/ameoto/open_and_send.hpp"
#include "clients/ameoto/udp_client.hpp"
#include "clients/ameoto/usage.hpp"

namespace ameoto::client {
namespace {

constexpr const char* status_error_prefix = "ameoto status: ";

int usage_error(const CommandIo& io, const std::string& message) {
    io.err << status_error_prefix << message << "\n(see ameoto status --help)\n";
    return exit_status::usage;
}

}  // namespace

int run_status(const CommandWords& words, const CommandIo& io) {
    TargetOptions target_options(io.environment);
    OptionReader r(words);
    bool json = false;
    std::string error;
    while (r.next_option()) {
        if (r.is("--help") || r.is("-h")) {
            io.out << status_usage();
            return exit_status::ok;
        }
        if (target_options.take(r, error)) {
            if (!error.empty()) return usage_error(io, error);
        } else if (r.is("--json")) {
            if (!r.flag()) return usage_error(io, r.error());
            json = true;
        } else {
            return usage_error(io, r.unknown());
        }
    }
    if (auto e = target_options.finish()) return usage_error(io, *e);
    if (const auto rest = r.rest(); !rest.empty()) return usage_error(io, "unexpected argument '" + rest.front() + "'");
    const Target& target = target_options.target();

    auto client = open_and_send(target, Transport::udp, protocol::encode_message("/status", {}), io, status_error_prefix);
    if (!client) return exit_status::not_sent;

    int result = exit_status::refused;
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(status_timeout_s));
    const WaitResult w = wait_for_replies(
        *client, deadline,
        [&](const protocol::DecodedMessage& m) {
            if (m.address == "/fail") {
                io.err << status_error_prefix << "the server refused /status: " << format_message(m) << "\n";
                return true;
            }
            if (m.address != "/status.reply") return false;   // e.g. a stray /synced: not ours
            const StatusReport report = parse_status_reply(m);
            if (!report.error.empty()) {
                io.err << status_error_prefix << report.error << "\n" << "  " << format_message(m) << "\n";
                return true;
            }
            io.out << (json ? format_status_json(report) : format_status_text(report));
            result = exit_status::ok;
            return true;
        },
        [&](const std::string& problem) { io.err << status_error_prefix << problem << "\n"; });

    switch (w.ending) {
        case WaitResult::Ending::stopped: return result;
        case WaitResult::Ending::timed_out:
            io.err << status_error_prefix << "no reply from " << target.describe() << " within " << shortest_double(status_timeout_s)
                   << " s: is ameotod running?\n";
            return exit_status::refused;
        case WaitResult::Ending::refused:
            io.err << status_error_prefix << "no reply from " << target.describe()
                   << ": nothing is listening there (connection refused): is ameotod running?\n";
            return exit_status::refused;
        case WaitResult::Ending::error:
            io.err << status_error_prefix << "cannot read the reply from " << target.describe() << ": " << w.error << "\n";
            return exit_status::refused;
    }
    return result;
}

}  // namespace ameoto::client
