// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The one place audio is made: every backend (JACK, null, offline render) calls Renderer::process.
//
// Interface:
//   Renderer r(RendererConfig{...});          // builds the scene; allocates everything it will use
//   r.schedule(command);                      // audio thread: queue a command (applied at its sample)
//   r.process(frames, outputs);               // audio thread: render `frames` samples into outputs[ch]
//   r.poll_event(event)                       // audio thread: events produced (synced, busy, swapped, retired)
//   r.stats()                                 // counters for /status
//   r.last_block()                            // what the last process() did (ameotod's --block-trace)
//   r.frame()                                 // sample clock: frames rendered so far
//   Renderer::make_scene(config)              // off the audio thread: an UmbrellaScene for swap_surface/
//                                             // swap_liquid (umbrella_scene.hpp)
//   auto parts = Renderer::make_parts(config);   // off the audio thread: the umbrella's parts, for more
//   Renderer r(config, parts.get());          // than one renderer or scene of the same umbrella (--level
//                                             // auto's measurement, then the stream: level_choice.hpp)
//
// Real-time contract (Mutable Instruments style: the constructor allocates, process never does):
// schedule, process and poll_event never allocate, free, lock, block or log. Commands carry a sample
// time; a command whose time has come (or that is untimed) is applied at the start of the sample it is
// due, so an untimed command sent between two blocks acts in the first sample of the next block.
// The output depends only on the seed and on the commands with their sample times, never on the block
// size: the rain is drawn per sample, so JACK at 256 frames and an offline render at 4096 frames
// produce the same samples.
//
// The scene (models/drop_on_canopy.hpp): the umbrella canopy, its far-field sound at the listener and
// a pool of lattice drops, the seed's full model. Two levels of detail reach it:
//   - /drop (CommandKind::drop): a lattice drop that falls onto the membrane, collides with its masses,
//     may break up and strike again (full model). It is placed touching the cap at its sample, so it
//     strikes within a sample or two. When the pool is full (capacity `full_drops`) the drop falls back
//     to the template below, counted in stats().drop_fallbacks: a drop is never lost.
//   - rain (/rain/rate): Marshall-Palmer sizes, Poisson arrivals; each drop's level of detail is chosen
//     by the governor (lod_governor.hpp) from its loudness at the listener, the masking by the drop rate
//     and the measured load: full (a lattice drop, as /drop), template (the contact force a lattice drop
//     of its size put on the membrane, recorded from the full model when the scene was built, replayed
//     into the nearest node: models/impact_templates.hpp), or texture (a noise grain of that template's
//     energy and colour, panned by the drop's azimuth: models/texture_grains.hpp).
// The governor sheds detail when the load measured by the caller (set_measured_load, the audio bridge's
// callback time over the block period) passes the budget (/lod), only when RendererConfig::adaptive_lod
// is set (live playback); offline renders leave it unset and stay reproducible to the sample. Live, it
// also prices a lattice drop before admitting one, starting from what the scene's template recording of
// its size cost this machine in a block of the length process() is given (lod_governor.hpp, "The prior").
// Either way the sound is the membrane's, radiated to the listener (Rayleigh far field), so the first
// sound of an impact reaches the output latency_samples() later (the nearest node's distance over c:
// 42 samples at 48 kHz for the default listener 0.3 m under the shaft).
//
// Material and liquid changes: swap_surface / swap_liquid install a whole scene built off the audio
// thread (make_scene; by pointer). The old scene keeps ringing for 0.5 s with no new impacts (its
// drops in flight finish their fall into it), summed into the output so the change makes no click,
// then goes back to the control thread in a `retired` event to be freed there. Nothing is allocated
// or freed here.
//
// Ambisonics (listener = ListenerStyle::ambix, 4, 9 or 16 channels: orders 1 to 3, ACN/SN3D): two buses,
// summed before the head's rotation. The body bus: the umbrella's panels by their centres' directions
// from the head and the texture grains over a virtual ring of 8 directions at the canopy's mean
// elevation, each encoded (an approximation: a grain's direction is its ring neighbours', as on a ring of
// speakers); the umbrella is held, so it turns with the body. The world bus: each other surface by its
// direction in the scene's frame, turned by the body's facing (/listener: a FacingTurn,
// listener_rotation.hpp, gliding over its 256 samples) and added to the body bus. Then the whole bus is
// rotated by the head's orientation (CommandKind::orientation, /listener/orientation), the matrix built
// off the audio thread and reached over rotation_ramp_frames by crossfading the old matrix's output into
// the new one's (no click). At facing 0 the world bus is the body bus (no extra pass); at the identity
// the head's rotation is skipped: the samples are the encoder's. Nothing is re-encoded or rebuilt.
// The panned formats (stereo, ring:N) turn the head by re-panning: each sound's direction is turned by
// H^T (the full rotation) and panned by the azimuth that results, the gains gliding over 256 samples
// (the umbrella's panels: DropOnCanopy::turn_head; the surfaces: SceneSurfaces::set_head; a grain at
// its start). Ears and mono have nothing to turn (the protocol refuses the orientation on ears).
// renderer_listener.cpp holds all of it.
// Output: full scale (1.0) is `full_scale_pa` pascals at level gain and gain 0 dB (output_stage.hpp
// states the calibration); the output stage (gain, limiter) is the last thing a sample passes. Mono: one listening point; stereo and more:
// one point, each panel panned by its azimuth over the speakers (ListenerStyle::panned), or for two
// channels optionally two ears (ListenerStyle::ears).

