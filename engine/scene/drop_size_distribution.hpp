// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Raindrop size distributions and the impact flux they imply.
//
// Interface:
//   DropSizeDistribution dsd;                          // Marshall-Palmer (the default)
//   DropSizeDistribution::marshall_palmer()            // N0 = 8000 m^-3 mm^-1, Lambda = 4.1 R^-0.21 mm^-1
//   DropSizeDistribution::joss_drizzle()               // N0 = 30000, Lambda = 5.7 R^-0.21
//   DropSizeDistribution::joss_thunderstorm()          // N0 = 1400,  Lambda = 3.0 R^-0.21
//   DropSizeDistribution::gamma(mu, lambda_per_mm)     // N0 D^mu exp(-Lambda D), N0 set by R (water-matched)
//   DropSizeDistribution::gamma_zhang(lambda_per_mm)   // the same with mu from Zhang et al.'s mu-Lambda relation
//   dsd.lambda_per_mm(R), dsd.mu_at(R)                 // shape at rain rate R (mm/h)
//   dsd.n0_at(R)                                       // N0 in m^-3 mm^-(1+mu)
//   dsd.number_density(diameter_mm, R)                 // N(D), m^-3 mm^-1
//   dsd.water_mm_per_h(R)                              // the rain rate the distribution really delivers
//   impact_flux(dsd, R, d_min_mm, d_max_mm)            // drops m^-2 s^-1 = integral N(D) v(D) dD
//   MarshallPalmer                                     // the former name of this type (an alias): a
//                                                      // default MarshallPalmer{} is still Marshall-Palmer
//
// The family: N(D) = N0(R) D^mu exp(-Lambda(R) D), D in mm, with Lambda(R) = lambda_coefficient *
// R^lambda_exponent and mu either given (mu; 0 is the exponential family) or, with mu_from_lambda, the
// constrained relation mu = -0.016 Lambda^2 + 1.213 Lambda - 1.957 (Zhang et al. 2001, IEEE TGRS 39:830,
// as written in ../shared/reference/physics.md section 2). Sources of the presets: Marshall & Palmer 1948,
// J. Meteor. 5:165; Joss, Thams & Waldvogel 1968 (drizzle and thunderstorm), via physics.md section 2.
//
// N0 and the water delivered (physics.md s.2 asks the docs to say): with N0Mode::published (the three
// exponential presets) N0 is the published constant and is NOT renormalised, so the water actually
// carried, 6 pi 1e-4 integral D^3 v(D) N(D) dD mm/h, differs from R: Marshall-Palmer delivers 1.18 R at
// 1 mm/h and 1.05 R at 100 mm/h, Joss drizzle 0.89..0.93 R and Joss thunderstorm 0.92 R at 1 mm/h down
// to 0.73 R at 100 mm/h; the drop counts then match the published distributions, which is what a
// listener hears. With N0Mode::water_matched (the gamma presets: no N0 is published for them; any preset
// may switch to it) N0(R) is chosen so the water delivered is exactly R (to the quadrature, 1e-6). The
// measured ratios per preset are printed by tests/engine/scene/drop_size_distribution_test.cpp.
// The water integral runs over 0..20 mm (the tail beyond is < 1e-6 of it for these slopes); the flux over
// the caller's [d_min, d_max]. Rain rates are in mm/h and diameters in mm here because the published fits
// are written in them; callers convert at this boundary. Valid shapes: Lambda > 0 and mu > -1 (checked by
// RainSpawner over its whole rate range).

namespace ameoto {

enum class N0Mode {
    published,       // N0 = n0_per_m3_mm as given (units m^-3 mm^-(1+mu))
    water_matched,   // N0 = R / (water delivered per unit N0): the distribution delivers exactly R
};

struct DropSizeDistribution {
    double n0_per_m3_mm = 8000.0;      // used with N0Mode::published
    double lambda_coefficient = 4.1;   // Lambda = lambda_coefficient * R^lambda_exponent, mm^-1
    double lambda_exponent = -0.21;
    double mu = 0.0;                   // shape; ignored when mu_from_lambda
    bool mu_from_lambda = false;       // Zhang et al. 2001 constrained relation
    N0Mode n0_mode = N0Mode::published;

    static DropSizeDistribution marshall_palmer() { return {}; }
    static DropSizeDistribution joss_drizzle() { return {30000.0, 5.7, -0.21}; }
    static DropSizeDistribution joss_thunderstorm() { return {1400.0, 3.0, -0.21}; }
    // Lambda fixed (lambda_exponent 0): the shape is the same at every rate, the number of drops scales
    // with R. For a rate-dependent slope set lambda_exponent afterwards.
    static DropSizeDistribution gamma(double mu, double lambda_per_mm) {
        return {0.0, lambda_per_mm, 0.0, mu, false, N0Mode::water_matched};
    }
    static DropSizeDistribution gamma_zhang(double lambda_per_mm) {
        return {0.0, lambda_per_mm, 0.0, 0.0, true, N0Mode::water_matched};
    }

    double lambda_per_mm(double rate_mm_per_h) const;
    double mu_at(double rate_mm_per_h) const;
    // water_matched: integrates (about 4000 points); not for the audio thread.
    double n0_at(double rate_mm_per_h) const;
    double number_density(double diameter_mm, double rate_mm_per_h) const;
    double water_mm_per_h(double rate_mm_per_h) const;
    // D^mu exp(-Lambda D): N(D) / N0, the shape alone (no integral; cheap).
    double shape(double diameter_mm, double rate_mm_per_h) const;
};

using MarshallPalmer = DropSizeDistribution;

// Zhang et al. 2001 constrained relation (physics.md s.2): mu = -0.016 Lambda^2 + 1.213 Lambda - 1.957.
double zhang_mu(double lambda_per_mm);

// Impacts per m^2 per s of drops with d_min <= D <= d_max on a horizontal surface, by composite
// Simpson integration of N(D) v(D) with Gunn-Kinzer speeds. Not for the audio thread (it loops
// over a few thousand points); RainSpawner tabulates it once.
double impact_flux(const DropSizeDistribution& dsd, double rate_mm_per_h, double d_min_mm, double d_max_mm);

}  // namespace ameoto
