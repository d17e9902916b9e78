#pragma once

#include <cstddef>

namespace stepstone::portable {

/// portable::sincos of `count` angles at once: s[i] and c[i] get exactly the
/// bits portable::sincos(x[i], s[i], c[i]) gives: eight angles per AVX-512
/// vector where core/cpu.hpp's avx512_kernels_allowed(), then four per AVX2
/// vector where avx2_kernels_allowed(), then one at a time. Every lane runs the scalar
/// function's operations in its order (the reduction by pi/2 in three parts,
/// the two Horner polynomials, the quadrant), and no operation is contracted
/// into FMA, so the builds cannot differ. The arrays may not overlap.
void sincos_lanes(const double* x, double* s, double* c, std::size_t count);

/// The same without AVX-512 (four angles a vector where AVX2 is allowed), for tests.
void sincos_lanes_avx2(const double* x, double* s, double* c, std::size_t count);

/// The same, one angle at a time (the build without AVX2), for tests.
void sincos_lanes_generic(const double* x, double* s, double* c, std::size_t count);

}  // namespace stepstone::portable
