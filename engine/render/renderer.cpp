#include "engine/render/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/core/physical_constants.hpp"
#include "engine/scene/terminal_speed.hpp"

namespace ameoto {

std::array<double, Renderer::max_channels> pan_gains(double azimuth, int channels) {
    std::array<double, Renderer::max_channels> g{};
    if (channels <= 1) {
        g[0] = 1.0;
        return g;
    }
    if (channels == 2) {
        // pan 0 = hard left (azimuth +90 deg), 1 = hard right.
        const double pan = 0.5 * (1.0 - std::sin(azimuth));
        g[0] = std::cos(pan * constants::pi / 2.0);
        g[1] = std::sin(pan * constants::pi / 2.0);
        return g;
    }
    // Speaker c sits at azimuth a_c = first - c * spacing (clockwise from front-left).
    const double spacing = 2.0 * constants::pi / channels;
    const double first = spacing / 2.0;
    double rel = (first - azimuth) / spacing;   // position in speaker units, clockwise
    rel -= std::floor(rel / channels) * channels;
    const int c0 = static_cast<int>(rel) % channels;
    const int c1 = (c0 + 1) % channels;
    const double t = rel - std::floor(rel);
    g[static_cast<std::size_t>(c0)] = std::cos(t * constants::pi / 2.0);
    g[static_cast<std::size_t>(c1)] = std::sin(t * constants::pi / 2.0);
    return g;
}

namespace {
RainSpawner::Config rain_config_for(const Canopy& canopy) {
    RainSpawner::Config rc;
    rc.area_m2 = canopy.area();
    return rc;
}
}  // namespace

Renderer::Renderer(const RendererConfig& config)
    : config_(config),
      dt_(1.0 / config.sample_rate),
      rng_(config.seed),
      canopy_(new Canopy(config.canopy, config.material, 1.0 / config.sample_rate)),
      liquid_density_(constants::water_density),
      rain_(rain_config_for(*canopy_)) {
    if (config.channels < 1 || config.channels > max_channels) throw std::invalid_argument("channels must be 1 to 16");
    if (!(config.sample_rate >= 8000.0 && config.sample_rate <= 384000.0))
        throw std::invalid_argument("sample rate must be 8000 to 384000 Hz");
    rain_.set_rate_now(config.rain_rate_mm_per_h);
    panel_force_.assign(static_cast<std::size_t>(canopy_->panel_count()), 0.0);
    fading_force_.assign(static_cast<std::size_t>(canopy_->panel_count()), 0.0);
    panel_gain_.resize(static_cast<std::size_t>(canopy_->panel_count()));
    for (int k = 0; k < canopy_->panel_count(); ++k) {
        const Point2 c = canopy_->panel_centroid(k);
        const double r = std::sqrt(c.x * c.x + c.y * c.y + config.listener_below_m * config.listener_below_m);
        const double pa_per_newton =
            constants::air_density / (2.0 * constants::pi * r) / config.material.areal_density;
        auto gains = pan_gains(canopy_->panel_azimuth(k), config.channels);
        for (auto& g : gains) g *= pa_per_newton / config.full_scale_pa;
        panel_gain_[static_cast<std::size_t>(k)] = gains;
    }
}

void Renderer::push_event(const RendererEvent& event) { (void)push_event_checked(event); }

bool Renderer::push_event_checked(const RendererEvent& event) {
    if (event_count_ == event_capacity) return false;   // the control thread is far behind
    events_[static_cast<std::size_t>((event_read_ + event_count_) % event_capacity)] = event;
    ++event_count_;
    return true;
}

void Renderer::swap_canopy(const Command& c) {
    auto* incoming = static_cast<Canopy*>(c.object);
    if (!incoming || incoming->panel_count() != canopy_->panel_count()) {
        // Only a canopy of the same geometry can take over (its panning and listener distances are set);
        // a mismatch goes straight back to be freed.
        push_event({RendererEventKind::retired, c.kind, c.reply_to, c.id, incoming});
        return;
    }
    if (fading_) push_event({RendererEventKind::retired, c.kind, c.reply_to, c.id, fading_});   // a change during a fade
    fading_ = canopy_;
    fade_left_ = static_cast<int>(0.5 / dt_);
    canopy_ = incoming;
    push_event({RendererEventKind::swapped, c.kind, c.reply_to, c.id});
}

Renderer::~Renderer() {
    // Runs on the control thread once audio has stopped: free everything still owned, including canopies
    // waiting in the pending list.
    for (int i = 0; i < pending_count_; ++i)
        if (pending_[static_cast<std::size_t>(i)].kind == CommandKind::swap_canopy)
            delete static_cast<Canopy*>(pending_[static_cast<std::size_t>(i)].object);
    delete fading_;
    delete canopy_;
}

bool Renderer::poll_event(RendererEvent& event) {
    if (event_count_ == 0) return false;
    event = events_[static_cast<std::size_t>(event_read_)];
    event_read_ = (event_read_ + 1) % event_capacity;
    --event_count_;
    return true;
}

void Renderer::schedule(const Command& command) {
    Command c = command;
    if (!c.timed || c.frame < frame_) {
        if (c.timed) ++stats_.late_commands;
        c.frame = frame_;   // due now: the first sample of the next block
    }
    if (pending_count_ == pending_capacity) {
        ++stats_.busy_commands;
        push_event({RendererEventKind::busy, c.kind, c.reply_to, c.id});
        return;
    }
    // Insertion keeps the list sorted by frame and first-come-first-served among equal frames.
    int i = pending_count_;
    while (i > 0 && pending_[static_cast<std::size_t>(i - 1)].frame > c.frame) {
        pending_[static_cast<std::size_t>(i)] = pending_[static_cast<std::size_t>(i - 1)];
        --i;
    }
    pending_[static_cast<std::size_t>(i)] = c;
    ++pending_count_;
}

void Renderer::start_impact(double diameter_m, double speed_m_per_s, double x, double y) {
    const CanopyHit hit = canopy_->locate(x, y);
    if (hit.panel < 0) return;
    const double mass = liquid_density_ * constants::pi / 6.0 * diameter_m * diameter_m * diameter_m;
    const double speed = speed_m_per_s > 0.0 ? speed_m_per_s : terminal_speed(diameter_m);
    ++stats_.drops;
    if (!impacts_.add(hit, mass * speed, diameter_m / speed, dt_)) ++stats_.impacts_dropped;
}

void Renderer::apply(const Command& c) {
    switch (c.kind) {
        case CommandKind::drop: start_impact(c.values[0], c.values[1], c.values[2], c.values[3]); break;
        case CommandKind::rain_rate: rain_.set_rate(c.values[0]); break;
        case CommandKind::sync: push_event({RendererEventKind::synced, c.kind, c.reply_to, c.id}); break;
        case CommandKind::swap_canopy: swap_canopy(c); break;
        case CommandKind::set_liquid_density:
            liquid_density_ = c.values[0];
            push_event({RendererEventKind::swapped, c.kind, c.reply_to, c.id});
            break;
    }
}

void Renderer::render_sample(float* const* outputs, int offset) {
    const int arrivals = rain_.advance(dt_, rng_);
    for (int a = 0; a < arrivals; ++a) {
        const double d = rain_.sample_diameter_m(rng_);
        const Point2 p = canopy_->sample_point(rng_);
        start_impact(d, 0.0, p.x, p.y);
    }
    // A falling drop pushes the membrane down, against its upward normal (as the collider does).
    impacts_.emit(dt_, [this](CanopyHit hit, double force) { canopy_->apply_force(hit, -force); });
    canopy_->step(panel_force_.data());
    if (fading_) {
        fading_->step(fading_force_.data());
        for (std::size_t k = 0; k < panel_force_.size(); ++k) panel_force_[k] += fading_force_[k];
        if (--fade_left_ <= 0 && push_event_checked({RendererEventKind::retired, CommandKind::swap_canopy, 0, 0, fading_}))
            fading_ = nullptr;   // if the event list is full it rings on and is handed back next sample
    }
    const int channels = config_.channels;
    for (int ch = 0; ch < channels; ++ch) {
        double sample = 0.0;
        for (std::size_t k = 0; k < panel_force_.size(); ++k)
            sample += panel_gain_[k][static_cast<std::size_t>(ch)] * panel_force_[k];
        // A panel that went non-finite is reset at the end of the block; until then it is muted.
        outputs[ch][offset] = std::isfinite(sample) ? static_cast<float>(sample) : 0.0f;
    }
}

void Renderer::process(int frames, float* const* outputs) {
    for (int n = 0; n < frames; ++n) {
        const std::uint64_t now = frame_ + static_cast<std::uint64_t>(n);
        // Apply every command due at this sample, in order.
        int applied = 0;
        while (applied < pending_count_ && pending_[static_cast<std::size_t>(applied)].frame <= now)
            apply(pending_[static_cast<std::size_t>(applied++)]);
        if (applied > 0) {
            std::copy(pending_.begin() + applied, pending_.begin() + pending_count_, pending_.begin());
            pending_count_ -= applied;
        }
        render_sample(outputs, n);
    }
    frame_ += static_cast<std::uint64_t>(frames);
    // Runtime guard (core/stability.hpp): a panel whose state went non-finite or whose energy ran away is
    // reset and counted, never left to explode.
    stats_.body_resets += static_cast<std::uint64_t>(canopy_->reset_unstable());
    if (fading_) stats_.body_resets += static_cast<std::uint64_t>(fading_->reset_unstable());
    stats_.active_impacts = impacts_.active();
    stats_.rain_rate_mm_per_h = rain_.rate();
}

}  // namespace ameoto
