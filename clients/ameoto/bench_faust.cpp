// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_faust.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "clients/ameoto/bench_drive.hpp"

// AMEOTO_CXX_COMPILER and AMEOTO_CXX_FLAGS come from clients/ameoto/CMakeLists.txt: the compiler and
// flags ameoto itself was built with, so the Faust peer is compiled the same way.

namespace ameoto::client {
namespace {

constexpr const char* install_hint = "install it with scripts/install-bench-deps to compare";

std::string shell_quoted(const std::string& word) {
    std::string out = "'";
    for (const char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// Runs `command` through the shell; its stdout and stderr go to `output`. Returns the exit status
// (-1 when it could not run or did not exit normally).
int run_command(const std::string& command, std::string& output) {
    output.clear();
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return -1;
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
    const int status = pclose(pipe);
    return status >= 0 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

std::string last_lines(const std::string& text, std::size_t count) {
    std::vector<std::string> lines;
    std::stringstream in(text);
    std::string line;
    while (std::getline(in, line)) lines.push_back(line);
    std::string out;
    for (std::size_t i = lines.size() > count ? lines.size() - count : 0; i < lines.size(); ++i) out += lines[i] + "\n";
    return out;
}

}  // namespace

std::string faust_architecture() {
    // Placeholders <<includeIntrinsic>> and <<includeclass>> are where faust puts its code.
    return std::string(R"ARCH(// Driver for ameoto bench (clients/ameoto/bench_faust.cpp), wrapped around Faust's class.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <utility>
#include <vector>
#define FAUSTFLOAT double
struct Meta {
    void declare(const char*, const char*) {}
};
struct UI {
    std::vector<std::pair<std::string, double*>> zones;
    void openTabBox(const char*) {}
    void openHorizontalBox(const char*) {}
    void openVerticalBox(const char*) {}
    void closeBox() {}
    void addButton(const char* l, double* z) { zones.push_back({l, z}); }
    void addCheckButton(const char* l, double* z) { zones.push_back({l, z}); }
    void addVerticalSlider(const char* l, double* z, double, double, double, double) { zones.push_back({l, z}); }
    void addHorizontalSlider(const char* l, double* z, double, double, double, double) { zones.push_back({l, z}); }
    void addNumEntry(const char* l, double* z, double, double, double, double) { zones.push_back({l, z}); }
    void addHorizontalBargraph(const char*, double*, double, double) {}
    void addVerticalBargraph(const char*, double*, double, double) {}
    void addSoundfile(const char*, const char*, void*) {}
    void declare(double*, const char*, const char*) {}
    double* zone(const char* label) {
        for (auto& z : zones)
            if (z.first == label) return z.second;
        return nullptr;
    }
};
struct dsp {
    virtual ~dsp() {}
};
<<includeIntrinsic>>
<<includeclass>>
static double cpu_seconds() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}
int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "";
    static TriangleMesh mesh;
    mesh.init(48000);
    UI ui;
    mesh.buildUserInterface(&ui);
    double* slider = ui.zone("Pluck Position");
    if (!slider) {
        std::fprintf(stderr, "no \"Pluck Position\" slider\n");
        return 2;
    }
    const long block = 64, period = )ARCH") +
           std::to_string(pluck_period) + R"ARCH(;
    double out[block];
    double* outs[1] = {out};
    long clock = 0;
    double checksum = 0.0;
    auto render = [&](long samples, std::vector<double>* dump) {
        for (long done = 0; done < samples; done += block) {
            *slider = (clock / period) % 2 == 0 ? 1.0 : -1.0;
            mesh.compute(block, nullptr, outs);
            for (long k = 0; k < block; ++k) checksum += out[k];
            if (dump) dump->insert(dump->end(), out, out + block);
            clock += block;
        }
    };
    if (mode == "dump" && argc == 3) {
        const long samples = std::atol(argv[2]);
        std::vector<double> y;
        render((samples + block - 1) / block * block, &y);
        for (long n = 0; n < samples; ++n) std::printf("%.17g\n", y[n]);
        return 0;
    }
    if (mode == "time" && argc == 4) {
        // As ameoto's bench_timer.cpp: warm up for a tenth of the budget, then RUNS equal runs.
        const double budget = std::atof(argv[2]);
        const int runs = std::max(1, std::atoi(argv[3]));
        long warm = 0;
        double warm_time = 0.0;
        for (long chunk = 64; warm < 256 || warm_time < 0.1 * budget; chunk *= 2) {
            const double start = cpu_seconds();
            render(chunk, nullptr);
            warm_time += cpu_seconds() - start;
            warm += chunk;
        }
        const double per_sample = warm_time / warm;
        long samples = static_cast<long>(0.9 * budget / runs / std::max(per_sample, 1e-12));
        samples = std::max(block, samples / block * block);
        for (int r = 0; r < runs; ++r) {
            const double start = cpu_seconds();
            render(samples, nullptr);
            std::printf("run_ns_per_sample %.6g\n", 1e9 * (cpu_seconds() - start) / samples);
        }
        std::printf("samples_per_run %ld\nchecksum %.17g\n", samples, checksum);
        return 0;
    }
    std::fprintf(stderr, "usage: %s time BUDGET_S RUNS | dump SAMPLES\n", argv[0]);
    return 2;
}
)ARCH";
}

std::optional<std::string> find_on_path(const std::string& program) {
    const char* path = std::getenv("PATH");
    if (!path) return std::nullopt;
    std::stringstream dirs(path);
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
        const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + program;   // "" is "."
        if (access(candidate.c_str(), X_OK) == 0 && !std::filesystem::is_directory(candidate)) return candidate;
    }
    return std::nullopt;
}

