// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/svg_plot.hpp"

#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>

namespace ameoto::client {
namespace {

constexpr const char* palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2"};

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.2f", v);
    return b;
}

std::string short_num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3g", v);
    return b;
}

}  // namespace

std::string xml_escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

SvgPlot::SvgPlot(double width, double height, const std::string& title) : width_(width), height_(height) {
    body_ += "<text x=\"" + num(width / 2) + "\" y=\"22\" text-anchor=\"middle\" font-size=\"16\">" + xml_escape(title) + "</text>\n";
}

void SvgPlot::frame(PlotBox b, const std::string& label) {
    body_ += "<rect x=\"" + num(b.x) + "\" y=\"" + num(b.y) + "\" width=\"" + num(b.width) + "\" height=\"" + num(b.height) +
             "\" fill=\"none\" stroke=\"#444\"/>\n";
    body_ += "<text x=\"" + num(b.x) + "\" y=\"" + num(b.y - 6) + "\" font-size=\"12\">" + xml_escape(label) + "</text>\n";
}

void SvgPlot::axis_ticks(PlotBox b, double x_min, double x_max, double y_min, double y_max, const std::string& x_label,
                         const std::string& y_label) {
    body_ += "<text x=\"" + num(b.x) + "\" y=\"" + num(b.y + b.height + 14) + "\" font-size=\"10\">" + short_num(x_min) + "</text>\n";
    body_ += "<text x=\"" + num(b.x + b.width) + "\" y=\"" + num(b.y + b.height + 14) + "\" font-size=\"10\" text-anchor=\"end\">" +
             short_num(x_max) + "</text>\n";
    body_ += "<text x=\"" + num(b.x + b.width / 2) + "\" y=\"" + num(b.y + b.height + 14) +
             "\" font-size=\"10\" text-anchor=\"middle\">" + xml_escape(x_label) + "</text>\n";
    body_ += "<text x=\"" + num(b.x - 4) + "\" y=\"" + num(b.y + 10) + "\" font-size=\"10\" text-anchor=\"end\">" + short_num(y_max) + "</text>\n";
    body_ += "<text x=\"" + num(b.x - 4) + "\" y=\"" + num(b.y + b.height) + "\" font-size=\"10\" text-anchor=\"end\">" + short_num(y_min) +
             "</text>\n";
    if (!y_label.empty())
        body_ += "<text x=\"" + num(b.x - 4) + "\" y=\"" + num(b.y + b.height / 2) + "\" font-size=\"10\" text-anchor=\"end\">" +
                 xml_escape(y_label) + "</text>\n";
}

void SvgPlot::series(PlotBox b, const std::vector<double>& x, const std::vector<double>& y, const std::string& label,
                     const std::string& x_label) {
    frame(b, label);
    if (x.empty() || x.size() != y.size()) return;
    const double x0 = x.front(), x1 = std::max(x.back(), x0 + 1e-12);
    double y0 = *std::min_element(y.begin(), y.end()), y1 = *std::max_element(y.begin(), y.end());
    if (y1 - y0 < 1e-12) y1 = y0 + 1.0;
    auto px = [&](double v) { return b.x + (v - x0) / (x1 - x0) * b.width; };
    auto py = [&](double v) { return b.y + b.height - (v - y0) / (y1 - y0) * b.height; };
    std::string path = "M" + num(px(x[0])) + "," + num(py(y[0]));
    for (std::size_t i = 1; i < x.size(); ++i) path += " H" + num(px(x[i])) + " V" + num(py(y[i]));   // a step line
    body_ += "<path d=\"" + path + "\" fill=\"none\" stroke=\"" + palette[0] + "\" stroke-width=\"1.5\"/>\n";
    axis_ticks(b, x0, x1, y0, y1, x_label, "");
}

void SvgPlot::scatter(PlotBox b, const std::vector<PlotPoint>& points, const std::string& label, const std::string& x_label,
                      const std::string& y_label) {
    frame(b, label);
    if (points.empty()) return;
    double x0 = points[0].x, x1 = x0, y0 = points[0].y, y1 = y0;
    for (const auto& p : points) {
        x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    }
    // Equal scales on both axes, so a round drop looks round.
    const double span = std::max({x1 - x0, y1 - y0, 1e-9}) * 1.1;
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    const double scale = std::min(b.width, b.height) / span;
    for (const auto& p : points) {
        const double sx = b.x + b.width / 2 + (p.x - cx) * scale;
        const double sy = b.y + b.height / 2 - (p.y - cy) * scale;
        body_ += "<circle cx=\"" + num(sx) + "\" cy=\"" + num(sy) + "\" r=\"1.6\" fill=\"" + palette[p.group % 8] + "\"/>\n";
    }
    axis_ticks(b, cx - span / 2, cx + span / 2, cy - span / 2, cy + span / 2, x_label, y_label);
}