#include <array>
#include <cstdint>
#include <memory>

#include "engine/core/random.hpp"
#include "engine/models/drop_on_canopy.hpp"
#include "engine/models/ambisonics.hpp"
#include "engine/models/impact_templates.hpp"
#include "engine/models/panning.hpp"
#include "engine/models/texture_grains.hpp"
#include "engine/render/command.hpp"
#include "engine/render/listener_rotation.hpp"
#include "engine/render/loaded_scene.hpp"
#include "engine/render/lod_governor.hpp"
#include "engine/render/output_stage.hpp"
#include "engine/render/scene_surfaces.hpp"
#include "engine/render/umbrella_scene.hpp"
#include "engine/scene/output_format.hpp"
#include "engine/scene/rain_spawner.hpp"

namespace ameoto {

struct RendererConfig {
    // The scene: its umbrella (if any) and other surfaces, listener, rain and level of detail. The fields
    // below for the umbrella (canopy, material, listener_below_m), the rain rate and the LOD are what the
    // renderer uses; configure_for_scene() sets them from a scene, so a caller picks one or the other.
    SceneDescription scene = *builtin_scene("umbrella");
    double sample_rate = 48000.0;         // Hz
    int channels = 2;                     // 1..16
    std::uint64_t seed = 0;
    double rain_rate_mm_per_h = 2.0;      // the default scene: light rain
    CanopyGeometry canopy{};
    MembraneMaterial material = MembraneMaterial::nylon_canopy();
    bool air = false;                     // the canopy in air (air_canopy.hpp) or in vacuum; the scene's
                                          // umbrella air= key through configure_for_scene
    bool air_push = true;                 // in air: the contacts' push above the modes through compressible
                                          // air (air_push.hpp); false: the modes alone (the model before it,
                                          // which ameoto bench scene measures beside it)
    ImpactModel impact = ImpactModel::wet;  // how drops meet the canopy (wet_impact.hpp); the umbrella's
                                          // impact= key through configure_for_scene
    Liquid liquid = liquids::water();
    ListenerStyle listener = ListenerStyle::panned;
    double listener_below_m = 0.3;        // listener on the shaft, this far below the canopy
    double full_scale_pa = 100.0;         // pressure at output 1.0 (134 dB SPL: heavy rain's peaks fit)
    int full_drops = 4;                   // lattice drops at once (/drop, rain), at most max_full_drops;
                                          // more play as templates (/lod changes it live)
    double lod_budget = 0.4;              // fraction of the block period the governor aims for (/lod)
    double lod_full_level_db = 6.0;       // the governor's thresholds (lod_governor.hpp); benchmarks move
    double lod_texture_margin_db = 20.0;  // them to put every drop in one tier
    bool adaptive_lod = false;            // shed detail by measured load (live only: not reproducible)
    // Output (output_stage.hpp): the scene's level gain (what --level auto chose for it: level_choice.hpp;
    // 0 for --level physical), the listening gain on top (--gain, /gain, the scene's `output gain=`), the
    // look-ahead limiter. All three at their defaults: the samples are the physical ones, bit for bit.
    double level_gain_db = 0.0;
    double gain_db = 0.0;
    bool limiter = false;
    bool settle = true;                   // the lattice drops' settling (drop_on_canopy.hpp, "Settling");
                                          // false: the model before it (ameoto bench drop/scene time both)
    NetworkOptions canopy_network{};      // the canopy panels' method; configure_for_scene sets it from the
                                          // scene's accuracy budget (core/method_choice.hpp)
    int node = 0;                         // 1..16: render only the surfaces the scene gives this node (its
                                          // umbrella too if it is that node's); 0: the whole scene. Same
                                          // seed, same listener and rain: the nodes' outputs sum to the
                                          // whole scene's (scene_surfaces.hpp)
};

struct RendererStats {
    std::uint64_t drops = 0;              // impacts started (rain and /drop)
    std::uint64_t full_drops = 0;         // /drop drops given to the full (lattice) model
    std::uint64_t drop_fallbacks = 0;     // /drop drops played as templates because the pool was full
    std::uint64_t impacts_dropped = 0;    // template impacts lost because their pool was full
    std::uint64_t late_commands = 0;      // timed commands that arrived after their sample
    std::uint64_t busy_commands = 0;      // commands refused because the pending list was full
    std::uint64_t body_resets = 0;        // panels reset by the runtime guard (non-finite or runaway)
    int active_impacts = 0;               // template impacts sounding now
    int active_full_drops = 0;            // lattice drops in the scene now
    int active_grains = 0;                // texture grains sounding now
    std::uint64_t grains_dropped = 0;     // texture grains lost because their pool was full
    LodCounts rain_tiers;                 // rain drops given each tier so far
    double detail = 1.0;                  // the governor's detail now (1: nothing shed)
    std::uint64_t surface_drops = 0;      // drops struck on the scene's other surfaces
    double rain_rate_mm_per_h = 0.0;      // current (ramping) rate
    std::uint64_t clipped_samples = 0;    // samples that left the output stage past full scale (|x| > 1)
};

// What one process() did, for the per-block trace of slow callbacks (server/realtime/block_trace.hpp):
// the work that can make a block cost more than the steady rain does.
struct BlockActivity {
    int commands = 0;             // commands applied (their samples fell in this block)
    int lattice_spawned = 0;      // lattice drops spawned (rain given the full tier, /drop)
    int lattice_awake = 0;        // lattice drops alive in the block (the most at once)
    long link_breaks = 0;         // lattice links broken (a breakup)
    int full_rain = 0;            // rain drops given the full tier
    int template_impacts = 0;     // template impacts started (rain, and /drop fallbacks)
    int texture_grains = 0;       // rain drops heard as texture grains
    int priced_out = 0;           // rain drops the governor kept from the full tier by its price
    double detail = 1.0;          // the governor's detail at the end of the block
    bool scene_changed = false;   // a scene, surface or liquid was installed in this block
};

// Whether the scene's umbrella (if it has one) is rendered by `node` (0: the whole scene).
bool umbrella_on_node(const SceneDescription& scene, int node);

// Sets config's umbrella fields, rain rate and LOD from the scene, and the scene itself; throws
// std::invalid_argument with the reason (an unknown umbrella material, a listener not under the umbrella).
// `material` resolves umbrella material names (presets, or custom ones the caller knows); null: presets.
using MaterialResolver = std::optional<MembraneMaterial> (*)(const std::string& name, const void* context);
RendererConfig configure_for_scene(RendererConfig config, const SceneDescription& scene,
                                   MaterialResolver material = nullptr, const void* context = nullptr);

// Sets config's channels and listener style for an output format (scene/output_format.hpp). Binaural:
// the renderer makes the format's Ambisonic bus (order 3, 16 channels), which the caller decodes to two
// ears with a BinauralDecoder (binaural_decoder.hpp).
void apply_output_format(RendererConfig& config, const OutputFormat& format);

class Renderer {
public:
    static constexpr int max_channels = max_pan_channels;
    static constexpr int max_full_drops = 64;   // the lattice pool's capacity (what /lod may ask for)
    static constexpr int pending_capacity = 1024;
    static constexpr int event_capacity = 1024;
    static constexpr int rotation_ramp_frames = 256;   // 5.3 ms at 48 kHz: a head tracker's 100 Hz updates
                                                       // glide into each other without a click
    static constexpr int grain_ring = 8;               // virtual directions of the texture bed (ambix)

