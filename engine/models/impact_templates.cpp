// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/models/impact_templates.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <ctime>
#include <exception>
#include <future>
#include <optional>
#include <thread>

#include "engine/core/nearest_in_log.hpp"
#include "engine/models/drop.hpp"

namespace ameoto {

int ImpactTemplateTable::nearest(double diameter_m) const {
    return nearest_in_log(diameters_m.data(), static_cast<int>(diameters_m.size()), diameter_m);
}

double ImpactTemplateTable::worst_cpu_s(int frames, int k) const {
    if (cpu_chunks <= 0 || frames <= 0 || k < 0 || k >= static_cast<int>(diameters_m.size())) return 0.0;
    const int window = std::min(cpu_chunks, (frames + cpu_chunk - 1) / cpu_chunk);
    const double* cum = cpu_s.data() + static_cast<std::size_t>(k) * static_cast<std::size_t>(cpu_chunks + 1);
    double worst = 0.0;
    for (int c = 0; c + window <= cpu_chunks; ++c) worst = std::max(worst, cum[c + window] - cum[c]);
    return worst;
}

double ImpactTemplateTable::worst_cpu_s(int frames) const {
    double worst = 0.0;
    for (int k = 0; k < static_cast<int>(diameters_m.size()); ++k) worst = std::max(worst, worst_cpu_s(frames, k));
    return worst;
}

namespace {

double thread_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// One grid size: a fresh scene, one drop, `length` samples of the force the membrane takes, into
// `forces` (length values). Returns the samples up to the last non-zero force. Touches nothing shared
// but the process's lattice cache (drop.cpp, locked) and, read only, the prototype canopy, so sizes can
// be recorded on several threads. prototype null: the scene builds its own canopy (CanopyBuild::per_size).
// cpu: the run's thread CPU time, cumulative at every cpu_chunk samples from the drop's spawn (chunks + 1
// values).
int record_one(const DropOnCanopyConfig& c, const Canopy* prototype, double diameter_m, int length, double* forces, double* cpu) {
    const double x = 0.5 * c.geometry.radius_m * std::cos(0.0), y = 0.0;
    DropOnCanopy run = prototype ? DropOnCanopy(c, *prototype) : DropOnCanopy(c);
    const double start = thread_cpu_seconds();
    run.drop(diameter_m, 0.0, x, y);
    const Vec3 n = run.canopy().surface_normal(x, y);
    float frame[1];
    cpu[0] = 0.0;
    for (int i = 0; i < length; ++i) {
        run.process_frame(frame);
        if ((i + 1) % ImpactTemplateTable::cpu_chunk == 0) cpu[(i + 1) / ImpactTemplateTable::cpu_chunk] = thread_cpu_seconds() - start;
        // The membrane takes the opposite of what the drop masses took.
        forces[i] = -dot(run.contact_force(), n);
    }
    int used = length;
    while (used > 1 && forces[used - 1] == 0.0) --used;
    return used;
}

}  // namespace

namespace {

// Both public forms: `given` is the caller's canopy (the scene's own), else one is built here for
// CanopyBuild::shared, or none for per_size.
ImpactTemplateTable record(const DropOnCanopyConfig& scene, const Canopy* given, const TemplateGrid& grid, int threads,
                           CanopyBuild build) {
    ImpactTemplateTable t;
    t.sample_rate = scene.sample_rate;
    t.density = scene.liquid.density;
    for (double d = grid.min_diameter_m; d <= grid.max_diameter_m * (1.0 + 1e-9); d *= grid.step_ratio) t.diameters_m.push_back(d);
    t.length = static_cast<int>(std::ceil(grid.seconds * scene.sample_rate));
    t.forces.assign(t.diameters_m.size() * static_cast<std::size_t>(t.length), 0.0);
    t.used.assign(t.diameters_m.size(), 0);
    t.cpu_chunks = t.length / ImpactTemplateTable::cpu_chunk;
    t.cpu_s.assign(t.diameters_m.size() * static_cast<std::size_t>(t.cpu_chunks + 1), 0.0);
    for (const double d : t.diameters_m) t.speeds_m_per_s.push_back(arrival_speed(d, scene.liquid.density));

    DropOnCanopyConfig c = scene;
    c.output = SceneOutput::mass_pickup;   // the sound is not needed, only the contact force
    c.channels = 1;
    c.listener = ListenerStyle::panned;    // mono (whatever the scene's listener)
    c.capacity = 1;
    c.max_diameter = grid.max_diameter_m * (1.0 + 1e-9);
    c.gap_m = 0.0;                         // striking in the first sample, as the server's /drop

    // The sizes are independent runs, each writing only its own row: the table is the same whatever
    // the number of threads or the order they finish in (tested). Sizes are handed out one at a time
    // (an atomic counter): the large drops, with more masses, cost the most.
    const int sizes = static_cast<int>(t.diameters_m.size());
    if (threads <= 0) threads = static_cast<int>(std::max(1u, std::min(std::thread::hardware_concurrency(), 4u)));
    threads = std::max(1, std::min(threads, sizes));
    // Every size's scene starts from the same canopy at rest: built once here (on this thread, before
    // the helpers start; they only copy it) instead of once per size, where it was ~85 % of the
    // recording's cost (docs/reliability.md, "Start-up cost"). A copy of a canopy never stepped is the
    // canopy its constructor builds, so the table is the same bit for bit (tested against per_size).
    std::optional<Canopy> prototype;
    if (!given && build == CanopyBuild::shared && sizes > 0) prototype.emplace(DropOnCanopy::fresh_canopy(c));
    const Canopy* shared = given ? given : prototype ? &*prototype : nullptr;
    std::atomic<int> next{0};
    auto work = [&] {
        for (int k = next++; k < sizes; k = next++)
            // data() + offset, not &forces[offset]: with a refused configuration the length can be 0 and
            // the table empty, and indexing an empty vector is undefined (UBSan caught it).
            t.used[static_cast<std::size_t>(k)] = record_one(c, shared, t.diameters_m[static_cast<std::size_t>(k)], t.length,
                                                             t.forces.data() + static_cast<std::size_t>(k) * static_cast<std::size_t>(t.length),
                                                             t.cpu_s.data() + static_cast<std::size_t>(k) * static_cast<std::size_t>(t.cpu_chunks + 1));
    };
    std::vector<std::future<void>> helpers;
    for (int i = 1; i < threads; ++i) helpers.push_back(std::async(std::launch::async, work));
    std::exception_ptr failure;
    try {
        work();
    } catch (...) {
        failure = std::current_exception();
        next = sizes;   // the helpers stop after their current size
    }
    for (auto& h : helpers) {
        try {
            h.get();
        } catch (...) {
            if (!failure) failure = std::current_exception();
            next = sizes;
        }
    }
    if (failure) std::rethrow_exception(failure);
    return t;
}

}  // namespace

ImpactTemplateTable record_impact_templates(const DropOnCanopyConfig& scene, const TemplateGrid& grid, int threads,
                                            CanopyBuild build) {
    return record(scene, nullptr, grid, threads, build);
}

ImpactTemplateTable record_impact_templates(const DropOnCanopyConfig& scene, const Canopy& prototype, const TemplateGrid& grid,
                                            int threads) {
    return record(scene, &prototype, grid, threads, CanopyBuild::shared);
}

bool TemplatePool::add(CanopyHit target, const ImpactTemplateTable& table, double diameter_m, double speed_m_per_s,
                       double density) {
    if (count_ == capacity || table.empty() || target.panel < 0) return false;
    const int k = table.nearest(diameter_m);
    const double d_k = table.diameters_m[static_cast<std::size_t>(k)];
    const double v_k = table.speeds_m_per_s[static_cast<std::size_t>(k)];
    const double speed = speed_m_per_s > 0.0 ? speed_m_per_s : arrival_speed(diameter_m, density);
    const double dr = diameter_m / d_k, vr = speed / v_k;
    Playing& p = playing_[static_cast<std::size_t>(count_++)];
    p.target = target;
    p.index = k;
    p.position = 0.0;
    p.rate = vr / dr;                                   // duration ~ D / V
    p.gain = (density / table.density) * vr * vr * dr * dr;   // force ~ rho V^2 D^2
    return true;
}

}  // namespace ameoto
