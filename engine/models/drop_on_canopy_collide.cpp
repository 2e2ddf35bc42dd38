// SPDX-License-Identifier: GPL-3.0-or-later
// The lattice drops against the membrane, each sample (DropOnCanopy::collide) and the coarse-step
// floors that settling reads from it (DropOnCanopy::set_drop_floors): the costliest part of a sample
// once drops have landed, and the one whose skipping rules must keep the result to the bit (below).
// The scene's construction, stepping and output are drop_on_canopy.cpp.
#include "engine/models/drop_on_canopy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/models/collision_scan.hpp"

namespace ameoto {

// MembraneCollider::collide_drops, mass by mass, skipping the masses that collide_one would turn away
// anyway (collision detection, Canopy::locate, is much of a sample's cost once a drop has landed or
// shattered: most of its masses are above the layer that touches the membrane, or flying off). The
// masses that remain are collided exactly as collide_drops would, in the same order, so the result is
// identical to the bit (tested against collide_drops itself). collide_one (membrane_collision.cpp)
// collides a mass at p, velocity v, over node j of a panel, only if
//   h = a - u_j <= 0, with a = (p_z - z_rest(x, y)) n_z(x, y) (its height over the rest cap), and
//   closing = v . n_j - v2 < 0 with v2 = du_j/dt + pending_j, and -h = u_j - a < T (v2 - v . n_j) + skin.
// Inside the rim's circle z_rest lies between bottom_ and top_ and n_z >= n_z(rim), so a vertical
// distance d beyond that band is at least d n_z(rim) along the normal. Skipped:
//   - off the rim's circle: every panel (a triangle from the shaft to two rib tips at radius R) lies
//     inside it (with a relative 1e-12 for the rounding of the rib tips' coordinates);
//   - above: h <= 0 needs a <= u_j. The band's bound: more than reach_ over top_, 5 cm along the
//     normal, where the membrane does not reach (its largest excursion from one drop, measured: 0.9 mm
//     for 5 mm at terminal speed on nylon, 16 mm for 8 mm at 30 m/s on vinyl). Tighter, when collide()
//     has read the membrane's u this step: exactly a > max_j u_j (a computed by the same calls and
//     operations as in collide_one: on a flat canopy z_rest = +0 and n_z = 1, so a is p_z itself; a
//     correctly rounded a - u_j is <= 0 exactly when a <= u_j, and were collide_one's product fused
//     with its subtraction, its h <= 0 would still imply a <= u_j), after the quicker
//     p_z > top_ + max(max u, 0) / n_z(rim) (1e-9 of it and 1e-12 m for the rounding), which needs no
//     square root;
//   - below: -h < T (v2 - v . n_j) + skin needs a > u_j - skin - T (du_j/dt + |v|), since pending_j
//     (what this step's earlier collisions gave node j) is never positive (each impulse pushes the node
//     down, away from the drop: J >= 0) and v . n_j >= -|v| >= -|v|_1 (n_j is a unit vector). With
//     5 cm bounding the membrane's |u| + T |du/dt|, a mass more than 5 cm + skin + T |v|_1 under the
//     rim's rest height (along the normal) cannot collide; when u has been read this step, the 5 cm is
//     added to the lowest u instead (then it only bounds T |du/dt|: 2400 m/s at 48 kHz). Counting the
//     mass's own travel keeps a mass fast enough to cross the band in one step for collide_one's swept
//     test (the fixed band let one through from 2400 m/s at 48 kHz, 400 m/s at 8 kHz).
// Reading u is a pass over every node (a call each, 400 for the default canopy: about what 16 lookups
// cost, measured), so collide() reads it when it pays, when 16 or more masses were in the band the step
// before (an impact, several drops); and, to watch the band's bound, at least every 256 steps while
// drops are active, and every step while the last reading found |u| beyond a quarter of the band
// (12.5 mm; or no finite node). It reads at the start of the step, so that every mass and drop is tested
// against the same bounds. The canopy does not move during collide() (it steps afterwards), so a reading
// holds for the whole step. A node gone NaN is passed over by it and never collides.
// Most masses of a splash are in flight, over both the band and `above`: one comparison with the higher
// of the two (`high`) passes each of them over, before the checks above (the same masses skipped: a
// mass over `above` is turned away, and one over the band is not counted as near); and a drop whose
// lowest mass (DropPool::lowest_z: Body3D::lowest_z(), which the drop's last step measured in its update,
// or the dormant drop's lowest at spawn plus its shift) is over `high` is passed over whole, without a
// look at its masses (counted in stats().drops_passed_over; the test against collide_drops requires
// some). When u has been read, a drop whose lowest mass is over `above` is passed over whole as well:
// each of its masses would be turned away by the same comparison (visit()). Such a drop may still have
// masses in the band, which are not looked at; all of its masses count as near instead (at most an
// overestimate), so that u is read again next step as it would have been, when 16 or more. A splash
// hovering in flight over the membrane, as a 5 mm drop's does (its lowest piece 1.7 to 4 cm over a flat
// canopy from 20 ms to 100 ms after the impact, all of it rising), then costs one reading of u a step
// (shared by every drop) instead of a scan of its 122 masses (ameoto bench drop: docs/bench.md), while a
// lone drop of fewer than 16 masses does not make u be read every step, and is scanned as before.
void DropOnCanopy::collide() {
    collider_.begin_step();
    contact_force_ = Vec3{};
    const double r = canopy_.geometry().radius_m;
    const double r2_max = r * r * (1.0 + 1e-12);
    const bool flat = canopy_.flat();
    const double band_below = bottom_ - reach_;
    double below = band_below;
    const double per_normal = (1.0 + 1e-9) / rim_normal_z_;   // vertical per normal distance, rounded up
    // Wet: a mass is held up to 3/7 of its parcel (under its reach) below a node; skin plus the reach
    // covers that (drop_on_canopy.hpp), so the band below is widened by the reach.
    const double skin = collider_.options().skin_m + touch_, t = collider_.time_step();
    bool have_u = false;
    double u_max = 0.0, above = top_ + reach_;
    // Settling: also while an awake drop's lowest mass is in the band over the membrane, so that its
    // coarse steps (their floor, below) go by the membrane's highest point and not by the band's top:
    // a splash's pieces flying a few centimetres over the membrane, once what lay on it is parked.
    bool coarse_wanted = false;
    if (config_.settle)
        for (const int d : pool_.active()) {
            const double lowest = pool_.lowest_z(d);
            // Over the rest cap's top by the reach: below that, a piece lies on the membrane and the drop
            // cannot step coarsely whatever the floor (no reading: a lone drop's sliding pieces would
            // pay two passes over the nodes a sample for nothing).
            if (!pool_.dormant(d) && lowest > top_ + touch_ && lowest <= top_ + reach_) {
                coarse_wanted = true;
                break;
            }
        }
    if ((near_masses_ >= 16 || displaced_ || unread_steps_ >= 255 || coarse_wanted) && !pool_.active().empty()) {
        const DisplacementRange u = canopy_.displacement_range();
        // Wet: a mass touches up to touch_ over a node (its parcel's reach, at most the collider's cap);
        // 1e-12 m more keeps a - u_j <= reach from being lost to the rounding of u_max + touch_.
        u_max = touch_ > 0.0 ? u.highest + touch_ + 1e-12 : u.highest;
        above = top_ + std::max(u_max, 0.0) * per_normal + 1e-12;
        below = band_below - std::max(-u.lowest, 0.0) * per_normal;
        displaced_ = !(std::max(u.highest, -u.lowest) <= 0.25 * 0.05);
        have_u = true;
    }
    const double band_top = top_ + reach_;
    // Coarse steps (drop_pool.hpp) this sample for a drop wholly above the floor. Without settling: the
    // membrane's highest point read now, with 2 mm for what it can rise in the few samples of a coarse
    // step and the collider's skin; unread, the band, which it never reaches. With settling: each drop's
    // own floor (set_drop_floors).
    if (config_.settle) {
        set_drop_floors(have_u, above, skin, per_normal);
    } else {
        // Without settling (the model before it): one floor for the pool, from whatever was read this
        // sample for any drop.
        pool_.set_coarse_floor(have_u ? above + 2e-3 + skin : band_top);
    }
    // A mass higher than this is neither looked up (it is over `above`) nor counted as near (over the
    // band): one comparison for most of a splash's masses in flight; a drop whose lowest mass is over it
    // is skipped whole.
    const double high = std::max(above, band_top);
    int near = 0;
    // One mass: the checks below, then collide_one. Called with the mass's position as the pool gives it.
    // An awake drop's masses come from scan_for_collisions (collision_scan.hpp), which has already
    // applied the first checks (the circle, the band's count, over `high` or `above`, and on a flat
    // canopy with u read a > u_max) in the same form, and enters at `look`.
    auto look = [&](int d, int m, const Vec3 p) {
        if (have_u) {
            const double a = flat ? p.z : (p.z - canopy_.rest_height(p.x, p.y)) * canopy_.surface_normal(p.x, p.y).z;
            if (a > u_max) return;
        }
        const Vec3 v = pool_.velocity(d, m);
        if (p.z < below && p.z < below - (skin + t * (std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z))) * per_normal)
            return;
        Vec3 force;
        if (collider_.collide_one(canopy_, p, v, pool_.mass(d, m), force)) {
            pool_.apply_force(d, m, force);
            contact_force_ = contact_force_ + force;
        }
    };
    auto visit = [&](int d, int m, const Vec3 p) {
        if (p.x * p.x + p.y * p.y > r2_max) return;
        if (p.z <= band_top && p.z >= band_below) ++near;
        if (p.z > above) return;
        look(d, m, p);
    };
    CollisionScanBounds bounds;
    bounds.r2_max = r2_max;
    bounds.high = high;
    bounds.limit = above;
    bounds.limit_u = have_u && flat ? u_max : std::numeric_limits<double>::infinity();
    bounds.band_below = band_below;
    bounds.band_top = band_top;
    for (const int d : pool_.active()) {
        const double lowest = pool_.lowest_z(d);   // Body3D::lowest_z(): measured by the drop's last step
        if (lowest > high || (have_u && lowest > above)) {
            ++drops_passed_over_;
            if (!(lowest > band_top)) {
                near += pool_.mass_count(d);   // its masses in the band, uncounted: at most all of them
                ++drops_passed_over_in_band_;
            }
            continue;
        }
        const int n = pool_.mass_count(d);
        if (pool_.dormant(d)) {   // its body holds the positions at spawn: the pool adds the shift
            for (int m = 0; m < n; ++m) {
                const Vec3 p = pool_.position(d, m);
                if (!(p.z > high)) visit(d, m, p);
            }
            continue;
        }
        // Awake: the body's coordinate arrays (pool_.position(d, m) is position(m) of this same body;
        // body() wakes only a dormant drop, and apply_force only adds to the external forces, so the
        // arrays stay valid through the loop). A call per mass cost about as much as the checks.
        const Body3D::Coordinates c = pool_.body(d).positions();
        const int listed = scan_for_collisions(c.x, c.y, c.z, n, bounds, scan_.data(), near);
        for (int k = 0; k < listed; ++k) {
            const int m = scan_[static_cast<std::size_t>(k)];
            look(d, m, Vec3{c.x[m], c.y[m], c.z[m]});
        }
    }
    near_masses_ = near;
    unread_steps_ = have_u ? 0 : std::min(unread_steps_ + 1, 255);
}

