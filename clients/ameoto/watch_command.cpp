// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/watch_command.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <iostream>

#include "clients/ameoto/exit_status.hpp"
#include "clients/ameoto/number_text.hpp"
#include "clients/ameoto/option_reader.hpp"
#include "clients/ameoto/reply_format.hpp"
#include "clients/ameoto/reply_wait.hpp"
#include "clients/ameoto/target_options.hpp"
#include "clients/ameoto/open_and_send.hpp"
#include "clients/ameoto/udp_client.hpp"
#include "clients/ameoto/watch_view.hpp"

namespace ameoto::client {
namespace {

constexpr const char* watch_error_prefix = "ameoto watch: ";
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

volatile std::sig_atomic_t stop_requested = 0;
void request_stop(int) { stop_requested = 1; }

// Ctrl-C and SIGTERM end the watch through the loop (which then unsubscribes), not by killing it.
// No SA_RESTART: a pending receive returns at once.
struct StopSignals {
    struct sigaction old_int {}, old_term {};
    StopSignals() {
        stop_requested = 0;
        struct sigaction a {};
        a.sa_handler = request_stop;
        sigemptyset(&a.sa_mask);
        sigaction(SIGINT, &a, &old_int);
        sigaction(SIGTERM, &a, &old_term);
    }
    ~StopSignals() {
        sigaction(SIGINT, &old_int, nullptr);
        sigaction(SIGTERM, &old_term, nullptr);
    }
};

int usage_error(const CommandIo& io, const std::string& message) {
    io.err << watch_error_prefix << message << "\n(see ameoto watch --help)\n";
    return exit_status::usage;
}

int count_lines(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

}  // namespace

std::string watch_usage() {
    return "usage: ameoto watch [--host H] [--port P] [--count N]\n"
           "\n"
           "Subscribes to ameotod's notifications (/notify 1) and shows them live: each channel's\n"
           "level (RMS bar over -60..0 dBFS, RMS and peak in dBFS, ten times a second, from /meter)\n"
           "and the server's load, drops and rain rate (every second, from /status.reply).\n"
           "On a terminal the screen is redrawn in place; otherwise (a pipe, a file) each update is\n"
           "one line:\n"
           "  meter t=1.000 1:-23.4/-31.0 2:-22.9/-30.7 dBFS peak/rms\n"
           "  status cpu=3.1% peak=4.0% drops/s=120.0 full=0 template=3 texture=40 rain=2.00mm/h xruns=0 late=0 backend=null\n"
           "Ctrl-C (SIGINT) or SIGTERM unsubscribes (/notify 0) and quits with status 0.\n"
           "\n"
           "Options:\n"
           "  --host H            server host name or IP address (default $AMEOTO_HOST, else 127.0.0.1)\n"
           "  --port P            server UDP port, 1..65535 (default $AMEOTO_PORT, else 7770)\n"
           "  --count N           quit after N updates, 1..1000000 (default: until Ctrl-C)\n"
           "\n"
           "When the server falls silent for 3 s, watch says so and subscribes again every 3 s\n"
           "(a restarted server has forgotten its subscribers).\n"
           "\n"
           "Exit status: 0 quit by Ctrl-C or after --count updates; 1 the server did not answer\n"
           "/notify within 2 s, or refused it (16 subscribers already); 2 usage error; 3 not sent.\n";
}

int run_watch(const CommandWords& words, const CommandIo& io) {
    TargetOptions target_options(io.environment);
    OptionReader r(words);
    long count = 0;   // 0: until Ctrl-C
    std::string error;
    while (r.next_option()) {
        if (r.is("--help") || r.is("-h")) {
            io.out << watch_usage();
            return exit_status::ok;
        }
        if (target_options.take(r, error)) {
            if (!error.empty()) return usage_error(io, error);
        } else if (r.is("--count")) {
            const auto n = r.number_into(1, 1000000, "", error);
            if (!n) return usage_error(io, error);
            if (*n != static_cast<long>(*n)) return usage_error(io, "--count needs a whole number of updates");
            count = static_cast<long>(*n);
        } else {
            return usage_error(io, r.unknown());
        }
    }
    if (auto e = target_options.finish()) return usage_error(io, *e);
    if (const auto rest = r.rest(); !rest.empty()) return usage_error(io, "unexpected argument '" + rest.front() + "'");
    const Target& target = target_options.target();

    const auto subscribe = protocol::encode_message("/notify", {protocol::OscArgument::from_int(1)});
    auto client = open_and_send(target, Transport::udp, subscribe, io, watch_error_prefix);
    if (!client) return exit_status::not_sent;
    const StopSignals signals;
    const bool screen = isatty(STDOUT_FILENO) && &io.out == &std::cout;
    WatchState state;
    state.target = target.describe();
    bool subscribed = false, refused = false, silent_said = false;
    int shown_lines = 0;
    long updates = 0;
    auto last_heard = Clock::now();
    const auto first_deadline = Clock::now() + 2s;

    auto show = [&] {
        ++updates;
        if (!screen) return;
        const std::string text = format_watch_screen(state);
        if (shown_lines > 0) io.out << "\x1b[" << shown_lines << "A\r\x1b[J";   // back to the top of the last screen, clear it
        io.out << text << std::flush;
        shown_lines = count_lines(text);
    };
    auto on_message = [&](const protocol::DecodedMessage& m) {
        last_heard = Clock::now();
        if (silent_said) {
            io.err << watch_error_prefix << "the server is back\n";
            silent_said = false;
            shown_lines = 0;
        }
        if (m.address == "/done" && !m.args.empty() && m.args[0].text == "/notify") {
            subscribed = true;
        } else if (m.address == "/fail") {
            io.err << watch_error_prefix << "the server refused: " << format_message(m) << "\n";
            shown_lines = 0;
            if (!m.args.empty() && m.args[0].text == "/notify") refused = true;
            return refused;
        } else if (m.address == "/meter") {
            subscribed = true;
            MeterReading meter = parse_meter(m);
            if (!meter.error.empty()) {
                io.err << watch_error_prefix << meter.error << "\n";
                shown_lines = 0;
                return false;
            }
            if (!screen) io.out << format_meter_line(meter) << std::flush;
            state.meter = std::move(meter);
            show();
        } else if (m.address == "/status.reply") {
            subscribed = true;
            StatusReport report = parse_status_reply(m);
            if (!report.error.empty()) {
                io.err << watch_error_prefix << report.error << "\n";
                shown_lines = 0;
                return false;
            }
            if (!screen) io.out << format_status_line(report) << std::flush;
            state.status = std::move(report);
            show();
        }
        return count > 0 && updates >= count;
    };

    int result = exit_status::ok;
    while (!stop_requested) {
        // Short waits, so Ctrl-C is seen within 200 ms even if the receive is not interrupted.
        const WaitResult w = wait_for_replies(*client, Clock::now() + 200ms, on_message,
                                              [&](const std::string& problem) { io.err << watch_error_prefix << problem << "\n"; });
        if (w.ending == WaitResult::Ending::stopped) {
            if (refused) result = exit_status::refused;
            break;
        }
        if (w.ending == WaitResult::Ending::error) {
            io.err << watch_error_prefix << "cannot read from " << target.describe() << ": " << w.error << "\n";
            return exit_status::refused;
        }
        if (w.ending == WaitResult::Ending::refused && !subscribed) {
            io.err << watch_error_prefix << "no reply from " << target.describe()
                   << ": nothing is listening there (connection refused): is ameotod running?\n";
            return exit_status::refused;
        }
        if (!subscribed && Clock::now() > first_deadline) {
            io.err << watch_error_prefix << "no reply to /notify from " << target.describe() << " within 2 s: is ameotod running?\n";
            return exit_status::refused;
        }
        if (subscribed && Clock::now() - last_heard > 3s) {
            if (!silent_said) {
                io.err << watch_error_prefix << "no notifications from " << target.describe() << " for 3 s; subscribing again\n";
                shown_lines = 0;   // a terminal's screen moved down by that line: draw the next one below it
            }
            silent_said = true;
            last_heard = Clock::now();
            client->send(subscribe, error);   // a refused port (server down) is seen as silence here
        }
    }
    // Leave the subscriber list, so the server stops sending (and the place is free for another).
    if (!refused && client->send(protocol::encode_message("/notify", {protocol::OscArgument::from_int(0)}), error))
        wait_for_replies(
            *client, Clock::now() + 500ms,
            [](const protocol::DecodedMessage& m) { return m.address == "/done" && !m.args.empty() && m.args[0].text == "/notify"; },
            [](const std::string&) {});
    return result;
}

}  // namespace ameoto::client
