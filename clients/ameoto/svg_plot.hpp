// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Plots for `ameoto render drop --plot FILE.svg`: a drop's breakup over time above the sound it made,
// as one self-contained SVG file (no scripts, no external fonts or images).
//
// Interface:
//   SvgPlot plot(900, 760, "5 mm water drop on nylon, 4 m/s");          // width, height (px), title
//   plot.series({x0, y0, w, h}, times_s, values, "pieces", "time (s)");  // a step line, e.g. pieces
//   plot.scatter({...}, points, "drop masses, side view", "x (mm)", "z (mm)");   // snapshots
//   plot.waveform({...}, samples, sample_rate);                          // min/max per pixel column
//   plot.spectrogram({...}, samples, sample_rate);                       // STFT magnitude in dB
//   std::string svg = plot.str();                                        // the document
//
// The spectrogram: Hann-windowed STFT (Eigen's FFT), 1024-point frames, hop chosen for about one frame
// per 4 pixels; magnitude in dB, 80 dB range below the loudest bin, drawn as grey rectangles on a
// logarithmic frequency axis from 20 Hz to Nyquist (a membrane's modes and a drop's clicks both show).

#include <string>
#include <vector>

namespace ameoto::client {

struct PlotBox {
    double x = 0, y = 0, width = 100, height = 100;
};

struct PlotPoint {
    double x = 0, y = 0;
    int group = 0;   // colour index: e.g. one per snapshot time
};

class SvgPlot {
public:
    SvgPlot(double width, double height, const std::string& title);

    void series(PlotBox box, const std::vector<double>& x, const std::vector<double>& y, const std::string& label,
                const std::string& x_label);
    void scatter(PlotBox box, const std::vector<PlotPoint>& points, const std::string& label, const std::string& x_label,
                 const std::string& y_label);
    void waveform(PlotBox box, const std::vector<float>& samples, double sample_rate);
    void spectrogram(PlotBox box, const std::vector<float>& samples, double sample_rate);

    std::string str() const;

private:
    void frame(PlotBox box, const std::string& label);
    void axis_ticks(PlotBox box, double x_min, double x_max, double y_min, double y_max, const std::string& x_label,
                    const std::string& y_label);
    double width_, height_;
    std::string body_;
};

// Escapes text for SVG/XML.
std::string xml_escape(const std::string& text);

// Spectrogram data (exposed for tests): frames x bins magnitudes in dB, and the frame hop in samples.
struct Spectrogram {
    int frames = 0, bins = 0, hop = 0, size = 0;
    std::vector<float> db;   // frames * bins, frame-major
};
Spectrogram compute_spectrogram(const std::vector<float>& samples, int frame_size, int hop);

}  // namespace ameoto::client