// Settling's coarse floors, each drop's own: a function of the drop's lowest mass and of the membrane as
// it is this sample, never of the other drops, so that a drop's steps (and its samples) are the same
// whenever, and among whatever, it falls. (One floor for the pool, read when any drop wanted it, let a
// drop's coarse steps change with another's presence: drop_settle_independence_test.) For an awake drop
// whose lowest mass clears the rest cap's top by the reach but lies in the band (coarse_wanted in
// collide(), which has then read the membrane's extremes: have_u):
//   - the membrane's highest point (with the reach, `above`) plus 2 mm for what it can rise in the few
//     samples of a coarse step (0.1 mm at 1 m/s over 4 samples at 48 kHz) and the collider's skin;
//   - when its lowest mass lies between `above` and 1 mm over that, the membrane's fastest node read as
//     well (a pass over the nodes, made once a sample however many drops need it; in air the modes'
//     bound on it, AirCanopyState::velocity_bound, which only raises the floor): its highest point
//     plus 1.5 times that speed and 0.5 m/s over the longest coarse step (0.25 mm for a 5 mm drop on
//     nylon, 1.7 m/s at most; 1.9 mm for 8 mm at 30 m/s on vinyl, 14.5 m/s), instead of a fixed
//     3-4 mm: a wet splash's sheet flies 3-5 mm over the membrane for its first 50 ms.
// Any other drop's floor is the band's top, which the membrane never reaches: over it the drop is clear
// of the membrane; under the cap's top by the reach (a piece on the membrane) or dormant, it takes no
// coarse step whatever the floor. (A mass that touched during a coarse step would end it: counted in
// DropPoolStats::coarse_interrupted, never seen.)
void DropOnCanopy::set_drop_floors(bool have_u, double above, double skin, double per_normal) {
    const double band_top = top_ + reach_;
    const double fixed = above + 2e-3 + skin;
    bool fastest_read = false;
    double fastest = 0.0;
    for (const int d : pool_.active()) {
        const double lowest = pool_.lowest_z(d);
        double floor = band_top;
        if (have_u && !pool_.dormant(d) && lowest > top_ + touch_ && lowest <= band_top) {
            floor = fixed;
            if (lowest > above && lowest <= fixed + 1e-3) {
                if (!fastest_read) {
                    if (canopy_.in_air()) {
                        // The modes' bound, O(modes): the exact node velocities cost nodes x modes a reading
                        // (400 000 products on the default canopy), 60 % of recording a scene's templates in air.
                        fastest = canopy_.air_state().velocity_bound(*canopy_.air_modes());
                    } else {
                        canopy_.velocities(node_velocities_.data());
                        for (const double v : node_velocities_) fastest = std::max(fastest, std::fabs(v));
                    }
                    fastest_read = true;
                }
                if (std::isfinite(fastest))
                    floor = above + (1.5 * fastest + 0.5) * config_.coarse_steps * dt_ * per_normal + 1e-12;
            }
        }
        pool_.set_coarse_floor(d, floor);
    }
}

}  // namespace ameoto
