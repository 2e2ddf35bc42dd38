// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Shared by the bench tests: render a benchmark method on Faust's triangle mesh, and find a method by name.
//
// Interface:
//   std::vector<double> y = render(method_named("network explicit Verlet"), 4800);   // the .dsp's pluck

#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "clients/ameoto/bench_engine.hpp"
#include "clients/ameoto/bench_mesh.hpp"
#include "clients/ameoto/bench_methods.hpp"

namespace ameoto::client::test {

inline std::vector<double> render(const BenchMethod& method, long samples) {
    auto body = method.build(mi_triangle_mesh());
    std::vector<double> y(static_cast<std::size_t>(samples));
    PluckDrive drive;
    body->pluck(samples, drive, y.data());
    return y;
}

inline const BenchMethod& method_named(const std::string& name) {
    for (const auto& m : bench_methods())
        if (m.name() == name) return m;
    FAIL("no method " << name);
    return bench_methods().front();
}

}  // namespace ameoto::client::test
