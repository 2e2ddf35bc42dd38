// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/bench_accuracy_charts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "clients/ameoto/svg_plot.hpp"

namespace ameoto::client {

namespace {

const char* const colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};

std::string fmt(const char* f, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, f, a, b, c, d);
    return buffer;
}

std::string text(double x, double y, const std::string& s, const char* anchor = "middle", int size = 11,
                 const char* extra = "") {
    return fmt("<text x=\"%.1f\" y=\"%.1f\" font-size=\"", x, y) + std::to_string(size) + "\" text-anchor=\"" + anchor +
           "\" font-family=\"sans-serif\"" + extra + ">" + xml_escape(s) + "</text>\n";
}

std::string tick_label(double v) {
    char buffer[32];
    if (v >= 1e4 || v < 1e-2) std::snprintf(buffer, sizeof buffer, "1e%d", static_cast<int>(std::lround(std::log10(v))));
    else std::snprintf(buffer, sizeof buffer, "%g", v);
    return buffer;
}

// A log-log frame: maps values to pixels and draws decades.
struct LogFrame {
    double x, y, w, h, x0, x1, y0, y1;   // box and decade range (log10)
    double px(double v) const { return x + (std::log10(v) - x0) / (x1 - x0) * w; }
    double py(double v) const { return y + h - (std::log10(v) - y0) / (y1 - y0) * h; }
    std::string draw(const std::string& x_label, const std::string& y_label) const {
        std::string s = fmt("<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"#333\"/>\n", x, y, w, h);
        for (int d = static_cast<int>(std::floor(x0)); d <= static_cast<int>(std::ceil(x1)); ++d) {
            const double v = std::pow(10.0, d);
            if (std::log10(v) < x0 - 1e-9 || std::log10(v) > x1 + 1e-9) continue;
            s += fmt("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", px(v), y, px(v), y + h);
            s += text(px(v), y + h + 15, tick_label(v));
        }
        for (int d = static_cast<int>(std::floor(y0)); d <= static_cast<int>(std::ceil(y1)); ++d) {
            const double v = std::pow(10.0, d);
            if (std::log10(v) < y0 - 1e-9 || std::log10(v) > y1 + 1e-9) continue;
            s += fmt("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", x, py(v), x + w, py(v));
            s += text(x - 6, py(v) + 4, tick_label(v), "end");
        }
        s += text(x + w / 2, y + h + 34, x_label);
        s += fmt("<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" text-anchor=\"middle\" font-family=\"sans-serif\" "
                 "transform=\"rotate(-90 %.1f %.1f)\">", x - 42, y + h / 2, x - 42, y + h / 2) +
             xml_escape(y_label) + "</text>\n";
        return s;
    }
};

std::string header(double width, double height, const std::string& title) {
    return fmt("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\">\n", width,
               height, width, height) +
           fmt("<rect width=\"%.0f\" height=\"%.0f\" fill=\"white\"/>\n", width, height) + text(width / 2, 22, title, "middle", 14);
}

}  // namespace

