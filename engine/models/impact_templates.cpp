#include "engine/models/impact_templates.hpp"

#include <cmath>

#include "engine/models/drop.hpp"

namespace ameoto {

int ImpactTemplateTable::nearest(double diameter_m) const {
    // The grid is geometric: the nearest in log D is found by bisection on the geometric midpoints.
    int lo = 0, hi = static_cast<int>(diameters_m.size()) - 1;
    if (hi < 0) return -1;
    while (lo < hi) {
        const int mid = (lo + hi) / 2;
        const double split = std::sqrt(diameters_m[static_cast<std::size_t>(mid)] * diameters_m[static_cast<std::size_t>(mid + 1)]);
        if (diameter_m < split) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    return lo;
}

ImpactTemplateTable record_impact_templates(const DropOnCanopyConfig& scene, const TemplateGrid& grid) {
    ImpactTemplateTable t;
    t.sample_rate = scene.sample_rate;
    t.density = scene.liquid.density;
    for (double d = grid.min_diameter_m; d <= grid.max_diameter_m * (1.0 + 1e-9); d *= grid.step_ratio) t.diameters_m.push_back(d);
    t.length = static_cast<int>(std::ceil(grid.seconds * scene.sample_rate));
    t.forces.assign(t.diameters_m.size() * static_cast<std::size_t>(t.length), 0.0);

    DropOnCanopyConfig c = scene;
    c.output = SceneOutput::mass_pickup;   // the sound is not needed, only the contact force
    c.channels = 1;
    c.capacity = 1;
    c.max_diameter = grid.max_diameter_m * (1.0 + 1e-9);
    c.gap_m = 0.0;                         // striking in the first sample, as the server's /drop
    const double x = 0.5 * scene.geometry.radius_m * std::cos(0.0), y = 0.0;
    for (std::size_t k = 0; k < t.diameters_m.size(); ++k) {
        DropOnCanopy run(c);
        const double d = t.diameters_m[k];
        t.speeds_m_per_s.push_back(arrival_speed(d, scene.liquid.density));
        run.drop(d, 0.0, x, y);
        const Vec3 n = run.canopy().surface_normal(x, y);
        float frame[1];
        for (int i = 0; i < t.length; ++i) {
            run.process_frame(frame);
            // The membrane takes the opposite of what the drop masses took.
            t.forces[k * static_cast<std::size_t>(t.length) + static_cast<std::size_t>(i)] = -dot(run.contact_force(), n);
        }
        int used = t.length;
        while (used > 1 && t.forces[k * static_cast<std::size_t>(t.length) + static_cast<std::size_t>(used - 1)] == 0.0) --used;
        t.used.push_back(used);
    }
    return t;
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