void SvgPlot::waveform(PlotBox b, const std::vector<float>& samples, double sample_rate) {
    frame(b, "waveform");
    if (samples.empty()) return;
    float peak = 1e-12f;
    for (float s : samples) peak = std::max(peak, std::fabs(s));
    const int columns = std::max(1, static_cast<int>(b.width));
    std::string path;
    for (int c = 0; c < columns; ++c) {
        const std::size_t from = samples.size() * static_cast<std::size_t>(c) / static_cast<std::size_t>(columns);
        const std::size_t to = std::max(from + 1, samples.size() * static_cast<std::size_t>(c + 1) / static_cast<std::size_t>(columns));
        float lo = samples[from], hi = samples[from];
        for (std::size_t i = from; i < to && i < samples.size(); ++i) lo = std::min(lo, samples[i]), hi = std::max(hi, samples[i]);
        const double x = b.x + c + 0.5;
        // Appended piece by piece: "M" + std::string&& trips GCC 12's false -Wrestrict (bug 105329).
        path += 'M';
        path += num(x);
        path += ',';
        path += num(b.y + b.height / 2 - hi / peak * b.height / 2);
        path += " V";
        path += num(b.y + b.height / 2 - lo / peak * b.height / 2 + 0.5);
        path += ' ';
    }
    body_ += "<path d=\"" + path + "\" stroke=\"" + palette[0] + "\" stroke-width=\"1\"/>\n";
    axis_ticks(b, 0.0, static_cast<double>(samples.size()) / sample_rate, -peak, peak, "time (s)", "");
}

Spectrogram compute_spectrogram(const std::vector<float>& samples, int frame_size, int hop) {
    Spectrogram s;
    s.size = frame_size;
    s.hop = std::max(1, hop);
    s.bins = frame_size / 2 + 1;
    if (samples.size() < static_cast<std::size_t>(frame_size)) return s;
    s.frames = 1 + static_cast<int>((samples.size() - static_cast<std::size_t>(frame_size)) / static_cast<std::size_t>(s.hop));
    s.db.assign(static_cast<std::size_t>(s.frames) * static_cast<std::size_t>(s.bins), -300.0f);
    Eigen::FFT<float> fft;
    std::vector<float> frame(static_cast<std::size_t>(frame_size));
    std::vector<std::complex<float>> spectrum;
    for (int f = 0; f < s.frames; ++f) {
        for (int i = 0; i < frame_size; ++i) {
            const float hann = 0.5f - 0.5f * std::cos(2.0f * 3.14159265f * static_cast<float>(i) / static_cast<float>(frame_size));
            frame[static_cast<std::size_t>(i)] = hann * samples[static_cast<std::size_t>(f * s.hop + i)];
        }
        fft.fwd(spectrum, frame);
        for (int k = 0; k < s.bins; ++k) {
            const float magnitude = std::abs(spectrum[static_cast<std::size_t>(k)]);
            s.db[static_cast<std::size_t>(f * s.bins + k)] = 20.0f * std::log10(magnitude + 1e-30f);
        }
    }
    return s;
}

void SvgPlot::spectrogram(PlotBox b, const std::vector<float>& samples, double sample_rate) {
    frame(b, "spectrogram (80 dB range, log frequency)");
    const int size = 1024;
    const int columns = std::max(1, static_cast<int>(b.width / 4));
    const int hop = std::max(1, static_cast<int>((samples.size() > size ? samples.size() - size : 0) / static_cast<std::size_t>(columns)));
    const Spectrogram s = compute_spectrogram(samples, size, hop);
    if (s.frames == 0) return;
    const float top = *std::max_element(s.db.begin(), s.db.end());
    // Rows on a logarithmic frequency axis from 20 Hz to Nyquist (a membrane's modes sit in the lowest
    // few percent of a linear axis); each row shows the loudest bin in its band.
    const int rows = 96;
    const double f_low = 20.0, nyquist = sample_rate / 2, bin_hz = sample_rate / s.size;
    auto row_bin = [&](int r) { return static_cast<int>(f_low * std::pow(nyquist / f_low, static_cast<double>(r) / rows) / bin_hz); };
    const double cell_w = b.width / s.frames, cell_h = b.height / rows;
    for (int f = 0; f < s.frames; ++f) {
        for (int r = 0; r < rows; ++r) {
            const int k0 = std::min(row_bin(r), s.bins - 1), k1 = std::min(std::max(k0 + 1, row_bin(r + 1)), s.bins);
            float level = -300.0f;
            for (int k = k0; k < k1; ++k) level = std::max(level, s.db[static_cast<std::size_t>(f * s.bins + k)]);
            const double shade = std::clamp((level - (top - 80.0f)) / 80.0f, 0.0f, 1.0f);
            if (shade <= 0.02) continue;   // background stays white: a smaller file
            const int grey = static_cast<int>(255.0 * (1.0 - shade));
            char colour[16];
            std::snprintf(colour, sizeof colour, "#%02x%02x%02x", grey, grey, grey);
            body_ += "<rect x=\"" + num(b.x + f * cell_w) + "\" y=\"" + num(b.y + b.height - (r + 1) * cell_h) + "\" width=\"" +
                     num(cell_w + 0.3) + "\" height=\"" + num(cell_h + 0.3) + "\" fill=\"" + colour + "\"/>\n";
        }
    }
    axis_ticks(b, 0.0, static_cast<double>(samples.size()) / sample_rate, f_low, nyquist, "time (s)", "Hz (log)");
}

std::string SvgPlot::str() const {
    return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(width_) +
           "\" height=\"" + num(height_) + "\" viewBox=\"0 0 " + num(width_) + " " + num(height_) +
           "\" font-family=\"sans-serif\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n" + body_ + "</svg>\n";
}

}  // namespace ameoto::client
