#pragma once
// The one place audio is made: every backend (JACK, null, offline render) calls Renderer::process.
//
// Interface:
//   Renderer r(RendererConfig{...});          // builds the scene; allocates everything it will use
//   r.schedule(command);                      // audio thread: queue a command (applied at its sample)
//   r.process(frames, outputs);               // audio thread: render `frames` samples into outputs[ch]
//   r.poll_event(event)                       // audio thread: events produced (synced, busy)
//   r.stats()                                 // counters for /status
//   r.frame()                                 // sample clock: frames rendered so far
//
// Real-time contract (Mutable Instruments style: the constructor allocates, process never does):
// schedule, process and poll_event never allocate, free, lock, block or log. Commands carry a sample
// time; a command whose time has come (or that is untimed) is applied at the start of the sample it is
// due, so an untimed command sent between two blocks sounds in the first sample of the next block.
// The output depends only on the seed and on the commands with their sample times, never on the block
// size: the rain is drawn per sample, so JACK at 256 frames and an offline render at 4096 frames
// produce the same samples.
//
// Material changes: swap_canopy installs a canopy built off the audio thread (by pointer); the old one
// keeps ringing for 0.5 s with no new impacts, summed into the output, then goes back to the control
// thread in a `retired` event to be freed there. Nothing is allocated or freed here.
//
// Sound: each canopy panel is heard as a baffled piston at the listener (Rayleigh integral, far-field
// approximation): p = rho0 / (2 pi r) * (sum of the panel's normal accelerations times their areas)
// = rho0 / (2 pi r) * F_net / s, with F_net the panel's net force (models/canopy.hpp) and s its areal
// density. Panels are panned by azimuth. Output full scale (1.0) is `full_scale_pa` pascals.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/random.hpp"
#include "engine/models/canopy.hpp"
#include "engine/models/impact_force.hpp"
#include "engine/render/command.hpp"
#include "engine/scene/rain_spawner.hpp"

namespace ameoto {

struct RendererConfig {
    double sample_rate = 48000.0;         // Hz
    int channels = 2;
    std::uint64_t seed = 0;
    double rain_rate_mm_per_h = 2.0;      // the default scene: light rain
    CanopyGeometry canopy{};
    MembraneMaterial material = MembraneMaterial::nylon_canopy();
    double listener_below_m = 0.3;        // listener on the shaft, this far below the canopy
    double full_scale_pa = 40.0;          // pressure at output 1.0 (126 dB SPL)
};

struct RendererStats {
    std::uint64_t drops = 0;              // impacts started (rain and /drop)
    std::uint64_t impacts_dropped = 0;    // impacts lost because the pulse pool was full
    std::uint64_t late_commands = 0;      // timed commands that arrived after their sample
    std::uint64_t busy_commands = 0;      // commands refused because the pending list was full
    std::uint64_t body_resets = 0;        // panels reset by the runtime guard (non-finite or runaway)
    int active_impacts = 0;
    double rain_rate_mm_per_h = 0.0;      // current (ramping) rate
};

class Renderer {
public:
    static constexpr int max_channels = 16;
    static constexpr int pending_capacity = 1024;
    static constexpr int event_capacity = 1024;

    explicit Renderer(const RendererConfig& config);

    void schedule(const Command& command);
    void process(int frames, float* const* outputs);
    bool poll_event(RendererEvent& event);

    std::uint64_t frame() const { return frame_; }
    const RendererStats& stats() const { return stats_; }
    const RendererConfig& config() const { return config_; }
    const Canopy& canopy() const { return *canopy_; }   // audio thread (or before audio starts) only
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

private:
    void apply(const Command& command);
    void start_impact(double diameter_m, double speed_m_per_s, double x, double y);
    void push_event(const RendererEvent& event);
    void render_sample(float* const* outputs, int offset);
    void swap_canopy(const Command& command);
    bool push_event_checked(const RendererEvent& event);

    RendererConfig config_;
    double dt_;
    Random rng_;
    // The canopy in use, and the one it replaced, ringing out for fade_samples after a material change
    // so the change makes no click; both owned (raw pointers: ownership crosses threads by value).
    Canopy* canopy_ = nullptr;
    Canopy* fading_ = nullptr;
    int fade_left_ = 0;
    double liquid_density_;
    std::vector<double> fading_force_;
    RainSpawner rain_;
    ImpactPool impacts_;
    std::uint64_t frame_ = 0;
    RendererStats stats_;

    // Per panel: pressure per newton of net force, then split over the channels.
    std::vector<double> panel_force_;                 // sized in the constructor
    std::vector<std::array<double, max_channels>> panel_gain_;

    // Commands waiting for their sample, sorted by frame (stable for equal frames).
    std::array<Command, pending_capacity> pending_{};
    int pending_count_ = 0;
    std::array<RendererEvent, event_capacity> events_{};
    int event_read_ = 0, event_count_ = 0;
};

// Pans a source at azimuth (rad, 0 = front, counter-clockwise towards the left) over `channels`
// outputs with constant power: mono gets 1; stereo is left/right by sin(azimuth); three or more
// channels are a ring of speakers from front-left, clockwise, panned pairwise.
std::array<double, Renderer::max_channels> pan_gains(double azimuth, int channels);

}  // namespace ameoto
