#include "db/segment_codec.hpp"

#include <sqlite3.h>

#include <bit>
#include <cstring>

namespace stepstone::db {

namespace {

constexpr std::byte kPackedTag{0x50};
constexpr std::uint32_t kZeroBits = 0x00000000u;  // +0.0f (-0.0 is not binary: it is kept as it is)
constexpr std::uint32_t kOneBits = 0x3F800000u;   // 1.0f

static_assert(std::endian::native == std::endian::little, "segment blobs are little endian");

std::uint32_t bits_of(float value) { return std::bit_cast<std::uint32_t>(value); }

bool binary_channel(std::span<const float> values, std::size_t width, std::size_t channels, std::size_t c) {
    for (std::size_t r = 0; r < width; ++r) {
        const std::uint32_t b = bits_of(values[r * channels + c]);
        if (b != kZeroBits && b != kOneBits) return false;
    }
    return true;
}

std::size_t bytes_for(std::size_t bits) { return (bits + 7) / 8; }

}  // namespace

std::vector<std::byte> pack_segment(std::span<const float> values, std::size_t width, std::size_t channels) {
    const std::size_t raw_size = width * channels * sizeof(float);
    std::vector<bool> binary(channels);
    std::size_t binary_count = 0;
    for (std::size_t c = 0; c < channels; ++c) {
        binary[c] = binary_channel(values, width, channels, c);
        binary_count += binary[c];
    }
    const std::size_t packed_size = 1 + bytes_for(channels) + binary_count * bytes_for(width) +
                                    (channels - binary_count) * width * sizeof(float);
    std::vector<std::byte> out;
    if (packed_size >= raw_size) {
        out.resize(raw_size);
        std::memcpy(out.data(), values.data(), raw_size);
        return out;
    }
    out.assign(packed_size, std::byte{0});
    out[0] = kPackedTag;
    std::size_t at = 1;
    for (std::size_t c = 0; c < channels; ++c) {
        if (binary[c]) out[at + c / 8] |= std::byte{static_cast<unsigned char>(1u << (c % 8))};
    }
    at += bytes_for(channels);
    for (std::size_t c = 0; c < channels; ++c) {
        if (!binary[c]) continue;
        for (std::size_t r = 0; r < width; ++r) {
            if (bits_of(values[r * channels + c]) == kOneBits) {
                out[at + r / 8] |= std::byte{static_cast<unsigned char>(1u << (r % 8))};
            }
        }
        at += bytes_for(width);
    }
    for (std::size_t c = 0; c < channels; ++c) {
        if (binary[c]) continue;
        for (std::size_t r = 0; r < width; ++r) {
            std::memcpy(out.data() + at, &values[r * channels + c], sizeof(float));
            at += sizeof(float);
        }
    }
    return out;
}

bool unpack_segment(std::span<const std::byte> blob, std::size_t width, std::size_t channels,
                    std::span<float> out) {
    const std::size_t raw_size = width * channels * sizeof(float);
    if (out.size() != width * channels) return false;
    if (blob.size() == raw_size) {
        std::memcpy(out.data(), blob.data(), raw_size);
        return true;
    }
    const std::size_t mask_bytes = bytes_for(channels);
    if (blob.size() < 1 + mask_bytes || blob[0] != kPackedTag) return false;
    std::size_t binary_count = 0;
    for (std::size_t c = 0; c < channels; ++c) {
        binary_count += std::to_integer<unsigned>(blob[1 + c / 8] >> (c % 8)) & 1u;
    }
    // the mask's unused high bits must be 0, and the size must be what the mask says
    for (std::size_t c = channels; c < mask_bytes * 8; ++c) {
        if (std::to_integer<unsigned>(blob[1 + c / 8] >> (c % 8)) & 1u) return false;
    }
    const std::size_t expected =
        1 + mask_bytes + binary_count * bytes_for(width) + (channels - binary_count) * width * sizeof(float);
    if (blob.size() != expected) return false;
    auto is_binary = [&](std::size_t c) {
        return (std::to_integer<unsigned>(blob[1 + c / 8] >> (c % 8)) & 1u) != 0;
    };
    std::size_t at = 1 + mask_bytes;
    for (std::size_t c = 0; c < channels; ++c) {
        if (!is_binary(c)) continue;
        for (std::size_t r = 0; r < width; ++r) {
            const bool one = (std::to_integer<unsigned>(blob[at + r / 8] >> (r % 8)) & 1u) != 0;
            out[r * channels + c] = one ? 1.0f : 0.0f;
        }
        for (std::size_t r = width; r < bytes_for(width) * 8; ++r) {
            if (std::to_integer<unsigned>(blob[at + r / 8] >> (r % 8)) & 1u) return false;
        }
        at += bytes_for(width);
    }
    for (std::size_t c = 0; c < channels; ++c) {
        if (is_binary(c)) continue;
        for (std::size_t r = 0; r < width; ++r) {
            std::memcpy(&out[r * channels + c], blob.data() + at, sizeof(float));
            at += sizeof(float);
        }
    }
    return true;
}

namespace {

void segment_floats(sqlite3_context* context, int, sqlite3_value** args) {
    const auto width = sqlite3_value_int64(args[1]);
    const auto channels = sqlite3_value_int64(args[2]);
    const void* data = sqlite3_value_blob(args[0]);
    const int size = sqlite3_value_bytes(args[0]);
    if (width < 1 || channels < 1 || width * channels > (1 << 24) || size < 0) {
        sqlite3_result_null(context);
        return;
    }
    std::vector<float> values(static_cast<std::size_t>(width * channels));
    const std::span<const std::byte> blob(static_cast<const std::byte*>(data),
                                          static_cast<std::size_t>(size));
    if (!unpack_segment(blob, static_cast<std::size_t>(width), static_cast<std::size_t>(channels), values)) {
        sqlite3_result_null(context);
        return;
    }
    sqlite3_result_blob64(context, values.data(), values.size() * sizeof(float), SQLITE_TRANSIENT);
}

}  // namespace

void register_segment_functions(sqlite3* db) {
    sqlite3_create_function_v2(db, "segment_floats", 3, SQLITE_UTF8 | SQLITE_DETERMINISTIC | SQLITE_INNOCUOUS,
                               nullptr, segment_floats, nullptr, nullptr, nullptr);
}

}  // namespace stepstone::db
