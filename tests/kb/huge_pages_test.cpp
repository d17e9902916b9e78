#include <catch2/catch.hpp>

#include <cstdint>
#include <numeric>

#include "kb/detail/huge_pages.hpp"

using namespace stepstone;

TEST_CASE("arrays of 2 MiB or more start on a 2 MiB boundary and keep their contents as they grow", "[kb][memory]") {
    kb::detail::HugeVector<float> values;
    // grow one element at a time past several reallocations across the 2 MiB line
    constexpr std::size_t kCount = (std::size_t{5} << 20) / sizeof(float);
    for (std::size_t i = 0; i < kCount; ++i) values.push_back(static_cast<float>(i % 1000003));
    REQUIRE(values.size() == kCount);
    CHECK(reinterpret_cast<std::uintptr_t>(values.data()) % kb::detail::kHugePage == 0);
    bool same = true;
    for (std::size_t i = 0; i < kCount; ++i) same = same && values[i] == static_cast<float>(i % 1000003);
    CHECK(same);

    // a copy is a new huge array with the same contents
    const kb::detail::HugeVector<float> copy = values;
    CHECK(copy.data() != values.data());
    CHECK(reinterpret_cast<std::uintptr_t>(copy.data()) % kb::detail::kHugePage == 0);
    CHECK(copy == values);
}

TEST_CASE("small and large arrays are each freed the way they were allocated", "[kb][memory]") {
    // operator new below 2 MiB, aligned_alloc above: a mismatched release is
    // what the sanitizer build (dev preset) reports here
    kb::detail::HugeVector<std::uint32_t> array(1000);
    std::iota(array.begin(), array.end(), 7u);
    CHECK(array.back() == 1006u);
    array.resize((std::size_t{3} << 20) / sizeof(std::uint32_t));  // crosses 2 MiB: reallocated huge
    CHECK(array[999] == 1006u);
    CHECK(reinterpret_cast<std::uintptr_t>(array.data()) % kb::detail::kHugePage == 0);
    array.resize(10);
    array.shrink_to_fit();  // back to a small buffer
    CHECK(array.capacity() == 10);
    CHECK(array[9] == 16u);
}
