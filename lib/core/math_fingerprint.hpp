#pragma once

#include <string>

namespace stepstone {

/// A probe of how this process's math library rounds the functions a run
/// depends on: std::sin and std::cos (the simulator's headings), std::pow (the
/// polynomial mutation), std::atan2 and std::hypot (the scripted controllers).
/// It evaluates each on thousands of fixed arguments in the ranges a run uses
/// and hashes the results' bits into 16 hex digits.
///
/// glibc chooses among its own builds of these functions when a program starts
/// (on x86-64, one built with FMA instructions when the CPU has them, else
/// another). The builds differ in the last bit for a small share of arguments
/// (docs/architecture.md, Determinism, has the figures), so the same seed
/// can give different runs on machines of different kinds. Equal fingerprints
/// say that two processes round every probed argument alike; a run file stores
/// its machine's fingerprint (meta key `math_fingerprint`).
const std::string& math_fingerprint();

/// The meta key under which a run file stores its machine's fingerprint.
inline constexpr const char* kMathFingerprintKey = "math_fingerprint";

}  // namespace stepstone