    // parts (make_parts; null: built here) must fit config's umbrella, or it throws std::invalid_argument.
    explicit Renderer(const RendererConfig& config, const UmbrellaParts* parts = nullptr);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Off the audio thread: the scene a renderer with this config plays (its material and liquid).
    // Throws std::invalid_argument or StabilityError with the reason.
    // parts: as for the constructor.
    static std::unique_ptr<UmbrellaScene> make_scene(const RendererConfig& config, const UmbrellaParts* parts = nullptr);
    // Off the audio thread: everything config (from configure_for_scene) describes, for load_scene.
    static std::unique_ptr<LoadedScene> make_loaded_scene(const RendererConfig& config, const UmbrellaParts* parts = nullptr);
    // Off the audio thread: the umbrella's canopy, templates and texture for config (umbrella_scene.hpp),
    // to build several renderers or scenes of it from one build. They fit any config that differs from
    // this one only in what the umbrella does not depend on: the rain, the listener style and channels,
    // the level, gain, limiter, detail and node.
    static std::shared_ptr<const UmbrellaParts> make_parts(const RendererConfig& config);
    // The umbrella scene's configuration for a renderer's (make_scene builds it).
    static DropOnCanopyConfig umbrella_config(const RendererConfig& config);

    void schedule(const Command& command);
    // The last block's load, 0..1+ (live): the governor's input, and what it prices lattice drops from.
    void set_measured_load(double load);
    void process(int frames, float* const* outputs);
    bool poll_event(RendererEvent& event);

