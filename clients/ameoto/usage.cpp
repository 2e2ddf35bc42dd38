// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/usage.hpp"

#include "clients/ameoto/reply_format.hpp"
#include "clients/ameoto/status_report.hpp"
#include "protocol/address_table.hpp"

#ifndef AMEOTO_VERSION
#define AMEOTO_VERSION "unknown"
#endif

namespace ameoto::client {
namespace {

constexpr const char* units = "Units: rain rate mm/h, drop diameter mm, speed m/s, positions m.\n";

constexpr const char* target_help =
    "  --host H            server host name or IP address (default $AMEOTO_HOST, else 127.0.0.1)\n"
    "  --port P            server UDP port, 1..65535 (default $AMEOTO_PORT, else 7770)\n";

// "cpu_average_percent, cpu_peak_percent, ..." wrapped to the help's column.
std::string json_keys() {
    std::string out, line = "                      ";
    const auto fields = status_fields();
    for (std::size_t i = 0; i < fields.size(); ++i) {
        const std::string word = std::string(fields[i].json_key) + (i + 1 < fields.size() ? "," : "");
        if (line.size() + 1 + word.size() > 90) {
            out += line + "\n";
            line = "                      ";
        }
        line += (line.back() == ' ' ? "" : " ") + word;
    }
    return out + line + "\n";
}

// "/drop diameter speed x y [surface]" and one line per argument: unit, range, help.
std::string address_list() {
    std::string out;
    for (const protocol::AddressSpec& a : protocol::address_table()) {
        std::string line = std::string("  ") + a.address;
        for (const auto& arg : a.arguments) line += arg.optional ? std::string(" [") + arg.name + "]" : std::string(" ") + arg.name;
        out += line + "\n      " + a.summary;
        if (*a.reply) out += std::string(" Reply: ") + a.reply + ".";
        out += "\n";
        if (a.query.available) {
            out += std::string("      Query: ") + a.address;
            for (const auto& arg : a.query.arguments) out += std::string(" ") + arg.name;
            out += std::string(" -> ") + a.query.reply + "\n";
        }
        for (const auto& arg : a.arguments) {
            out += std::string("      ") + arg.name + ": ";
            if (arg.kind == protocol::ArgumentKind::text) {
                out += "text";
            } else {
                out += arg.kind == protocol::ArgumentKind::integer ? "integer" : "number";
                if (*arg.unit) out += std::string(" in ") + arg.unit;
                out += ", " + shortest_double(arg.min) + ".." + shortest_double(arg.max);
            }
            if (*arg.help) out += std::string("; ") + arg.help;
            out += "\n";
        }
    }
    return out;
}

}  // namespace

std::string general_usage() {
    return std::string(
               "usage: ameoto COMMAND [options] [arguments]\n"
               "       ameoto --help | --version | help [COMMAND]\n"
               "\n"
               "ameoto controls the ameotod rain server over OSC (UDP).\n"
               "\n"
               "Commands:\n"
               "  send      send one OSC message and print the server's replies\n"
               "  status    print the server's state: CPU load, drops, xruns, rain rate, ...\n"
               "  watch     live level meters and load in the terminal (Ctrl-C quits)\n"
               "  bench     measure the physics engine on this machine: speed, accuracy (no server needed)\n"
               "  render    render one drop on the umbrella to a WAV file, offline (no server needed)\n"
               "  reference run the offline air reference's validations (FDTD; no server needed)\n"
               "  help      this text, or a command's: ameoto help send\n"
               "\n"
               "Options (--host and --port: send, status and watch):\n") +
           target_help +
           "  --help              the command's help\n"
           "\n"
           "Examples:\n"
           "  ameoto send /rain/rate 30           rain at 30 mm/h (ramps over 1 s)\n"
           "  ameoto send /drop 3 0 0.2 0.1       one 3 mm drop at terminal speed, at (0.2, 0.1) m\n"
           "  ameoto status                       the server's state, one field per line\n"
           "  ameoto watch                        live meters and load until Ctrl-C\n"
           "  ameoto render drop --diameter 5 -o drop.wav   a 5 mm drop on the canopy, offline\n"
           "\n" +
           units +
           "Exit status: 0 done; 1 the server refused (/fail) or did not answer; 2 usage error;\n"
           "3 the message could not be sent. See docs/cli.md.\n";
}

std::string send_usage() {
    return std::string(
               "usage: ameoto send [--host H] [--port P] [--tcp] [--types TAGS] [--wait SECONDS] ADDRESS [ARGS...]\n"
               "\n"
               "Sends one OSC message to ameotod and prints each reply, one per line, e.g.\n"
               "  /fail \"/rain/rate\" \"argument 1 rate (mm/h): 900 is outside 0..500\"\n"
               "Options come before ADDRESS; everything after it is an argument (so -3 is a number).\n"
               "\n"
               "Options:\n") +
           target_help +
           "  --tcp               send over TCP instead of UDP, to the server's --tcp-port (give it\n"
           "                      with --port); replies come back on the connection\n"
           "  --types TAGS        OSC type tags for all arguments, one letter each: i h (integer),\n"
           "                      f d (float), s (string), T (true), F (false); e.g. --types ffffs.\n"
           "                      Without it each argument's type is inferred: 30 -> i, 0.2 or 1e3\n"
           "                      -> f, true/false -> T/F, anything else -> s (the server takes i\n"
           "                      or f for every number)\n"
           "  --wait SECONDS      how long to wait for replies, 0..3600 (default 0.5). The wait\n"
           "                      ends early at the reply that settles it: /status.reply for\n"
           "                      /status, /synced for /sync, /done for /quit, or a /fail for the\n"
           "                      address sent. Other addresses are answered only when refused,\n"
           "                      so for them the whole time is spent listening for a /fail.\n"
           "                      0 sends and returns at once, seeing no /fail.\n"
           "\n"
           "Exit status: 0 no /fail came back; 1 a /fail came back; 2 usage error (nothing sent);\n"
           "3 not sent (unknown host, socket error, nothing listening on the port).\n"
           "\n"
           "Examples:\n"
           "  ameoto send /rain/rate 30\n"
           "  ameoto send /drop 3 0 0.2 0.1\n"
           "  ameoto send --types ffffs /drop 3 0 0.2 0.1 umbrella\n"
           "  ameoto send /sync 7                 prints /synced 7 once everything before it is applied\n"
           "  ameoto send --port 7771 /quit\n"
           "\n" +
           units +
           "\n"
           "Addresses this version knows (the server has the final word):\n" +
           address_list();
}

std::string status_usage() {
    return std::string(
               "usage: ameoto status [--host H] [--port P] [--json]\n"
               "\n"
               "Asks ameotod for /status.reply (waiting up to 2 s) and prints each field with its\n"
               "name and unit, one per line, e.g. \"cpu average: 3.1 %\".\n"
               "\n"
               "Options:\n") +
           target_help +
           "  --json              print one JSON object on one line instead, with these keys\n"
           "                      (units in the names; backend is a string, the rest numbers):\n" +
           json_keys() +
           "\n"
           "Exit status: 0 printed; 1 no reply within 2 s (is ameotod running?), or a /fail;\n"
           "2 usage error; 3 not sent.\n"
           "\n"
           "Examples:\n"
           "  ameoto status\n"
           "  ameoto status --json | jq .rain_rate_mm_per_h\n";
}

std::string version_text() { return "ameoto " AMEOTO_VERSION "\n"; }

}  // namespace ameoto::client
