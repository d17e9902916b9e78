#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace stepstone {

/// An allocator whose arrays start on an `Alignment`-byte boundary (a power of
/// two at least alignof(T)). The lane kernels load whole vectors from their
/// arrays: a vector that straddles two cache lines costs two loads.
template <class T, std::size_t Alignment>
struct AlignedAllocator {
    static_assert(Alignment >= alignof(T) && (Alignment & (Alignment - 1)) == 0);
    using value_type = T;
    template <class U>
    struct rebind {
        using other = AlignedAllocator<U, Alignment>;
    };

    AlignedAllocator() = default;
    template <class U>
    AlignedAllocator(const AlignedAllocator<U, Alignment>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
        return static_cast<T*>(::operator new (n * sizeof(T), std::align_val_t{Alignment}));
    }
    void deallocate(T* p, std::size_t) noexcept { ::operator delete (p, std::align_val_t{Alignment}); }

    template <class U>
    bool operator==(const AlignedAllocator<U, Alignment>&) const noexcept {
        return true;
    }
};

/// A vector whose elements start on a cache line (64 bytes).
template <class T>
using CacheAlignedVector = std::vector<T, AlignedAllocator<T, 64>>;

}  // namespace stepstone
