// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/render/umbrella_scene.hpp"

#include <stdexcept>

namespace ameoto {

namespace {

// The fields the parts do not depend on, set alike: the templates record a mono mass pickup and the
// texture a mono far field whatever the scene's output (impact_templates.cpp, texture_grains.cpp).
DropOnCanopyConfig without_output(DropOnCanopyConfig c) {
    c.output = SceneOutput::far_field;
    c.channels = 1;
    c.listener = ListenerStyle::panned;
    return c;
}

const UmbrellaParts& fitting(const UmbrellaParts& parts, const DropOnCanopyConfig& config) {
    if (!parts.fits(config))
        throw std::invalid_argument("the umbrella's parts were built for another scene (its material, liquid, geometry, rate, air or impact)");
    return parts;
}

}  // namespace

// The same order and calls as UmbrellaScene(config, prototype): the same parts bit for bit.
UmbrellaParts::UmbrellaParts(const DropOnCanopyConfig& c)
    : config(c),
      canopy(DropOnCanopy::fresh_canopy(c)),
      templates(record_impact_templates(c, canopy)),
      texture(calibrate_texture(c, templates, canopy)) {}

bool UmbrellaParts::fits(const DropOnCanopyConfig& other) const { return without_output(other) == without_output(config); }

UmbrellaScene::UmbrellaScene(const DropOnCanopyConfig& config, const UmbrellaParts& parts)
    : drops(config, fitting(parts, config).canopy), templates(parts.templates), texture(parts.texture) {}

}  // namespace ameoto