std::optional<std::string> find_triangle_mesh_dsp() {
    const std::string tail = "/mi-faust/12_TriangleMesh/triangleMesh.dsp";
    std::string listing;
    if (find_on_path("dpkg") && run_command("dpkg -L faust-common", listing) == 0) {
        std::stringstream lines(listing);
        std::string line;
        while (std::getline(lines, line))
            if (line.size() >= tail.size() && line.compare(line.size() - tail.size(), tail.size(), tail) == 0 &&
                std::filesystem::is_regular_file(line))
                return line;
    }
    for (const char* dir : {"/usr/share/faust/examples/physicalModeling", "/usr/local/share/faust/examples/physicalModeling",
                            "/usr/share/doc/faust-common/examples/physicalModeling"}) {
        const std::string candidate = dir + tail;
        if (std::filesystem::is_regular_file(candidate)) return candidate;
    }
    return std::nullopt;
}

struct FaustPeer::TempDir {
    std::filesystem::path path;
    ~TempDir() {
        std::error_code ignored;
        if (!path.empty()) std::filesystem::remove_all(path, ignored);
    }
};

FaustPeer::FaustPeer() = default;
FaustPeer::FaustPeer(FaustPeer&&) noexcept = default;
FaustPeer& FaustPeer::operator=(FaustPeer&&) noexcept = default;
FaustPeer::~FaustPeer() = default;

FaustPeer FaustPeer::prepare() {
    FaustPeer peer;
    const auto faust = find_on_path("faust");
    if (!faust) {
        peer.problem_ = std::string("faust not installed: ") + install_hint;
        return peer;
    }
    std::string output;
    if (run_command(shell_quoted(*faust) + " --version", output) == 0) peer.version_ = first_line(output);
    const auto dsp = find_triangle_mesh_dsp();
    if (!dsp) {
        peer.problem_ = std::string("faust's example mi-faust/12_TriangleMesh/triangleMesh.dsp not found (package faust-common): ") +
                        install_hint;
        return peer;
    }
    peer.dsp_ = *dsp;

    std::error_code ec;
    std::string pattern = (std::filesystem::temp_directory_path(ec) / "ameoto-bench-XXXXXX").string();
    if (ec || !mkdtemp(pattern.data())) {
        peer.problem_ = "cannot create a temporary directory for the Faust program";
        return peer;
    }
    peer.dir_ = std::make_unique<TempDir>();
    peer.dir_->path = pattern;
    const std::filesystem::path arch = peer.dir_->path / "driver.cpp", generated = peer.dir_->path / "mesh.cpp";
    const std::filesystem::path program = peer.dir_->path / "mesh";
    std::ofstream(arch) << faust_architecture();

    const std::string generate = shell_quoted(*faust) + " -double -cn TriangleMesh -a " + shell_quoted(arch.string()) + " " +
                                 shell_quoted(peer.dsp_) + " -o " + shell_quoted(generated.string());
    if (run_command(generate, output) != 0) {
        peer.problem_ = "faust could not compile " + peer.dsp_ + ":\n" + last_lines(output, 8);
        return peer;
    }
    peer.compile_ = std::string(AMEOTO_CXX_COMPILER) + " " + AMEOTO_CXX_FLAGS + " -std=c++17";
    if (run_command(peer.compile_ + " " + shell_quoted(generated.string()) + " -o " + shell_quoted(program.string()), output) != 0) {
        peer.problem_ = "the C++ compiler could not build Faust's program (" + peer.compile_ + "):\n" + last_lines(output, 8);
        return peer;
    }
    peer.program_ = program.string();
    peer.ready_ = true;
    return peer;
}

std::optional<BenchTiming> FaustPeer::time(double budget_s, int runs, std::string& error) const {
    std::string output;
    char budget[64];
    std::snprintf(budget, sizeof budget, "%.6g", budget_s);
    if (run_command(shell_quoted(program_) + " time " + budget + " " + std::to_string(runs), output) != 0) {
        error = "Faust's program failed: " + last_lines(output, 4);
        return std::nullopt;
    }
    std::vector<double> ns;
    BenchTiming t;
    std::stringstream lines(output);
    std::string key;
    while (lines >> key) {
        if (key == "run_ns_per_sample") {
            double v = 0.0;
            lines >> v;
            ns.push_back(v);
        } else if (key == "samples_per_run") {
            lines >> t.samples_per_run;
        } else {
            std::string rest;
            std::getline(lines, rest);
        }
    }
    if (ns.empty()) {
        error = "Faust's program printed no timing: " + last_lines(output, 4);
        return std::nullopt;
    }
    t.runs = static_cast<int>(ns.size());
    t.median_ns = median(ns);
    t.min_ns = *std::min_element(ns.begin(), ns.end());
    t.max_ns = *std::max_element(ns.begin(), ns.end());
    return t;
}

std::optional<std::vector<double>> FaustPeer::dump(long samples, std::string& error) const {
    std::string output;
    if (run_command(shell_quoted(program_) + " dump " + std::to_string(samples), output) != 0) {
        error = "Faust's program failed: " + last_lines(output, 4);
        return std::nullopt;
    }
    std::vector<double> y;
    std::stringstream lines(output);
    double v = 0.0;
    while (lines >> v) y.push_back(v);
    if (static_cast<long>(y.size()) != samples) {
        error = "Faust's program printed " + std::to_string(y.size()) + " samples, not " + std::to_string(samples);
        return std::nullopt;
    }
    return y;
}

}  // namespace ameoto::client
