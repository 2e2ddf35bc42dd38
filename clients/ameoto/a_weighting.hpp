// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The A frequency weighting of IEC 61672-1:2013 (sound level meters), as a digital filter for levels
// measured offline (`ameoto bench levels`), and the standard's analogue weighting it approximates.
//
// Interface (any thread; an AWeighting is one signal's state, not shared between threads):
//   double a = a_weighting_db(1000.0);        // the standard's A(f) in dB, 0 at 1 kHz (IEC 61672-1 E.6)
//   AWeighting w(48000.0);                    // the filter at this sample rate (8 kHz .. 768 kHz)
//   double y = w.process(x);                  // one sample in, one weighted sample out
//   double g = w.response_db(1000.0);         // the filter's own magnitude response, dB (0.000 at 1 kHz)
//   w.reset();                                // back to rest
//
// The analogue weighting (IEC 61672-1:2013, Annex E, E.6):
//   A(s) = K s^4 / ((s + w1)^2 (s + w2) (s + w3) (s + w4)^2),  wi = 2 pi fi,
//   f1 = 20.598997 Hz, f2 = 107.65265 Hz, f3 = 737.86223 Hz, f4 = 12194.217 Hz,
// K such that |A| = 1 at 1 kHz. The filter is that product of six first-order sections, each mapped by
// the bilinear transform with its pole frequency pre-warped (wi' = 2 fs tan(wi / 2 fs)): the four
// zeros at s = 0 go to z = 1 exactly, each corner lands at its analogue frequency, and the gain is set
// to 0 dB at 1 kHz from the digital response itself. Warping the poles widens the pass band a little
// and the bilinear map still folds the last octave onto Nyquist: at 48 kHz the filter is within 0.1 dB
// of A(f) up to 2 kHz, then +0.1 dB at 2.5 kHz, +0.3 at 4, +0.7 at 8, +0.6 at 10, -0.2 at 12.5 and -2.9
// at 16 kHz, inside IEC 61672-1:2013's class 1 limits (+1.0, +1.0, +1.5, +2.0, -5.0, -16 dB there;
// tested at the standard's third-octave frequencies 10 Hz .. 16 kHz). At 96 kHz: within 0.16 dB up to
// 12.5 kHz, -0.45 at 16. (Without the pre-warping: -1.2 dB at 10 kHz, -2.7 at 12.5, -6.2 at 16.)
// Cascaded first-order sections in double: no coefficient is closer to 1 than 1 - 2.7e-3 at 48 kHz.

#include <array>

namespace ameoto::client {

double a_weighting_db(double frequency_hz);

class AWeighting {
public:
    explicit AWeighting(double sample_rate);
    double process(double x) {
        for (Section& s : sections_) {
            const double y = s.b0 * x + s.b1 * s.x1 - s.a1 * s.y1;
            s.x1 = x;
            s.y1 = y;
            x = y;
        }
        return gain_ * x;
    }
    double response_db(double frequency_hz) const;
    void reset();

private:
    struct Section {   // y[n] = b0 x[n] + b1 x[n-1] - a1 y[n-1]
        double b0 = 1.0, b1 = 0.0, a1 = 0.0;
        double x1 = 0.0, y1 = 0.0;
    };
    std::array<Section, 6> sections_{};
    double sample_rate_;
    double gain_ = 1.0;
    double raw_response(double frequency_hz) const;   // |H| of the sections alone
};

}  // namespace ameoto::client
