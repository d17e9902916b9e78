#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "report/axis.hpp"
#include "report/canvas.hpp"

namespace stepstone::report {

/// Default figure size in pixels: readable at 800 px wide.
inline constexpr int kFigureWidth = 800;
inline constexpr int kFigureHeight = 460;

/// One line of a line chart, with an optional band (e.g. quartiles) around it.
struct Curve {
    std::string name;  ///< legend entry (empty: none)
    Colour colour = kBlue;
    std::vector<double> x, y;
    std::vector<double> low, high;  ///< the band, same length as x, or empty
    bool dashed = false;
    bool steps = false;  ///< drawn as a step function (value held until the next x)
    double width = 2.2;  ///< line width in pixels
};

/// What every chart has: a title, axis labels (with units) and data ranges.
/// A range left empty is taken from the data; both are widened to round ticks.
struct ChartFrame {
    std::string title;
    std::string x_label;
    std::string y_label;
    std::optional<std::pair<double, double>> x_range;
    std::optional<std::pair<double, double>> y_range;
    bool x_tick_labels = true;  ///< false: the caller labels the x axis itself
    /// The part of the canvas the chart takes, {x, y, width, height} in pixels
    /// (a panel of a figure); absent: the whole canvas, filled white first.
    std::optional<std::array<double, 4>> region = std::nullopt;
    /// Extra pixels left free under the x axis label (a table under the axis).
    double below = 0.0;
};

/// The plotting area of a chart drawn on a canvas: background, title, grid,
/// ticks at round numbers, axis labels, then the data in data coordinates.
class Chart {
public:
    /// Draws the frame for data within [x0, x1] x [y0, y1] (frame ranges win).
    Chart(Canvas& canvas, const ChartFrame& frame, double x0, double x1, double y0, double y1);

    double px(double x) const { return x_scale_(x); }
    double py(double y) const { return y_scale_(y); }
    /// The plotting area's edges in pixels.
    double left() const { return left_; }
    double right() const { return right_; }
    double bottom() const { return bottom_; }
    const Ticks& x_ticks() const { return x_ticks_; }
    const Ticks& y_ticks() const { return y_ticks_; }
    Canvas& canvas() const { return canvas_; }

    void curve(const Curve& curve);
    void bar(double x0, double x1, double height, Colour colour);
    void point(double x, double y, double radius, Colour colour, double alpha = 0.8);
    /// A horizontal reference line at y with a label at its right end.
    void reference(double y, const std::string& label);
    /// Legend entries in a box at the top left (or right) of the plotting
    /// area, or at its bottom with `bottom`.
    void legend(std::span<const std::pair<std::string, Colour>> entries, bool right = false,
                bool bottom = false);
    /// The legend's box of `entries` in the corner of the plotting area that
    /// covers the fewest points of `curves` (their lines and bands, sampled);
    /// ties keep the top left, then top right, bottom right, bottom left.
    void legend_off(std::span<const std::pair<std::string, Colour>> entries, std::span<const Curve> curves);
    /// The legend's box of `entries` in one corner: x, y, width, height in pixels.
    std::array<double, 4> legend_box(std::span<const std::pair<std::string, Colour>> entries, bool right,
                                     bool bottom) const;
    /// Clips drawing to the plotting area until release_clip().
    void clip();
    void release_clip();

private:
    Canvas& canvas_;
    Ticks x_ticks_, y_ticks_;
    Scale x_scale_, y_scale_;
    double left_, right_, top_, bottom_;
};

/// The legend entries of `curves`: each named curve's name and colour; a curve
/// drawn exactly over an earlier one (same points) says so, "mo (same line as
/// sum)", since only the later colour can be seen.
std::vector<std::pair<std::string, Colour>> legend_entries(std::span<const Curve> curves);

/// A line chart of `curves` (legend from their names, off the curves), on a new canvas.
void line_chart(Canvas& canvas, const ChartFrame& frame, std::span<const Curve> curves);

/// A histogram: bars over [edges[i], edges[i + 1]) of height counts[i].
void histogram_chart(Canvas& canvas, const ChartFrame& frame, std::span<const double> edges,
                     std::span<const double> counts, Colour colour);

/// One group of a strip chart.
struct Strip {
    std::string name;
    Colour colour;
    std::vector<double> values;
};
/// A strip chart: each group's values as jittered points around its slot on
/// the x axis, with its median as a bar; `threshold` (if set) as a dashed line.
/// The jitter is a fixed function of the point's index, so a figure redraws
/// identically.
void strip_chart(Canvas& canvas, const ChartFrame& frame, std::span<const Strip> strips,
                 std::optional<double> threshold);

}  // namespace stepstone::report
