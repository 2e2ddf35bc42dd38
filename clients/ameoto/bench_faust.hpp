// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The Faust peer of `ameoto bench engine`: Faust's own mass-interaction library (mi.lib) running the
// mi-faust triangleMesh.dsp example, compiled here from the Debian faust packages, timed the same way.
//
// Interface:
//   FaustPeer peer = FaustPeer::prepare();     // finds faust and the .dsp, generates C++, compiles it
//   if (!peer.ready()) say(peer.problem());   // e.g. "faust not installed: install it with ..."
//   std::optional<BenchTiming> t = peer.time(budget_s, runs, error);   // ns per sample (bench_timer)
//   std::optional<std::vector<double>> y = peer.dump(samples, error);   // the first output samples
//   peer.dsp_path(), peer.faust_version(), peer.compile_command()
//   std::string arch = faust_architecture();  // the driver faust wraps around the generated class
//
// Steps (all in a fresh directory under $TMPDIR, removed afterwards; nothing generated is kept):
//   faust -double -cn TriangleMesh -a driver.cpp triangleMesh.dsp -o mesh.cpp
//   <ameoto's C++ compiler> <ameoto's build flags> -std=c++17 mesh.cpp -o mesh
// The driver is faust_architecture(): minimal Meta, UI (records each widget's zone by label) and
// dsp classes, then a main that sets the "Pluck Position" slider per block of 64 samples (+1, and
// -1 every pluck_period samples, as bench_drive.hpp's PluckDrive) and runs compute() at 48 kHz:
//   mesh time BUDGET_S RUNS   -> "run_ns_per_sample X" per run, "samples_per_run N", "checksum S"
//   mesh dump SAMPLES         -> one output sample per line (%.17g)
// timed with the same clock and the same warm-up and run scheme as bench_timer.hpp. FAUSTFLOAT is
// double, so inputs, sliders and outputs are double, like ameoto's.
// The .dsp is found with `dpkg -L faust-common` or at the packages' known paths.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clients/ameoto/bench_timer.hpp"

namespace ameoto::client {

std::string faust_architecture();
std::optional<std::string> find_triangle_mesh_dsp();
std::optional<std::string> find_on_path(const std::string& program);

class FaustPeer {
public:
    static FaustPeer prepare();
    bool ready() const { return ready_; }
    const std::string& problem() const { return problem_; }
    const std::string& dsp_path() const { return dsp_; }
    const std::string& faust_version() const { return version_; }
    const std::string& compile_command() const { return compile_; }

    std::optional<BenchTiming> time(double budget_s, int runs, std::string& error) const;
    std::optional<std::vector<double>> dump(long samples, std::string& error) const;

    FaustPeer(FaustPeer&&) noexcept;
    FaustPeer& operator=(FaustPeer&&) noexcept;
    ~FaustPeer();

private:
    FaustPeer();
    struct TempDir;
    std::unique_ptr<TempDir> dir_;
    bool ready_ = false;
    std::string problem_, dsp_, version_, compile_, program_;
};

}  // namespace ameoto::client
