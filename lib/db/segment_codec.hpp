#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

struct sqlite3;

namespace stepstone::db {

// How kb_segment.segment_values holds a segment (docs/schema.md: segment values).
//
// Raw: width x channels float32, little endian, row-major: exactly
// width x channels x 4 bytes (every file before schema 0006).
//
// Packed, lossless: a channel whose values are all exactly +0.0 or 1.0 (the
// bumpers, the light sensors, carrying) is stored as one bit a step, the
// others as float32:
//
//   byte 0                  'P' (0x50)
//   ceil(channels / 8)      bit c set: channel c is binary (bit c % 8 of byte c / 8)
//   per binary channel      ceil(width / 8) bytes, bit r: the value at step r is 1.0
//   per other channel       width float32, little endian, step order
//
// Channels come in increasing order in both lists. A segment is written
// packed only when that is shorter than raw, so a blob of exactly
// width x channels x 4 bytes is always raw and any other length is packed.

/// The stored form of one segment (width x channels values, row-major).
std::vector<std::byte> pack_segment(std::span<const float> values, std::size_t width, std::size_t channels);

/// Decodes a stored segment into `out` (width x channels values, row-major).
/// Returns false when `blob` is neither form (wrong size, tag or padding).
bool unpack_segment(std::span<const std::byte> blob, std::size_t width, std::size_t channels,
                    std::span<float> out);

/// Registers the SQL function segment_floats(blob, width, channels): the raw
/// form of a stored segment (NULL for a malformed one), so that SQL sees every
/// segment as float32 values whatever its stored form (the run digest, users).
void register_segment_functions(sqlite3* db);

}  // namespace stepstone::db