    std::uint64_t frame() const { return frame_; }
    const RendererStats& stats() const { return stats_; }
    const BlockActivity& last_block() const { return last_block_; }
    const RendererConfig& config() const { return config_; }
    // Audio thread (or before audio starts) only:
    const UmbrellaScene& umbrella() const { return *scene_; }
    bool has_umbrella() const { return has_umbrella_; }
    const SceneSurfaces& surfaces() const { return *surfaces_; }
    const DropOnCanopy& scene() const { return scene_->drops; }
    const LodGovernor& governor() const { return governor_; }
    const Canopy& canopy() const { return scene_->drops.canopy(); }
    // The first sound of an impact: the nearest node's distance over c, plus the limiter's look-ahead.
    int latency_samples() const { return scene_->drops.latency_samples() + output_.latency_frames(); }
    const OutputStage& output() const { return output_; }
    bool ambisonic() const { return config_.listener == ListenerStyle::ambix; }
    const AmbixRotation& rotation() const { return rotation_to_; }   // the bus's rotation (its target while it turns)
    const FacingTurn& facing_turn() const { return facing_turn_; }   // ambix: the world bus's turn
    double level_gain_db() const { return level_db_; }   // the current scene's level gain (the target of a ramp)

private:
    void apply(const Command& command);
    void start_drop(const Command& command);
    void start_impact(double diameter_m, double speed_m_per_s, double x, double y);
    void start_rain_drop(double diameter_m, Point2 at);
    void swap_scene(const Command& command);
    void load_scene(const Command& command);
    void set_wind(double speed, double direction, double gustiness);
    void set_level_db(double db, bool ramp);
    // renderer_listener.cpp: the listener's turns (facing, head) on every format.
    void set_orientation(const Command& command);
    void move_listener(const Command& command);
    void hand_over_listener();               // a swapped-in scene hears the head as it is turned now
    double grain_azimuth(Point2 at, double height) const;
    void rotate(float* frame);
    void encode_grains(const Canopy& canopy);
    bool retire(void* object, RetiredObject type);
    void render_sample(float* const* outputs, int offset);
    void push_event(const RendererEvent& event) { (void)push_event_checked(event); }
    bool push_event_checked(const RendererEvent& event);