std::string cost_error_chart(const std::string& title, const std::vector<LogPanel>& panels) {
    const double panel_w = 520, panel_h = 420, left = 70, top = 50, row_h = panel_h + 100;
    const std::size_t columns = std::min<std::size_t>(panels.size(), 2), rows = (panels.size() + 1) / 2;
    std::string s = header(left + columns * (panel_w + 90), top + rows * row_h - 40, title);
    for (std::size_t p = 0; p < panels.size(); ++p) {
        const LogPanel& panel = panels[p];
        double cmin = std::numeric_limits<double>::infinity(), cmax = 0, emin = std::numeric_limits<double>::infinity(), emax = 0;
        for (const ChartPoint& c : panel.points) {
            if (!(c.cost > 0) || !std::isfinite(c.cost)) continue;
            cmin = std::min(cmin, c.cost);
            cmax = std::max(cmax, c.cost);
            const double e = std::max(c.error, panel.floor);
            if (std::isfinite(e)) {
                emin = std::min(emin, e);
                emax = std::max(emax, e);
            }
        }
        if (!(cmax > 0) || !(emax > 0)) continue;
        const LogFrame f{left + (p % 2) * (panel_w + 90), top + (p / 2) * row_h, panel_w, panel_h, std::floor(std::log10(cmin)),
                         std::ceil(std::log10(cmax) + 0.05), std::floor(std::log10(emin)), std::ceil(std::log10(emax) + 0.05)};
        s += f.draw(panel.x_label, panel.y_label + " (log)");
        if (!panel.heading.empty()) s += text(f.x + f.w / 2, f.y - 8, panel.heading, "middle", 12);
        // The front: cheapest first, a staircase (right, then down).
        std::vector<ChartPoint> front;
        for (const ChartPoint& c : panel.points)
            if (c.front && std::isfinite(c.error)) front.push_back(c);
        std::sort(front.begin(), front.end(), [](const ChartPoint& a, const ChartPoint& b) { return a.cost < b.cost; });
        if (!front.empty()) {
            std::string path = fmt("M %.1f %.1f", f.px(front[0].cost), f.py(std::max(front[0].error, panel.floor)));
            for (std::size_t i = 1; i < front.size(); ++i) {
                path += fmt(" H %.1f V %.1f", f.px(front[i].cost), f.py(std::max(front[i].error, panel.floor)));
            }
            s += "<path d=\"" + path + "\" fill=\"none\" stroke=\"#2ca02c\" stroke-width=\"2\" stroke-dasharray=\"6 3\"/>\n";
            s += text(f.x + f.w - 8, f.y + 16, "dashed: Pareto front", "end", 11, " fill=\"#2ca02c\"");
        }
        // Labels: the first of eight places around the marker that overlaps no label or marker placed so far.
        struct Box {
            double x0, y0, x1, y1;
            bool hits(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
        };
        std::vector<Box> taken;
        for (const ChartPoint& c : panel.points)
            if (c.cost > 0 && std::isfinite(c.error)) {
                const double x = f.px(c.cost), y = f.py(std::max(c.error, panel.floor));
                taken.push_back({x - 5, y - 5, x + 5, y + 5});
            }
        std::vector<std::string> omitted;
        for (const ChartPoint& c : panel.points) {
            if (!(c.cost > 0) || !std::isfinite(c.error)) {
                omitted.push_back(c.label);
                continue;
            }
            const double e = std::max(c.error, panel.floor);
            const double x = f.px(c.cost), y = f.py(e);
            const std::string colour = !c.colour.empty() ? c.colour : c.front ? "#2ca02c" : "#1f77b4";
            s += fmt("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4.5\" fill=\"", x, y) + colour + "\" stroke=\"#000\" stroke-width=\"0.6\"/>\n";
            if (c.error < panel.floor)
                s += fmt("<path d=\"M %.1f %.1f v 12 m -4 -5 l 4 5 l 4 -5\" fill=\"none\" stroke=\"#333\"/>\n", x, y + 5);
            if (c.label.empty()) continue;   // a marker only: one of a cluster that a neighbour's label names
            const double width = 5.6 * static_cast<double>(c.label.size()), height = 11;
            const double places[][2] = {{7, -6}, {-7, -6}, {7, 14}, {-7, 14}, {7, -18}, {-7, -18}, {7, 26}, {-7, 26}};
            int chosen = 0;
            for (int k = 0; k < 8; ++k) {
                const bool right = places[k][0] > 0;
                const double lx = x + places[k][0], ly = y + places[k][1];
                const Box b{right ? lx : lx - width, ly - height + 2, right ? lx + width : lx, ly + 2};
                bool free = b.x0 >= f.x && b.x1 <= f.x + f.w;
                for (const Box& t : taken) free = free && !b.hits(t);
                if (free) {
                    chosen = k;
                    break;
                }
            }
            const bool right = places[chosen][0] > 0;
            const double lx = x + places[chosen][0], ly = y + places[chosen][1];
            taken.push_back({right ? lx : lx - width, ly - height + 2, right ? lx + width : lx, ly + 2});
            s += text(lx, ly, c.label, right ? "start" : "end", 10);
        }
        // Notes in the bottom-left corner: cheap and exact is where no method has been yet.
        const double note_y = f.y + f.h - 40;
        s += text(f.x + 8, note_y, panel.floor_note, "start", 10, " fill=\"#555\"");
        if (!omitted.empty()) {
            std::string list;
            for (const std::string& o : omitted) list += (list.empty() ? "" : ", ") + o;
            s += text(f.x + 8, note_y + 14, panel.omitted_note, "start", 10, " fill=\"#555\"");
            s += text(f.x + 8, note_y + 28, list, "start", 10, " fill=\"#555\"");
        }
    }
    return s + "</svg>\n";
}

std::string stability_chart(const std::string& title, const std::vector<StabilitySeries>& series) {
    const double left = 80, top = 50, w = 640, h = 420;
    std::string s = header(left + w + 230, top + h + 60, title);
    const LogFrame f{left, top, w, h, -1.0, 1.0, std::log10(0.5), 1.0};
    s += f.draw("omega_max T (log)", "amplitude growth factor per step (log)");
    for (double v : {0.5, 2.0, 5.0}) {   // between the decades: the axis spans only 1.3 of them
        s += fmt("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#eee\"/>\n", f.x, f.py(v), f.x + f.w, f.py(v));
        s += text(f.x - 6, f.py(v) + 4, tick_label(v), "end");
    }
    auto clamp_y = [](double v) { return std::clamp(v, 0.5, 10.0); };
    s += fmt("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#999\" stroke-dasharray=\"4 4\"/>\n", f.px(2.0), f.y,
             f.px(2.0), f.y + f.h);
    s += text(f.px(2.0) + 4, f.y + 14, "omega T = 2", "start", 10);
    s += fmt("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#999\"/>\n", f.x, f.py(1.0), f.x + f.w, f.py(1.0));
    for (std::size_t k = 0; k < series.size(); ++k) {
        const StabilitySeries& c = series[k];
        const char* colour = colours[k % 8];
        const double offset = 1.0 + 0.012 * (static_cast<double>(k) - 2.0);   // keeps overlapping markers apart
        std::string line;
        for (std::size_t i = 0; i < c.omega_t.size(); ++i) {
            line += (i == 0 ? "M " : " L ") + fmt("%.1f %.1f", f.px(c.omega_t[i]), f.py(clamp_y(c.theory[i] * offset)));
            const double m = c.measured[i];
            const double y = f.py(clamp_y(std::isfinite(m) ? m : 10.0));
            // Series with equal values (explicit Verlet and symplectic Euler share one bound and one growth)
            // stay visible side by side: each series' markers shifted a few pixels.
            const double shift = 3.0 * (static_cast<double>(k) - 2.0);
            s += fmt("<rect x=\"%.1f\" y=\"%.1f\" width=\"6\" height=\"6\" fill=\"", f.px(c.omega_t[i]) - 3 + shift, y - 3) + colour +
                 "\" stroke=\"#000\" stroke-width=\"0.4\"/>\n";
        }
        s += "<path d=\"" + line + "\" fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"1.5\" opacity=\"0.8\"" +
             (k % 2 ? " stroke-dasharray=\"6 4\"" : "") + "/>\n";
        const double ly = top + 20 + 22.0 * static_cast<double>(k);
        s += fmt("<rect x=\"%.1f\" y=\"%.1f\" width=\"10\" height=\"10\" fill=\"", left + w + 20, ly - 9) + colour + "\"/>\n";
        s += text(left + w + 36, ly, c.name, "start");
    }
    s += text(left + w + 20, top + 20 + 22.0 * series.size() + 10, "squares: measured", "start", 10);
    s += text(left + w + 20, top + 20 + 22.0 * series.size() + 26, "lines: theoretical bound", "start", 10);
    s += text(left + w + 20, top + 20 + 22.0 * series.size() + 42, "(above 10 and below 0.5:", "start", 10);
    s += text(left + w + 20, top + 20 + 22.0 * series.size() + 56, "drawn at the edge)", "start", 10);
    return s + "</svg>\n";
}

}  // namespace ameoto::client
