#pragma once

// Byte strings of plain values, for messages between the ranks of an MPI job
// (exp/parallel/mpi.hpp). Values are copied bit for bit, so doubles arrive exactly;
// both ends run the same binary, so byte order and sizes agree.

#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone {

/// Appends values to a byte string.
class ByteWriter {
public:
    /// Appends the bytes of a trivially copyable value.
    template <class T>
    ByteWriter& put(const T& value) {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
        return *this;
    }
    /// Appends a count, then the elements.
    template <class T>
    ByteWriter& put_span(std::span<const T> values) {
        static_assert(std::is_trivially_copyable_v<T>);
        put<std::uint64_t>(values.size());
        bytes_.append(reinterpret_cast<const char*>(values.data()), values.size_bytes());
        return *this;
    }
    /// Appends a length, then the text.
    ByteWriter& put_string(std::string_view text) {
        return put_span(std::span<const char>(text.data(), text.size()));
    }

    /// Room for `size` bytes in all, so that a large message is not copied as it grows.
    ByteWriter& reserve(std::size_t size) {
        bytes_.reserve(size);
        return *this;
    }

    const std::string& bytes() const { return bytes_; }
    std::string take() { return std::move(bytes_); }

private:
    std::string bytes_;
};

/// Reads the values a ByteWriter wrote, in the same order. Throws DataError
/// when the bytes run out (a message of another kind or version).
class ByteReader {
public:
    explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}

    template <class T>
    T get() {
        static_assert(std::is_trivially_copyable_v<T>);
        T value;
        std::memcpy(&value, take(sizeof value), sizeof value);
        return value;
    }
    /// Reads a count and the elements into `out` (resized).
    template <class Container>
    void get_into(Container& out) {
        using T = typename Container::value_type;
        static_assert(std::is_trivially_copyable_v<T>);
        const auto count = get<std::uint64_t>();
        if (count > bytes_.size() / sizeof(T)) throw DataError("a message ends too early");
        out.resize(count);
        if (count > 0) std::memcpy(out.data(), take(count * sizeof(T)), count * sizeof(T));
    }
    /// Reads a count and the elements straight into `out`, which must hold
    /// exactly that many (DataError otherwise): no intermediate copy.
    template <class T>
    void get_exactly(std::span<T> out) {
        static_assert(std::is_trivially_copyable_v<T>);
        const auto count = get<std::uint64_t>();
        if (count != out.size()) {
            throw DataError(
                concat("a message holds ", count, " values where ", out.size(), " were expected"));
        }
        if (count > 0) std::memcpy(out.data(), take(count * sizeof(T)), count * sizeof(T));
    }
    std::string get_string() {
        std::string text;
        get_into(text);
        return text;
    }
    bool done() const { return bytes_.empty(); }

private:
    const char* take(std::size_t size) {
        if (size > bytes_.size()) throw DataError("a message ends too early");
        const char* data = bytes_.data();
        bytes_.remove_prefix(size);
        return data;
    }

    std::string_view bytes_;
};

}  // namespace stepstone
