// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/realtime/block_trace.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace ameoto {

const char* BlockTraceFile::columns() {
    return "time_s callback frame frames gap_us wall_us cpu_us wall_pct cpu_pct cause minflt majflt vcsw ivcsw "
           "commands spawned awake link_breaks full template texture priced_out detail scene_changed";
}

BlockTraceFile::BlockTraceFile(const std::string& path, double sample_rate, double threshold)
    : sample_rate_(sample_rate), threshold_(threshold) {
    file_ = std::fopen(path.c_str(), "w");
    if (!file_) throw std::runtime_error("cannot write the block trace " + path + ": " + std::strerror(errno));
    std::fprintf(file_, "# ameotod block trace 1: callbacks over %.0f %% of their period, wall or thread CPU time\n",
                 100.0 * threshold_);
    std::fprintf(file_, "# cause: ours = the CPU time passed the threshold; machine = only the wall time did; "
                        "late = started over 1 + threshold periods after the last start (gap_us), that block on time\n");
    std::fprintf(file_, "%s\n", columns());
    std::fflush(file_);
}

BlockTraceFile::~BlockTraceFile() { close(0); }

bool BlockTraceFile::add(const BlockRecord& r) {
    if (!file_) return false;
    if (first_start_ns_ < 0) first_start_ns_ = r.start_ns;
    ++blocks_;
    const double period_ns = 1e9 * r.frames / sample_rate_;
    const double wall = static_cast<double>(r.wall_ns) / period_ns;
    const double cpu = static_cast<double>(r.cpu_ns) / period_ns;
    cpu_sum_ += cpu;
    wall_max_ = std::max(wall_max_, wall);
    cpu_max_ = std::max(cpu_max_, cpu);
    minor_faults_ += r.minor_faults;
    major_faults_ += r.major_faults;
    involuntary_ += r.involuntary_switches;
    // The start-to-start gap from the callback before (0 for the first, or after a lost record).
    const bool follows = previous_start_ns_ >= 0 && r.callback == previous_callback_ + 1;
    const double gap_ns = follows ? static_cast<double>(r.start_ns - previous_start_ns_) : 0.0;
    const bool late = follows && previous_wall_ <= 1.0 && gap_ns > (1.0 + threshold_) * period_ns;
    previous_start_ns_ = r.start_ns;
    previous_callback_ = r.callback;
    previous_wall_ = wall;
    const bool slow = wall > threshold_ || cpu > threshold_;
    if (!slow && !late) return false;
    const bool ours = cpu > threshold_;
    const char* cause = ours ? "ours" : slow ? "machine" : "late";
    ++(ours ? slow_ours_ : slow ? slow_machine_ : late_);
    const BlockActivity& a = r.activity;
    std::fprintf(file_, "%.6f %llu %llu %d %.1f %.1f %.1f %.1f %.1f %s %ld %ld %ld %ld %d %d %d %ld %d %d %d %d %.3f %d\n",
                 static_cast<double>(r.start_ns - first_start_ns_) * 1e-9, static_cast<unsigned long long>(r.callback),
                 static_cast<unsigned long long>(r.frame), r.frames, gap_ns * 1e-3, static_cast<double>(r.wall_ns) * 1e-3,
                 static_cast<double>(r.cpu_ns) * 1e-3, 100.0 * wall, 100.0 * cpu, cause,
                 r.minor_faults, r.major_faults, r.voluntary_switches, r.involuntary_switches, a.commands,
                 a.lattice_spawned, a.lattice_awake, a.link_breaks, a.full_rain, a.template_impacts, a.texture_grains,
                 a.priced_out, a.detail, a.scene_changed ? 1 : 0);
    return true;
}

void BlockTraceFile::flush() {
    if (file_) std::fflush(file_);
}

void BlockTraceFile::close(std::uint64_t lost) {
    if (!file_) return;
    std::fprintf(file_,
                 "# blocks %llu slow %llu ours %llu machine %llu late %llu lost %llu mean_cpu_pct %.1f max_wall_pct %.1f "
                 "max_cpu_pct %.1f minflt %ld majflt %ld ivcsw %ld\n",
                 static_cast<unsigned long long>(blocks_), static_cast<unsigned long long>(slow_ours_ + slow_machine_),
                 static_cast<unsigned long long>(slow_ours_), static_cast<unsigned long long>(slow_machine_),
                 static_cast<unsigned long long>(late_), static_cast<unsigned long long>(lost), blocks_ ? 100.0 * cpu_sum_ / static_cast<double>(blocks_) : 0.0,
                 100.0 * wall_max_, 100.0 * cpu_max_, minor_faults_, major_faults_, involuntary_);
    std::fclose(file_);
    file_ = nullptr;
}

}  // namespace ameoto