    RendererConfig config_;
    double dt_;
    Random rng_;
    // The scene in use, and the one it replaced, ringing out for fade_left_ samples after a change so
    // the change makes no click; both owned (raw pointers: ownership crosses threads by value).
    UmbrellaScene* scene_ = nullptr;
    UmbrellaScene* fading_ = nullptr;
    SceneSurfaces* surfaces_ = nullptr;          // owned, like scene_
    SceneSurfaces* fading_surfaces_ = nullptr;
    bool has_umbrella_ = true;
    bool fading_has_umbrella_ = true;
    int fade_left_ = 0;
    double rain_rate_ = 0.0;                     // mm/h, the scene's target
    RainSpawner* rain_ = nullptr;        // the umbrella's rain (owned; swapped with a loaded scene's DSD)
    Wind wind_;
    TemplatePool impacts_;
    LodGovernor governor_;
    std::unique_ptr<TextureGrains> grains_;
    Random grain_noise_;                  // the grains' own noise: the rain's draws do not depend on them
    double measured_load_ = 0.0;
    LatticeActivity last_activity_;              // what the lattice drops did in the last process()
    double last_block_seconds_ = 0.0;
    // The block length (frames) the governor's prior price of a lattice drop was last given for, 0
    // after a scene change: the prior is its templates' (lod_governor.hpp, set_lattice_prior).
    int prior_frames_ = 0;
    std::array<double, LodGovernor::max_prior_sizes> prior_events_{};   // per template size, for the governor
    void price_lattice_drops(int frames);
    static constexpr int governor_period = 64;   // samples
    int governor_samples_ = 0;
    int block_drops_ = 0;
    std::uint64_t frame_ = 0;
    RendererStats stats_;
    BlockActivity last_block_;
    // The scene's level gain (linear): the current scene's ramps over 50 ms to level_target_ (a load, or
    // /loudness); the fading scene keeps the gain it had, so a quiet scene's gain never lifts a loud one's tail.
    double level_db_ = 0.0;
    double level_ = 1.0, level_target_ = 1.0, level_step_ = 1.0;
    int level_ramp_left_ = 0;
    double fading_level_ = 1.0;
    OutputStage output_;
    // Ambisonics: the bus rotation (from_ while it turns to to_), the grains' ring encoding
    // [ring direction][acn], and rotations the event list could not take yet (handed back later).
    AmbixRotation rotation_from_, rotation_to_;
    int rotation_ramp_left_ = 0;
    bool rotating_ = false;
    std::array<std::array<double, max_ambix_channels>, grain_ring> grain_encoding_{};
    std::array<AmbixRotation*, 8> unreturned_{};
    FacingTurn facing_turn_;                     // ambix: the world bus's turn by the body's facing
    std::array<double, 9> head_{1, 0, 0, 0, 1, 0, 0, 0, 1};   // the head's rotation (head_rotation), panned formats
    bool head_turned_ = false;                   // head_ is not the identity

    // Commands waiting for their sample, sorted by frame (stable for equal frames).
    std::array<Command, pending_capacity> pending_{};
    int pending_count_ = 0;
    std::array<RendererEvent, event_capacity> events_{};
    int event_read_ = 0, event_count_ = 0;
};

}  // namespace ameoto
