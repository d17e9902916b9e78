#pragma once

#include <cstddef>
#include <span>

namespace stepstone::stats {

/// Five-number summary and mean of a sample.
struct Summary {
    std::size_t n = 0;  ///< number of values
    double min = 0;     ///< smallest value
    double q1 = 0;      ///< first quartile (type 7, see summarize)
    double median = 0;  ///< second quartile (type 7: the usual median)
    double q3 = 0;      ///< third quartile (type 7)
    double max = 0;     ///< largest value
    double mean = 0;    ///< sum of the values / n, summed in input order
};

/// Quartiles by linear interpolation between order statistics (R type 7 =
/// NumPy's default): with x_0 <= ... <= x_{n-1} the sorted values, the
/// q-quantile is x_l + (h - l) (x_{l+1} - x_l), h = (n - 1) q, l = floor(h),
/// evaluated as (1 - f) x_l + f x_{l+1} with f = h - l (R's form), and x_l
/// itself when f = 0 or x_{l+1} = x_l. {1, 2, 3, 4} gives q1 = 1.75,
/// median = 2.5, q3 = 3.25. Throws DataError if values is empty or holds a NaN.
Summary summarize(std::span<const double> values);

/// The type-7 median of summarize (the middle value, or the mean of the two
/// middle ones). Throws DataError if values is empty or holds a NaN.
double median(std::span<const double> values);

/// Number of values >= threshold (0 for no values). Throws DataError if the
/// threshold or a value is NaN.
std::size_t count_at_least(std::span<const double> values, double threshold);

}  // namespace stepstone::stats
