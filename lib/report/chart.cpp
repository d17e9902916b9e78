// Line charts, histograms and strip charts on a Canvas.

#include "report/chart.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "stats/summary.hpp"

namespace stepstone::report {

namespace {

constexpr double kTitleSize = 17.0;
constexpr double kLabelSize = 14.0;
constexpr double kTickSize = 12.0;
constexpr Colour kGrid = Colour::hex(0xE3E3E3);
constexpr Colour kAxis = Colour::hex(0x555555);

struct Bounds {
    double low = std::numeric_limits<double>::infinity();
    double high = -std::numeric_limits<double>::infinity();
    void add(double v) {
        if (!std::isfinite(v)) return;
        low = std::min(low, v);
        high = std::max(high, v);
    }
    void add(std::span<const double> values) {
        for (const double v : values) add(v);
    }
    bool empty() const { return low > high; }
};

// the largest size <= `size` at which `text` fits in `room` pixels (at least 9)
double fit(const Canvas& canvas, const std::string& text, double size, double room, bool bold = false) {
    const double width = canvas.text_width(text, size, bold);
    return width <= room ? size : std::max(9.0, size * room / width);
}

}  // namespace

Chart::Chart(Canvas& canvas, const ChartFrame& frame, double x0, double x1, double y0, double y1)
    : canvas_(canvas) {
    if (frame.x_range) std::tie(x0, x1) = *frame.x_range;
    if (frame.y_range) std::tie(y0, y1) = *frame.y_range;
    x_ticks_ = nice_ticks(x0, x1, 8);
    y_ticks_ = nice_ticks(y0, y1, 6);

    const double ox = frame.region ? (*frame.region)[0] : 0.0;
    const double oy = frame.region ? (*frame.region)[1] : 0.0;
    const double width = frame.region ? (*frame.region)[2] : canvas.width();
    const double height = frame.region ? (*frame.region)[3] : canvas.height();
    if (!frame.region) canvas.fill(kWhite);
    // room for the widest y tick label
    double label_width = 0.0;
    for (const double v : y_ticks_.values) label_width = std::max(label_width, canvas.text_width(y_ticks_.label(v), kTickSize));
    left_ = ox + 30.0 + label_width + 14.0;
    right_ = ox + width - 24.0;
    top_ = oy + (frame.title.empty() ? 20.0 : 48.0);
    bottom_ = oy + height - 58.0 - frame.below;
    x_scale_ = {x_ticks_.low, x_ticks_.high, left_, right_};
    y_scale_ = {y_ticks_.low, y_ticks_.high, bottom_, top_};

    cairo_t* cr = canvas.cr();
    if (!frame.title.empty()) {
        const double size = fit(canvas, frame.title, kTitleSize, width - 20.0, true);
        canvas.text(ox + width / 2.0, oy + 14.0, frame.title, size, kText, 0.5, 0.0, true);
    }
    cairo_set_line_width(cr, 1.0);
    canvas.set_colour(kGrid);
    for (const double v : y_ticks_.values) {
        cairo_move_to(cr, left_, std::round(py(v)) + 0.5);
        cairo_line_to(cr, right_, std::round(py(v)) + 0.5);
    }
    for (const double v : x_ticks_.values) {
        cairo_move_to(cr, std::round(px(v)) + 0.5, top_);
        cairo_line_to(cr, std::round(px(v)) + 0.5, bottom_);
    }
    cairo_stroke(cr);
    canvas.set_colour(kAxis);
    cairo_rectangle(cr, left_ + 0.5, top_ + 0.5, right_ - left_ - 1.0, bottom_ - top_ - 1.0);
    cairo_stroke(cr);
    for (const double v : y_ticks_.values) {
        cairo_move_to(cr, left_ - 5.0, std::round(py(v)) + 0.5);
        cairo_line_to(cr, left_, std::round(py(v)) + 0.5);
        canvas.text(left_ - 8.0, py(v), y_ticks_.label(v), kTickSize, kText, 1.0, 0.5);
    }
    for (const double v : x_ticks_.values) {
        cairo_move_to(cr, std::round(px(v)) + 0.5, bottom_);
        cairo_line_to(cr, std::round(px(v)) + 0.5, bottom_ + 5.0);
        if (frame.x_tick_labels) canvas.text(px(v), bottom_ + 8.0, x_ticks_.label(v), kTickSize, kText, 0.5, 0.0);
    }
    canvas.set_colour(kAxis);
    cairo_stroke(cr);
    canvas.text((left_ + right_) / 2.0, bottom_ + 50.0, frame.x_label, kLabelSize, kText, 0.5, 1.0);
    canvas.text(ox + 12.0, (top_ + bottom_) / 2.0, frame.y_label,
                fit(canvas, frame.y_label, kLabelSize, bottom_ - top_ + 40.0), kText, 0.5, 0.0, false,
                -M_PI / 2.0);
}

void Chart::clip() {
    cairo_save(canvas_.cr());
    cairo_rectangle(canvas_.cr(), left_, top_, right_ - left_, bottom_ - top_);
    cairo_clip(canvas_.cr());
}

void Chart::release_clip() { cairo_restore(canvas_.cr()); }

void Chart::curve(const Curve& c) {
    cairo_t* cr = canvas_.cr();
    const std::size_t n = std::min(c.x.size(), c.y.size());
    if (n == 0) return;
    clip();
    auto trace = [&](const std::vector<double>& ys, bool reverse) {
        for (std::size_t k = 0; k < n; ++k) {
            const std::size_t i = reverse ? n - 1 - k : k;
            const double x = px(c.x[i]);
            const double y = py(ys[i]);
            if (!c.steps) {
                cairo_line_to(cr, x, y);
                continue;
            }
            // hold each value until the next x (walking backwards: from the next x)
            const std::size_t next = reverse ? (i + 1 < n ? i + 1 : i) : i;
            if (reverse) {
                cairo_line_to(cr, px(c.x[next]), y);
                cairo_line_to(cr, x, y);
            } else {
                cairo_line_to(cr, x, y);
                if (i + 1 < n) cairo_line_to(cr, px(c.x[i + 1]), y);
            }
        }
    };
    if (c.low.size() == n && c.high.size() == n) {
        cairo_new_path(cr);
        trace(c.high, false);
        trace(c.low, true);
        cairo_close_path(cr);
        canvas_.set_colour(c.colour, 0.22);
        cairo_fill(cr);
    }
    cairo_new_path(cr);
    if (n == 1) {
        cairo_arc(cr, px(c.x[0]), py(c.y[0]), 3.0, 0.0, 2.0 * M_PI);
        canvas_.set_colour(c.colour);
        cairo_fill(cr);
    } else {
        trace(c.y, false);
        canvas_.set_colour(c.colour);
        cairo_set_line_width(cr, c.width);
        if (c.dashed) {
            const double dashes[] = {7.0, 4.0};
            cairo_set_dash(cr, dashes, 2, 0.0);
        }
        cairo_stroke(cr);
        cairo_set_dash(cr, nullptr, 0, 0.0);
    }
    release_clip();
}

void Chart::bar(double x0, double x1, double height, Colour colour) {
    cairo_t* cr = canvas_.cr();
    const double base = py(std::max(0.0, y_ticks_.low));
    cairo_rectangle(cr, px(x0) + 0.5, py(height), std::max(px(x1) - px(x0) - 1.0, 1.0), base - py(height));
    canvas_.set_colour(colour);
    cairo_fill(cr);
}

void Chart::point(double x, double y, double radius, Colour colour, double alpha) {
    cairo_t* cr = canvas_.cr();
    cairo_new_path(cr);
    cairo_arc(cr, px(x), py(y), radius, 0.0, 2.0 * M_PI);
    canvas_.set_colour(colour, alpha);
    cairo_fill_preserve(cr);
    canvas_.set_colour(colour);
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
}

void Chart::reference(double y, const std::string& label) {
    cairo_t* cr = canvas_.cr();
    const double dashes[] = {5.0, 4.0};
    cairo_set_dash(cr, dashes, 2, 0.0);
    cairo_set_line_width(cr, 1.3);
    canvas_.set_colour(kGrey);
    cairo_move_to(cr, left_, py(y));
    cairo_line_to(cr, right_, py(y));
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0.0);
    canvas_.text(right_ - 4.0, py(y) - 3.0, label, kTickSize, kGrey, 1.0, 1.0);
}

