// SPDX-License-Identifier: GPL-3.0-or-later
// systemd/ameotod.service and systemd/ameotod-user.service: `systemd-analyze verify` accepts both, the
// check is shown to catch broken copies, and the settings the issue asks for are there.
//
// verify needs the ExecStart binary to exist, so each unit is copied into a temporary folder with
// /usr/local/bin/ameotod replaced by the freshly built ameotod.
#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/child_process.hpp"
#include "tests/support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using ameoto::test::ProgramRun;
using ameoto::test::TempDir;

const std::string installed_binary = "/usr/local/bin/ameotod";

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    REQUIRE_MESSAGE(in.good(), "cannot read " << path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void write_text(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    REQUIRE_MESSAGE(out.good(), "cannot write " << path);
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) lines.push_back(line);
    return lines;
}


// Runs argv (looked up in PATH) with extra environment entries; out holds stdout and stderr together.
// A program that cannot be started gives exit code -1 and says so in out.
ProgramRun run(const std::vector<std::string>& argv, const std::vector<std::string>& extra_env) {
    return ameoto::test::run_program(argv, 120s, extra_env);
}

struct Unit {
    const char* source;      // in the source tree
    const char* installed;   // the name it is installed under (verify takes the unit name from it)
    bool user;               // verify with --user
};
const Unit system_unit{"systemd/ameotod.service", "ameotod.service", false};
const Unit user_unit{"systemd/ameotod-user.service", "ameotod.service", true};

std::string unit_text(const Unit& unit) { return read_text(fs::path(AMEOTO_SOURCE_DIR) / unit.source); }

// The unit with ExecStart pointing at the built binary.
std::string with_built_binary(std::string text) {
    std::string built = std::string(AMEOTO_BIN_DIR) + "/ameotod";
    if (built.find_first_of(" \t") != std::string::npos) built = "\"" + built + "\"";
    const std::string key = "ExecStart=" + installed_binary;
    const auto at = text.find(key);
    REQUIRE_MESSAGE(at != std::string::npos, "the unit has no " << key);
    REQUIRE_MESSAGE(text.find(key, at + 1) == std::string::npos, "the unit has more than one " << key);
    text.replace(at, key.size(), "ExecStart=" + built);
    return text;
}

bool verify_supports_recursive_errors() {
    static const bool supported = run({"systemd-analyze", "--help"}, {}).out.find("--recursive-errors") != std::string::npos;
    return supported;
}

struct Verdict {
    ProgramRun run;
    fs::path file;
    std::vector<std::string> blamed;   // lines about our unit: must be none
    std::vector<std::string> other;    // lines about anything else except a host's jack.service: must be none
    bool passed() const { return run.exit_code == 0 && blamed.empty() && other.empty(); }
};

// A line verify prints about a jack.service installed on this machine. Without
// --recursive-errors=no (systemd < 250 has no such option) verify also loads the units ours
// Wants=/After=, and prints their warnings under their own path; such lines are about the host's
// JACK unit, not ours, so they are tolerated, and only they: a line that also names our unit is
// still blamed. With --recursive-errors=no (systemd 252 here) dependencies are not loaded and these
// lines do not appear at all.
//
// A jack.service that does not exist produces no line either way: verify says nothing about a
// missing Wants=/After= dependency (checked with systemd 252 on a machine without jack.service: no
// output at all for either unit, with or without --recursive-errors=no).
bool about_host_jack_unit(const std::string& line) {
    const std::string subject = line.substr(0, line.find(':'));   // "jack.service" or "/path/jack.service"
    return subject == "jack.service" || (subject.size() > 13 && subject.compare(subject.size() - 13, 13, "/jack.service") == 0);
}

