// SPDX-License-Identifier: GPL-3.0-or-later
#include "tests/support/daemon_process.hpp"

#include <algorithm>
#include <stdexcept>

namespace ameoto::test {
namespace {

std::vector<std::string> command_line(std::vector<std::string> arguments, const std::vector<std::string>& wrapper) {
    arguments.insert(arguments.begin(), AMEOTO_BIN_DIR "/ameotod");
    arguments.insert(arguments.begin(), wrapper.begin(), wrapper.end());
    arguments.insert(arguments.end(), {"--port", "0"});
    // --level physical unless the test chooses: most tests check the physical samples (and the drop's onset
    // without the limiter's look-ahead), and --level auto's calibration render would cost every start about
    // 0.7 s of CPU (several seconds under the sanitizers). Level tests say --level auto.
    if (std::find(arguments.begin(), arguments.end(), "--level") == arguments.end()) arguments.insert(arguments.end(), {"--level", "physical"});
    return arguments;
}

std::string within(std::chrono::milliseconds t) { return "within " + std::to_string(t.count()) + " ms"; }

}  // namespace

DaemonProcess::DaemonProcess(std::vector<std::string> arguments, const std::vector<std::string>& env, const DaemonOptions& options)
    : process_(command_line(std::move(arguments), options.wrapper), env, options.child) {
    // A throw from here on destroys process_, which stops ameotod.
    const auto line = process_.wait_for_line("listening on osc.udp://", options.listen_timeout);
    if (!line)
        throw std::runtime_error("ameotod did not say where it listens " + within(options.listen_timeout) +
                                 "; it printed:\n" + process_.output() + process_.error_output());
    listening_line_ = *line;
    port_ = port_from_listening_line(*line);
    if (port_ <= 0) throw std::runtime_error("ameotod listens on no usable port: " + *line);
    if (!process_.wait_for_line(options.ready_line, options.running_timeout))
        throw std::runtime_error("ameotod did not say \"" + options.ready_line + "\" " + within(options.running_timeout) + "; it printed:\n" +
                                 process_.output() + process_.error_output());
    // The TCP line comes right after the UDP one, before "running": already read here.
    const std::string tcp = "listening on osc.tcp://";
    const std::string& out = process_.output();
    if (const auto at = out.find(tcp); at != std::string::npos) tcp_port_ = port_from_listening_line(out.substr(at, out.find('\n', at) - at));
}

int port_from_listening_line(const std::string& line) {
    const auto colon = line.rfind(':');
    return colon == std::string::npos ? -1 : std::stoi(line.substr(colon + 1));
}

}  // namespace ameoto::test
