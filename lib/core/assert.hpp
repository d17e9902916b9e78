#pragma once

// STEPSTONE_ASSERT checks internal invariants. It is on in Debug and in the
// `sanitize` preset that scripts/test runs, and compiles to nothing under
// NDEBUG (Release, the `ci` preset). User input is validated at the
// boundary with exceptions (core/error.hpp), never with asserts.

#include <cstdio>
#include <cstdlib>

#ifdef NDEBUG
#define STEPSTONE_ASSERT(cond) ((void)0)
#else
#define STEPSTONE_ASSERT(cond)                                                              \
    ((cond) ? (void)0                                                                       \
            : (std::fprintf(stderr, "stepstone: internal error: assertion '%s' failed at %s:%d\n", \
                            #cond, __FILE__, __LINE__),                                    \
               std::abort()))
#endif