namespace {

constexpr double kLegendRow = 19.0;

}  // namespace

std::array<double, 4> Chart::legend_box(std::span<const std::pair<std::string, Colour>> entries, bool right,
                                        bool bottom) const {
    double width = 0.0;
    for (const auto& [name, colour] : entries) width = std::max(width, canvas_.text_width(name, kTickSize));
    const double box_w = width + 44.0;
    const double box_h = kLegendRow * static_cast<double>(entries.size()) + 10.0;
    const double x = right ? right_ - box_w - 10.0 : left_ + 10.0;
    const double y = bottom ? bottom_ - box_h - 10.0 : top_ + 10.0;
    return {x, y, box_w, box_h};
}

void Chart::legend_off(std::span<const std::pair<std::string, Colour>> entries,
                       std::span<const Curve> curves) {
    if (entries.empty()) return;
    // (right, bottom) in the order ties are broken
    constexpr std::array<std::pair<bool, bool>, 4> corners = {
        {{false, false}, {true, false}, {true, true}, {false, true}}};
    std::size_t best = 0, fewest = std::numeric_limits<std::size_t>::max();
    for (std::size_t k = 0; k < corners.size(); ++k) {
        const auto [x, y, w, h] = legend_box(entries, corners[k].first, corners[k].second);
        std::size_t covered = 0;
        const auto count = [&](double dx, double dy) {
            const double u = px(dx), v = py(dy);
            covered += (u >= x && u <= x + w && v >= y && v <= y + h) ? 1 : 0;
        };
        for (const auto& c : curves) {
            for (const auto* ys : {&c.y, &c.low, &c.high}) {
                if (ys->size() != c.x.size()) continue;
                for (std::size_t i = 0; i < c.x.size(); ++i) {
                    count(c.x[i], (*ys)[i]);
                    // points along the segment to the next point, so a sparse line counts where it passes
                    if (i + 1 < c.x.size()) {
                        for (double t : {0.25, 0.5, 0.75}) {
                            count(c.x[i] + t * (c.x[i + 1] - c.x[i]),
                                  (*ys)[i] + t * ((*ys)[i + 1] - (*ys)[i]));
                        }
                    }
                }
            }
        }
        if (covered < fewest) {
            fewest = covered;
            best = k;
        }
    }
    legend(entries, corners[best].first, corners[best].second);
}