// Copies `text` into a temp folder as `unit.installed` and runs systemd-analyze verify on it.
// `unit_path`: a folder searched before the usual ones (SYSTEMD_UNIT_PATH), for stand-in units.
Verdict verify(const Unit& unit, const std::string& text, const TempDir& dir, const fs::path& unit_path = {}) {
    const fs::path folder = dir.path() / (unit.user ? "user" : "system");
    fs::create_directories(folder);
    Verdict v;
    v.file = folder / unit.installed;
    write_text(v.file, text);

    std::vector<std::string> argv{"systemd-analyze"};
    std::vector<std::string> env{"SYSTEMD_COLORS=0", "SYSTEMD_PAGER=cat", "SYSTEMD_LOG_LOCATION=0"};
    if (unit.user) {
        // `--user verify` starts a user-mode manager in-process, which wants $XDG_RUNTIME_DIR/systemd.
        // In a container or CI job without a login session it is unset ("Failed to lookup
        // RuntimeDirectory path: No such device or address"), so give it an empty private one.
        const fs::path runtime = dir.path() / "runtime";
        fs::create_directories(runtime);
        fs::permissions(runtime, fs::perms::owner_all, fs::perm_options::replace);
        env.push_back("XDG_RUNTIME_DIR=" + runtime.string());
        // The user manager also reads ~/.config/systemd/user and friends; point it at an empty
        // home so that neither the tester's own units nor an unreadable $HOME (a test run under
        // another uid) show up in the output.
        const fs::path home = dir.path() / "home";
        fs::create_directories(home);
        for (const char* variable : {"HOME", "XDG_CONFIG_HOME", "XDG_DATA_HOME", "XDG_STATE_HOME", "XDG_CACHE_HOME"})
            env.push_back(std::string(variable) + "=" + (variable == std::string("HOME") ? home : home / variable).string());
        argv.push_back("--user");
    }
    // The trailing ':' keeps the usual search path after ours.
    if (!unit_path.empty()) env.push_back("SYSTEMD_UNIT_PATH=" + unit_path.string() + ":");
    argv.push_back("verify");
    // Judge only our unit: do not load and judge its dependencies, e.g. whatever jack.service is
    // installed on the machine (with --recursive-errors=yes a warning in it fails verify).
    if (verify_supports_recursive_errors()) argv.push_back("--recursive-errors=no");
    argv.push_back(v.file.string());
    v.run = run(argv, env);

    for (const auto& line : lines_of(v.run.out)) {
        if (line.find(v.file.string()) != std::string::npos || line.find(unit.installed) != std::string::npos)
            v.blamed.push_back(line);
        else if (!about_host_jack_unit(line))
            v.other.push_back(line);
    }
    return v;
}

std::string describe(const Verdict& v) {
    return "systemd-analyze verify " + v.file.string() + " exited " + std::to_string(v.run.exit_code) + " and printed:\n" +
           v.run.out;
}

// The value of the last `Key=` line in the unit ("" when absent; systemd lets later lines win).
std::string value_of(const std::string& text, const std::string& key) {
    std::string value;
    for (const auto& line : lines_of(text))
        if (line.starts_with(key + "=")) value = line.substr(key.size() + 1);
    return value;
}

bool has_line(const std::string& text, const std::string& line) {
    for (const auto& l : lines_of(text))
        if (l == line) return true;
    return false;
}

}  // namespace

TEST_CASE("systemd-analyze is available for these tests") {
    const ProgramRun r = run({"systemd-analyze", "--version"}, {});
    REQUIRE_MESSAGE(r.exit_code == 0, "systemd-analyze is needed to check the unit files: " << r.out);
    MESSAGE("using " << lines_of(r.out).at(0));
}

TEST_CASE("systemd-analyze verify passes on both units") {
    for (const Unit* unit : {&system_unit, &user_unit}) {
        CAPTURE(unit->source);
        TempDir dir("ameoto-units");
        const Verdict v = verify(*unit, with_built_binary(unit_text(*unit)), dir);
        INFO(describe(v));
        CHECK(v.run.exit_code == 0);
        CHECK(v.blamed.empty());
        CHECK(v.other.empty());
    }
}

TEST_CASE("the verify check catches broken units") {
    // A missing executable is an error: non-zero exit code. A bad value or an unknown key is only
    // a warning, printed with the file and line; whether it changes the exit code depends on the
    // systemd version and options (252: 0 by default, 1 with --recursive-errors=...). So the check
    // insists on both a zero exit code and no line about our unit, and each breakage must fail it.
    struct Breakage {
        const char* what;
        const char* from;
        const char* to;
        bool exit_code_fails;   // the non-zero exit code catches it (otherwise only a blamed line)
    };
    const Breakage breakages[] = {
        {"a bad Type=", "\nType=notify\n", "\nType=notifyy\n", false},
        {"an unknown key in [Service]", "\nNotifyAccess=main\n", "\nNotifyAccess=main\nWatchdogSeconds=10\n", false},
        {"a bad resource limit", "\nLimitRTPRIO=95\n", "\nLimitRTPRIO=lots\n", false},
        {"a missing executable", "ExecStart=/usr/local/bin/ameotod", "ExecStart=/nonexistent/ameotod", true},
    };
    for (const Unit* unit : {&system_unit, &user_unit}) {
        for (const auto& b : breakages) {
            CAPTURE(unit->source);
            CAPTURE(b.what);
            std::string text = unit_text(*unit);
            const auto at = text.find(b.from);
            REQUIRE_MESSAGE(at != std::string::npos, "the unit no longer has " << b.from);
            text.replace(at, std::strlen(b.from), b.to);
            TempDir dir("ameoto-units");
            const Verdict v = verify(*unit, b.exit_code_fails ? text : with_built_binary(text), dir);
            INFO(describe(v));
            CHECK_FALSE(v.passed());
            if (b.exit_code_fails) CHECK(v.run.exit_code != 0);
            else CHECK_FALSE(v.blamed.empty());
        }
    }
}

