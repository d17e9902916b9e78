#include "core/portable_math.hpp"

#include <array>
#include <cmath>

#include "core/portable_math_constants.hpp"

namespace stepstone {

std::string_view to_string(Math math) { return math == Math::portable ? "portable" : "libm"; }

std::optional<Math> parse_math(std::string_view name) {
    for (const Math math : {Math::libm, Math::portable}) {
        if (name == to_string(math)) return math;
    }
    return std::nullopt;
}

}  // namespace stepstone

namespace stepstone::portable {

namespace {

using detail::inverse_factorial;
using detail::kTwoOverPi;

// ln 2 in two parts, the first of 33 bits
constexpr double kLn2Hi = 0x1.62e42fef00000p-1;
constexpr double kLn2Lo = 0x1.473de6af278edp-34;
constexpr double kInvLn2 = 0x1.71547652b82fep+0;

// log(m) for m in [sqrt(1/2), sqrt(2)): 2 atanh(s), s = (m - 1) / (m + 1),
// |s| <= 0.172, the series to s^25
double log_kernel(double m) {
    const double s = (m - 1.0) / (m + 1.0);
    const double z = s * s;
    double p = 1.0 / 25.0;
    for (int n = 23; n >= 3; n -= 2) p = 1.0 / static_cast<double>(n) + z * p;
    return 2.0 * s + 2.0 * s * (z * p);
}

// exp(t + tail) for finite t and |tail| <= 2^-40 |t|: t = k ln 2 + r, |r| <= ln 2 / 2, Taylor to
// r^17; the tail joins r, where its bits are kept
double exp_of(double t, double tail) {
    const double k = std::nearbyint(t * kInvLn2);
    const double r = ((t - k * kLn2Hi) - k * kLn2Lo) + tail;
    double p = inverse_factorial(17);
    for (int n = 16; n >= 2; --n) p = inverse_factorial(n) + r * p;
    const double e = 1.0 + (r + r * (r * p));
    return std::ldexp(e, static_cast<int>(k));
}

// a b = hi + lo exactly (Dekker's product: each factor split in two halves of 26 bits, no FMA)
void exact_product(double a, double b, double& hi, double& lo) {
    constexpr double kSplit = 134217729.0;  // 2^27 + 1
    const double ca = kSplit * a;
    const double a_hi = ca - (ca - a);
    const double a_lo = a - a_hi;
    const double cb = kSplit * b;
    const double b_hi = cb - (cb - b);
    const double b_lo = b - b_hi;
    hi = a * b;
    lo = ((a_hi * b_hi - hi) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo;
}

// atan u for |u| <= tan(pi/8) + rounding: u - u^3/3 + ... to u^47, whose
// first omitted term is below 2^-54 u
double atan_kernel(double u) {
    const double z = u * u;
    double p = -1.0 / 47.0;
    for (int n = 45; n >= 3; n -= 2) p = (n % 4 == 1 ? 1.0 : -1.0) / static_cast<double>(n) + z * p;
    return u + u * (z * p);
}

// pi/4, pi/2 and pi as a double and the rest
constexpr double kQuarterPi = 0x1.921fb54442d18p-1;
constexpr double kQuarterPiLo = 0x1.1a62633145c07p-55;
constexpr double kHalfPi = 0x1.921fb54442d18p+0;
constexpr double kHalfPiLo = 0x1.1a62633145c07p-54;
constexpr double kPi = 0x1.921fb54442d18p+1;
constexpr double kPiLo = 0x1.1a62633145c07p-53;
constexpr double kTanEighthPi = 0x1.a827999fcef32p-2;

}  // namespace

void sincos(double x, double& s, double& c) {
    const double k = std::nearbyint(x * kTwoOverPi);
    double r;
    double sr;
    double cr;
    detail::reduce(x, k, r);
    detail::sincos_kernel(r, sr, cr);
    // x = k pi/2 + r: the quadrant k mod 4 rotates (cos r, sin r)
    switch (static_cast<long long>(k) & 3) {
        case 0:
            s = sr, c = cr;
            break;
        case 1:
            s = cr, c = -sr;
            break;
        case 2:
            s = -sr, c = -cr;
            break;
        default:
            s = -cr, c = sr;
            break;
    }
}

double sin(double x) {
    double s = 0.0;
    double c = 0.0;
    sincos(x, s, c);
    return s;
}

double cos(double x) {
    double s = 0.0;
    double c = 0.0;
    sincos(x, s, c);
    return c;
}

double atan2(double y, double x) {
    if (std::isnan(x) || std::isnan(y)) return x + y;
    const double ax = std::fabs(x);
    const double ay = std::fabs(y);
    double a = 0.0;  // the angle of (|x|, |y|), in [0, pi/2]
    if (ay == 0.0) {
        a = 0.0;
    } else if (ax == 0.0 || std::isinf(ay)) {
        a = std::isinf(ax) ? kQuarterPi : kHalfPi;
    } else if (std::isinf(ax)) {
        a = 0.0;
    } else {
        const bool steep = ay > ax;
        double lo = steep ? ax : ay;
        double hi = steep ? ay : ax;
        const double t = lo / hi;  // in (0, 1]
        // atan t, its small part kept apart from the constant it is added to; above tan(pi/8),
        // atan t = pi/4 + atan u with u = (lo - hi) / (lo + hi), from the magnitudes themselves
        // rather than from the rounded t (lo - hi is exact from t = 1/2 on)
        double head = 0.0;
        double small = 0.0;
        if (t > kTanEighthPi) {
            if (hi > 0x1.0p1000) {  // lo + hi must not overflow: a power of 2 changes no ratio
                lo *= 0x1.0p-4;
                hi *= 0x1.0p-4;
            }
            head = kQuarterPi;
            small = atan_kernel((lo - hi) / (lo + hi)) + kQuarterPiLo;
        } else {
            small = atan_kernel(t);
        }
        // steep: pi/2 - atan t
        a = steep ? (kHalfPi - head) + (kHalfPiLo - small) : head + small;
    }
    if (std::signbit(x)) a = (kPi - a) + kPiLo;  // the left half plane (x = -0 too)
    return std::copysign(a, y);
}

double pow(double base, double exponent) {
    if (base == 0.0) return 0.0;
    if (base == 1.0) return 1.0;
    int e = 0;
    double m = std::frexp(base, &e);  // base = m 2^e, m in [1/2, 1)
    if (m < 0x1.6a09e667f3bcdp-1) {   // below sqrt(1/2): into [sqrt(1/2), sqrt(2))
        m *= 2.0;
        --e;
    }
    const double log_m = log_kernel(m);
    const double ke = static_cast<double>(e);
    // t = exponent * (e ln 2 + log m) in two doubles: e ln2_hi is exact and its product with the
    // exponent is kept whole, so t carries no rounding proportional to |t| (|t| reaches 37 when base
    // is 2^-53, which would cost as many ulp)
    double head = 0.0;
    double head_lo = 0.0;
    exact_product(exponent, ke * kLn2Hi, head, head_lo);
    const double rest = exponent * (ke * kLn2Lo + log_m);
    const double t = head + rest;
    const double t_lo = (head - t) + rest;  // exact when |head| >= |rest|, else within an ulp of rest
    return exp_of(t, t_lo + head_lo);
}

}  // namespace stepstone::portable
