// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The collision broad phase's first look at a drop's masses (DropOnCanopy::collide, drop_on_canopy_collide.cpp):
// one pass over a body's coordinate arrays that lists the masses worth a closer look and counts those
// in the band near the membrane, four masses per AVX2 vector where the CPU has it.
//
// Interface:
//   CollisionScanBounds b{r2_max, high, limit, limit_u, band_below, band_top};
//   int count = scan_for_collisions(x, y, z, n, b, out, near);   // out: n ints of room
//   set_portable_collision_scan(true);                             // the scalar loop even on AVX2 (tests)
//
// Mass m is listed (in out, ascending) when it is inside the rim's circle, !(x^2 + y^2 > r2_max), and
// not over any of the heights that rule a collision out: !(z > high) && !(z > limit) && !(z > limit_u).
// These are the first tests collide() applies to each mass, in the same form (a NaN coordinate passes,
// as there), so the listed masses are exactly those that reach collide()'s next checks. `near` is
// increased by the masses inside the circle with band_below <= z <= band_top (collide()'s count of the
// band, which decides when it reads the membrane's displacement; band_top <= high).
// Why a pass of its own: after a splash most of a drop's 122 masses fly within the 5 cm band over the
// canopy, so a per-mass branchy test cost about 11 instructions a mass; the pass here decides four masses
// with a few vector compares and leaves only the few low masses to the scalar checks. x^2 + y^2 is the
// same IEEE expression in either code (two products, one sum; no FMA: -ffp-contract=off), so the AVX2
// and scalar passes list the same masses (tested).

namespace ameoto {

struct CollisionScanBounds {
    double r2_max = 0.0;       // m^2: the rim's circle (squared radius, rounded up)
    double high = 0.0;         // m: over this, neither looked at nor near
    double limit = 0.0;        // m: over this, no collision (collide()'s `above`)
    double limit_u = 0.0;      // m: likewise (the flat canopy's highest node when read; else +infinity)
    double band_below = 0.0;   // m: the band counted as near
    double band_top = 0.0;
};

int scan_for_collisions(const double* x, const double* y, const double* z, int n, const CollisionScanBounds& bounds,
                        int* out, int& near);
void set_portable_collision_scan(bool on);

}  // namespace ameoto