void Chart::legend(std::span<const std::pair<std::string, Colour>> entries, bool right, bool bottom) {
    if (entries.empty()) return;
    cairo_t* cr = canvas_.cr();
    const double row = kLegendRow;
    const auto [x, y, box_w, box_h] = legend_box(entries, right, bottom);
    cairo_rectangle(cr, x, y, box_w, box_h);
    canvas_.set_colour(kWhite, 0.88);
    cairo_fill_preserve(cr);
    canvas_.set_colour(kGrid);
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const double cy = y + 5.0 + row * (static_cast<double>(i) + 0.5);
        cairo_rectangle(cr, x + 8.0, cy - 5.0, 20.0, 10.0);
        canvas_.set_colour(entries[i].second);
        cairo_fill(cr);
        canvas_.text(x + 36.0, cy, entries[i].first, kTickSize, kText, 0.0, 0.5);
    }
}

void line_chart(Canvas& canvas, const ChartFrame& frame, std::span<const Curve> curves) {
    Bounds xs, ys;
    for (const auto& c : curves) {
        xs.add(c.x);
        ys.add(c.y);
        ys.add(c.low);
        ys.add(c.high);
    }
    if (xs.empty()) xs = {0.0, 1.0};
    if (ys.empty()) ys = {0.0, 1.0};
    Chart chart(canvas, frame, xs.low, xs.high, std::min(ys.low, 0.0), ys.high);
    for (const auto& c : curves) chart.curve(c);
    chart.legend_off(legend_entries(curves), curves);
}

