#pragma once

#include <cstddef>

namespace stepstone::portable {

/// portable::sincos of `count` angles at once: s[i] and c[i] get exactly the
/// bits portable::sincos(x[i], s[i], c[i]) gives, four angles per AVX2 vector
/// where the CPU has AVX2 and the environment does not set STEPSTONE_NO_AVX2
/// (core/cpu.hpp), one at a time otherwise. Every lane runs the scalar
/// function's operations in its order (the reduction by pi/2 in three parts,
/// the two Horner polynomials, the quadrant), and no operation is contracted
/// into FMA, so the two builds cannot differ. The arrays may not overlap.
void sincos_lanes(const double* x, double* s, double* c, std::size_t count);

/// The same, one angle at a time (the build without AVX2), for tests.
void sincos_lanes_generic(const double* x, double* s, double* c, std::size_t count);

}  // namespace stepstone::portable
