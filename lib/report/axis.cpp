// Round-number axis ticks (Heckbert, "Nice numbers for graph labels").

#include "report/axis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace stepstone::report {

namespace {

// 1, 2, 5 or 10 times a power of ten: the nearest one to x when `round`,
// else the smallest one >= x
double nice_number(double x, bool round) {
    const double exponent = std::floor(std::log10(x));
    const double power = std::pow(10.0, exponent);
    const double fraction = x / power;
    double nice = 10.0;
    if (round) {
        if (fraction < 1.5) nice = 1.0;
        else if (fraction < 3.0) nice = 2.0;
        else if (fraction < 7.0) nice = 5.0;
    } else {
        if (fraction <= 1.0) nice = 1.0;
        else if (fraction <= 2.0) nice = 2.0;
        else if (fraction <= 5.0) nice = 5.0;
    }
    return nice * power;
}

}  // namespace

std::string Ticks::label(double value) const {
    // -0.0 and values like -1e-17 print as "0"
    const double shown = std::fabs(value) < step * 1e-9 ? 0.0 : value;
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, shown);
    return text;
}

Ticks nice_ticks(double low, double high, int target) {
    if (!std::isfinite(low) || !std::isfinite(high)) {
        low = 0.0;
        high = 1.0;
    }
    if (low > high) std::swap(low, high);
    if (low == high) {
        if (low == 0.0) {
            high = 1.0;
        } else {
            low -= 1.0;
            high += 1.0;
        }
    }
    target = std::max(target, 2);
    Ticks ticks;
    const double range = nice_number(high - low, false);
    ticks.step = nice_number(range / (target - 1), true);
    ticks.low = std::floor(low / ticks.step) * ticks.step;
    ticks.high = std::ceil(high / ticks.step) * ticks.step;
    ticks.decimals = std::max(0, static_cast<int>(-std::floor(std::log10(ticks.step))));
    const auto count = static_cast<long>(std::lround((ticks.high - ticks.low) / ticks.step));
    for (long i = 0; i <= count; ++i) {
        // from the tick's integer multiple, so no error accumulates
        ticks.values.push_back((std::round(ticks.low / ticks.step) + static_cast<double>(i)) * ticks.step);
    }
    ticks.low = ticks.values.front();
    ticks.high = ticks.values.back();
    return ticks;
}

}  // namespace stepstone::report