TEST_CASE("a broken jack.service installed on the machine does not fail our units") {
    // A deliberately bad jack.service stand-in, found first on the unit search path. With
    // --recursive-errors=no verify never loads it; on an older systemd it does and prints its
    // warnings, which the check tolerates.
    for (const Unit* unit : {&system_unit, &user_unit}) {
        CAPTURE(unit->source);
        TempDir dir("ameoto-units");
        const fs::path stand_ins = dir.path() / "stand-ins";
        fs::create_directories(stand_ins);
        write_text(stand_ins / "jack.service", "[Unit]\nDescription=bad JACK\n[Service]\nType=bogus\nExecStart=/nonexistent/jackd\nFooBar=1\n");
        const Verdict v = verify(*unit, with_built_binary(unit_text(*unit)), dir, stand_ins);
        INFO(describe(v));
        CHECK(v.passed());
        if (!verify_supports_recursive_errors()) CHECK(v.run.out.find("jack.service:") != std::string::npos);
    }
}

TEST_CASE("the host-JACK tolerance accepts only lines about jack.service") {
    CHECK(about_host_jack_unit("/etc/systemd/system/jack.service:4: Failed to parse service type, ignoring: bogus"));
    CHECK(about_host_jack_unit("jack.service: Command /usr/bin/jackd is not executable: No such file or directory"));
    CHECK_FALSE(about_host_jack_unit("/tmp/x/ameotod.service:12: Unknown key 'X' in section [Service], ignoring."));
    CHECK_FALSE(about_host_jack_unit("ameotod.service: Failed to add dependency on jack.service: Invalid argument"));
    CHECK_FALSE(about_host_jack_unit("/etc/systemd/system/myjack.service:4: Unknown key"));
    CHECK_FALSE(about_host_jack_unit("Failed to initialize manager: No such device or address"));
}

TEST_CASE("both units carry the settings the service relies on") {
    for (const Unit* unit : {&system_unit, &user_unit}) {
        CAPTURE(unit->source);
        const std::string t = unit_text(*unit);
        CHECK(value_of(t, "Type") == "notify");            // READY=1 from ameotod itself
        CHECK(value_of(t, "NotifyAccess") == "main");
        CHECK(value_of(t, "ExecStart").starts_with(installed_binary + " "));
        CHECK(value_of(t, "Restart") == "on-failure");
        CHECK(value_of(t, "RestartPreventExitStatus") == "2");   // ameotod's exit status for a bad command line
        CHECK_FALSE(value_of(t, "RestartSec").empty());
        CHECK(value_of(t, "WatchdogSec") == "10s");        // docs/systemd.md explains this value
        CHECK(value_of(t, "LimitRTPRIO") == "95");
        CHECK(value_of(t, "LimitMEMLOCK") == "infinity");
        CHECK(has_line(t, "Wants=jack.service"));
        CHECK(has_line(t, "After=jack.service"));
        CHECK(value_of(t, "StateDirectory") == "ameoto");
        CHECK(value_of(t, "NoNewPrivileges") == "yes");
        // Hardening that would break real-time audio must stay out.
        CHECK(value_of(t, "RestrictRealtime").empty());
        CHECK(value_of(t, "PrivateDevices") != "yes");
        CHECK(value_of(t, "PrivateIPC").empty());           // JACK shares memory with its clients
    }
    const std::string s = unit_text(system_unit);
    CHECK(value_of(s, "User") == "ameoto");
    CHECK(value_of(s, "Group") == "audio");
    CHECK(value_of(s, "WorkingDirectory") == "/var/lib/ameoto");
    CHECK(value_of(s, "ProtectSystem") == "strict");
    CHECK(value_of(s, "ProtectHome") == "yes");
    CHECK(value_of(s, "PrivateTmp") == "yes");            // /dev/shm, JACK's, is not affected
    CHECK(value_of(s, "WantedBy") == "multi-user.target");
    const std::string u = unit_text(user_unit);
    CHECK(value_of(u, "User").empty());                    // a user manager cannot switch users
    CHECK(value_of(u, "WantedBy") == "default.target");
}
