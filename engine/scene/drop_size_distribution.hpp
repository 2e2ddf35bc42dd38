#pragma once
// Raindrop size distribution and the impact flux it implies.
//
// Interface:
//   MarshallPalmer dsd;                          // N0 = 8000 m^-3 mm^-1, Lambda = 4.1 R^-0.21 mm^-1
//   dsd.lambda_per_mm(rate_mm_per_h)             // slope Lambda
//   dsd.number_density(diameter_mm, rate)        // N(D), m^-3 mm^-1
//   impact_flux(dsd, rate, d_min_mm, d_max_mm)   // drops m^-2 s^-1 = integral N(D) v(D) dD
//
// Source: Marshall & Palmer 1948, J. Meteor. 5:165; the flux integral and its reference values are
// in ../shared/reference/physics.md section 2. Plain Marshall-Palmer is used as published: N0 is NOT
// renormalised, so the water it delivers is 1.18 R at 1 mm/h and 1.05 R at 100 mm/h (docs/engine.md).
// Rain rates are in mm/h and diameters in mm here because the published fits are written in them;
// callers convert at this boundary.

namespace ameoto {

struct MarshallPalmer {
    double n0_per_m3_mm = 8000.0;
    double lambda_coefficient = 4.1;   // Lambda = lambda_coefficient * R^lambda_exponent
    double lambda_exponent = -0.21;

    double lambda_per_mm(double rate_mm_per_h) const;
    double number_density(double diameter_mm, double rate_mm_per_h) const;
};

// Impacts per m^2 per s of drops with d_min <= D <= d_max on a horizontal surface, by composite
// Simpson integration of N(D) v(D) with Gunn-Kinzer speeds. Not for the audio thread (it loops
// over a few thousand points); RainSpawner tabulates it once.
double impact_flux(const MarshallPalmer& dsd, double rate_mm_per_h, double d_min_mm, double d_max_mm);

}  // namespace ameoto
