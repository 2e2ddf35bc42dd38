// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/svg_plot.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace ameoto::client;

TEST_CASE("the spectrogram puts a sine's energy in its bin") {
    const double rate = 48000.0, f = 3000.0;
    std::vector<float> x(48000);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<float>(std::sin(2.0 * M_PI * f * static_cast<double>(i) / rate));
    const Spectrogram s = compute_spectrogram(x, 1024, 512);
    REQUIRE(s.frames == 1 + (48000 - 1024) / 512);
    REQUIRE(s.bins == 513);
    // The loudest bin of a middle frame is the sine's: bin = f / (rate / size) = 64 (exact here).
    const int frame = s.frames / 2;
    int loudest = 0;
    for (int k = 1; k < s.bins; ++k)
        if (s.db[static_cast<std::size_t>(frame * s.bins + k)] > s.db[static_cast<std::size_t>(frame * s.bins + loudest)]) loudest = k;
    CHECK(loudest == 64);
    // Far from it, the Hann window's leakage is more than 60 dB down.
    CHECK(s.db[static_cast<std::size_t>(frame * s.bins + 64)] - s.db[static_cast<std::size_t>(frame * s.bins + 200)] > 60.0f);
}

TEST_CASE("an SVG document holds every plot, escapes text, and maps values into its boxes") {
    SvgPlot plot(600, 400, "5 mm water & nylon <test>");
    plot.series({50, 40, 500, 80}, {0.0, 0.01, 0.02}, {1, 3, 5}, "pieces", "time (s)");
    plot.scatter({50, 160, 200, 200}, {{0, 0, 0}, {1, 1, 1}}, "masses", "x (mm)", "z (mm)");
    std::vector<float> wave(4800);
    for (std::size_t i = 0; i < wave.size(); ++i) wave[i] = static_cast<float>(std::sin(0.05 * static_cast<double>(i)));
    plot.waveform({300, 160, 250, 80}, wave, 48000.0);
    plot.spectrogram({300, 280, 250, 100}, wave, 48000.0);
    const std::string svg = plot.str();
    CHECK(svg.rfind("<?xml", 0) == 0);
    CHECK(svg.find("</svg>") != std::string::npos);
    CHECK(svg.find("5 mm water &amp; nylon &lt;test&gt;") != std::string::npos);
    CHECK(svg.find("<circle") != std::string::npos);
    CHECK(svg.find("<path d=\"M50.00,") != std::string::npos);   // the series starts at the box's left edge
    CHECK(svg.find("fill=\"#") != std::string::npos);           // spectrogram cells drawn
    CHECK(svg.find("nan") == std::string::npos);
}
