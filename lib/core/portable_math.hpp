#pragma once

#include <optional>
#include <string_view>

namespace stepstone {

/// Which sine, cosine and power a run uses: the C library's (glibc's, as every
/// run before this choice existed; the builds it picks by CPU can round
/// differently, core/math_fingerprint.hpp) or those below, the same bits on
/// every machine. A config's "math": "libm" | "portable".
enum class Math { libm, portable };

std::string_view to_string(Math math);
/// The Math that to_string names, or nothing for any other text.
std::optional<Math> parse_math(std::string_view name);

/// Sine, cosine, arc tangent and power computed from IEEE-754 additions,
/// multiplications, divisions, nearbyint, frexp and ldexp alone (the build
/// contracts nothing into FMA: -ffp-contract=off), so every x86-64 machine gives
/// the same bits, and so would any IEEE platform. glibc's own functions do not:
/// they come in builds picked by CPU, which round some arguments differently
/// (core/math_fingerprint.hpp). Measured against long double (tests/core): sin,
/// cos and atan2 within 1.5 ulp; pow within 1.5 ulp on the mutation's arguments
/// (base in [0, 1), exponent 1 / (eta + 1)) and within 2e-15 relative on wider
/// ones. Runs use them when their config says "math": "portable".
namespace portable {

/// sin and cos of `x`, for |x| < 2^20 (a Cody-Waite reduction by pi/2 in
/// three parts, then Taylor polynomials on |r| <= pi/4).
void sincos(double x, double& s, double& c);
double sin(double x);
double cos(double x);

/// The angle of (x, y) in [-pi, pi], as std::atan2 defines it for finite
/// arguments (signed zeros included): the ratio of the smaller to the larger
/// magnitude, reduced to |u| <= tan(pi/8) by atan t = pi/4 + atan((t-1)/(t+1)),
/// then a Taylor polynomial, then the octant.
double atan2(double y, double x);

/// base^exponent for base >= 0 and a finite exponent > 0 (0^y is 0), as
/// exp(exponent * log(base)).
double pow(double base, double exponent);

}  // namespace portable

}  // namespace stepstone
