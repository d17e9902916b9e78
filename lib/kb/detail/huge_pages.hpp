#pragma once

// Large arrays of the knowledge base on transparent huge pages.
//
// A lookup reads a few hundred bytes at random places of arrays of tens of
// megabytes (the segments' values, the block-means points); with 4 KiB pages
// nearly every such read also misses the TLB, and on the benchmark's workload
// the page walks were about a quarter of a lookup's time. Arrays of 2 MiB or
// more are therefore aligned to 2 MiB and marked MADV_HUGEPAGE, which Linux
// honours when transparent huge pages are enabled ("always" or "madvise" in
// /sys/kernel/mm/transparent_hugepage/enabled). Elsewhere, or when the kernel
// declines, an array simply stays on normal pages.

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace stepstone::kb::detail {

inline constexpr std::size_t kHugePage = std::size_t{2} << 20;

template <class T>
struct HugePageAllocator {
    using value_type = T;

    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        const std::size_t bytes = n * sizeof(T);
        if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
        if (bytes < kHugePage) return std::allocator<T>().allocate(n);
        const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
        void* p = std::aligned_alloc(kHugePage, rounded);
        if (p == nullptr) throw std::bad_alloc();
#if defined(MADV_HUGEPAGE)
        // advice only: a kernel without transparent huge pages refuses it
        (void)madvise(p, rounded, MADV_HUGEPAGE);
#endif
        return static_cast<T*>(p);
    }

    void deallocate(T* p, std::size_t n) noexcept {
        if (n * sizeof(T) < kHugePage) {
            std::allocator<T>().deallocate(p, n);
        } else {
            std::free(p);
        }
    }

    template <class U>
    bool operator==(const HugePageAllocator<U>&) const noexcept {
        return true;
    }
};

/// A std::vector whose buffers of 2 MiB or more sit on huge pages.
template <class T>
using HugeVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace stepstone::kb::detail
