#pragma once

#include <string>
#include <vector>

namespace stepstone::report {

/// The ticks of one axis: round numbers (1, 2 or 5 times a power of ten
/// apart) from `low` to `high`, which cover the data range asked for.
struct Ticks {
    double low = 0.0;   ///< first tick, <= the data's low end
    double high = 1.0;  ///< last tick, >= the data's high end
    double step = 0.2;  ///< distance between two ticks
    int decimals = 1;   ///< digits after the point that show every tick exactly
    std::vector<double> values;  ///< low, low + step, ..., high

    /// `value` written with `decimals` digits after the point ("0.25", "3000").
    std::string label(double value) const;
};

/// Ticks for data spanning [low, high], about `target` of them (Heckbert's
/// "nice numbers", Graphics Gems 1990): the range is rounded up to 1, 2, 5 or
/// 10 times a power of ten, divided by target - 1, and that step rounded to
/// the nearest of 1, 2, 5 or 10 times a power of ten; the axis then runs from
/// the multiple of the step at or below `low` to the one at or above `high`.
/// An empty range (low == high) is widened to [low - 1, low + 1] (or [0, 1]
/// for 0). Low and high are swapped if given in the wrong order; non-finite
/// input gives the ticks of [0, 1].
Ticks nice_ticks(double low, double high, int target = 6);

/// A linear map from data values [d0, d1] to pixels [p0, p1] (p1 < p0 for a
/// vertical axis, whose pixels grow downwards).
struct Scale {
    double d0 = 0.0, d1 = 1.0;
    double p0 = 0.0, p1 = 1.0;
    double operator()(double value) const { return p0 + (value - d0) * (p1 - p0) / (d1 - d0); }
};

}  // namespace stepstone::report