std::vector<std::pair<std::string, Colour>> legend_entries(std::span<const Curve> curves) {
    std::vector<std::pair<std::string, Colour>> entries;
    for (std::size_t i = 0; i < curves.size(); ++i) {
        const Curve& c = curves[i];
        if (c.name.empty()) continue;
        std::string name = c.name;
        for (std::size_t j = 0; j < i; ++j) {
            if (!c.x.empty() && curves[j].x == c.x && curves[j].y == c.y && !curves[j].name.empty()) {
                name += " (same line as " + curves[j].name + ")";
                break;
            }
        }
        entries.emplace_back(std::move(name), c.colour);
    }
    return entries;
}

void histogram_chart(Canvas& canvas, const ChartFrame& frame, std::span<const double> edges,
                     std::span<const double> counts, Colour colour) {
    Bounds ys;
    ys.add(counts);
    if (ys.empty()) ys = {0.0, 1.0};
    const double x0 = edges.empty() ? 0.0 : edges.front();
    const double x1 = edges.empty() ? 1.0 : edges.back();
    Chart chart(canvas, frame, x0, x1, 0.0, std::max(ys.high, 1.0));
    for (std::size_t i = 0; i + 1 < edges.size() && i < counts.size(); ++i) {
        if (counts[i] > 0) chart.bar(edges[i], edges[i + 1], counts[i], colour);
    }
}

void strip_chart(Canvas& canvas, const ChartFrame& frame, std::span<const Strip> strips,
                 std::optional<double> threshold) {
    Bounds ys;
    for (const auto& s : strips) ys.add(s.values);
    if (threshold) ys.add(*threshold);
    if (ys.empty()) ys = {0.0, 1.0};
    ChartFrame f = frame;
    const auto n = static_cast<double>(strips.size());
    f.x_range = std::pair{0.5, std::max(n, 1.0) + 0.5};
    f.x_tick_labels = false;  // the slots 1..n are labelled with the group names
    Chart chart(canvas, f, 0.5, n + 0.5, std::min(ys.low, 0.0), ys.high);
    cairo_t* cr = canvas.cr();
    if (threshold) chart.reference(*threshold, "success threshold");
    for (std::size_t g = 0; g < strips.size(); ++g) {
        const auto& s = strips[g];
        const double slot = static_cast<double>(g + 1);
        canvas.text(chart.px(slot), chart.py(chart.y_ticks().low) + 8.0, s.name, kLabelSize, kText, 0.5, 0.0);
        for (std::size_t i = 0; i < s.values.size(); ++i) {
            // a low-discrepancy spread in [-0.28, 0.28): the golden-ratio sequence
            const double u = std::fmod(0.5 + static_cast<double>(i) * 0.6180339887498949, 1.0);
            chart.point(slot + (u - 0.5) * 0.56, s.values[i], 4.5, s.colour, 0.55);
        }
        if (!s.values.empty()) {
            const double median = stats::summarize(s.values).median;
            cairo_set_line_width(cr, 3.0);
            canvas.set_colour(kBlack);
            cairo_move_to(cr, chart.px(slot - 0.34), chart.py(median));
            cairo_line_to(cr, chart.px(slot + 0.34), chart.py(median));
            cairo_stroke(cr);
        }
    }
}

}  // namespace stepstone::report
