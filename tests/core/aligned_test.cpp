// AlignedAllocator (core/aligned.hpp): every array it gives starts on its
// boundary, whatever the size, across growth and copies; the oracle is the
// address itself.
#include "core/aligned.hpp"

#include <catch2/catch.hpp>
#include <cstdint>

using namespace stepstone;

namespace {

bool on_line(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % 64 == 0; }

}  // namespace

TEST_CASE("cache-aligned vectors start on a cache line at every size, after growth and copies", "[core]") {
    for (std::size_t n = 1; n <= 300; n += 7) {
        // interleaved with plain allocations, which move malloc's next address about
        std::vector<char> noise(n);
        CacheAlignedVector<float> floats(n, 1.0f);
        CacheAlignedVector<double> doubles(n + 3);
        CHECK(on_line(floats.data()));
        CHECK(on_line(doubles.data()));
        for (int i = 0; i < 40; ++i) floats.push_back(2.0f);
        CHECK(on_line(floats.data()));
        const CacheAlignedVector<float> copy = floats;
        CHECK(on_line(copy.data()));
        CHECK(copy == floats);
    }
}
