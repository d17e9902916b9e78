// The byte strings the ranks of an MPI job exchange: written and read back
// in the same order, a message of the wrong length refused with a message.
#include "exp/parallel/bytes.hpp"

#include <catch2/catch.hpp>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/error.hpp"

using namespace stepstone;
using Catch::Matchers::Equals;

TEST_CASE("values, spans and strings read back as written", "[core][bytes]") {
    const std::vector<float> floats{1.5f, -0.25f, 3.0f};
    ByteWriter out;
    out.reserve(256)
        .put<std::uint64_t>(7)
        .put(2.5)
        .put_span(std::span<const float>(floats))
        .put_string("rank 1");
    // 8 + 8 + (8 + 3 x 4) + (8 + 6) bytes
    CHECK(out.bytes().size() == 50);

    ByteReader in(out.bytes());
    CHECK(in.get<std::uint64_t>() == 7);
    CHECK(in.get<double>() == 2.5);
    std::vector<float> back(5, 9.0f);
    in.get_exactly(std::span<float>(back).subspan(1, 3));  // straight into the middle of a buffer
    CHECK(back == std::vector<float>{9.0f, 1.5f, -0.25f, 3.0f, 9.0f});
    CHECK(in.get_string() == "rank 1");
    CHECK(in.done());
}

TEST_CASE("a message that does not hold what the reader expects is refused", "[core][bytes][errors]") {
    const std::vector<float> floats{1.0f, 2.0f, 3.0f};
    ByteWriter out;
    out.put_span(std::span<const float>(floats));

    std::vector<float> two(2, 0.0f);
    ByteReader in(out.bytes());
    CHECK_THROWS_AS(in.get_exactly(std::span<float>(two)), DataError);
    ByteReader again(out.bytes());
    CHECK_THROWS_WITH(again.get_exactly(std::span<float>(two)),
                      Equals("a message holds 3 values where 2 were expected"));
    CHECK(two == std::vector<float>{0.0f, 0.0f});  // nothing written
    std::vector<float> four(4, 0.0f);              // too few values is as wrong as too many
    ByteReader third(out.bytes());
    CHECK_THROWS_WITH(third.get_exactly(std::span<float>(four)),
                      Equals("a message holds 3 values where 4 were expected"));

    // cut short: the count promises 3 floats, 2 follow
    const std::string cut = out.bytes().substr(0, out.bytes().size() - 4);
    std::vector<float> three(3);
    ByteReader short_one(cut);
    CHECK_THROWS_WITH(short_one.get_exactly(std::span<float>(three)), Equals("a message ends too early"));
    ByteReader short_two(cut);
    std::vector<float> any;
    CHECK_THROWS_WITH(short_two.get_into(any), Equals("a message ends too early"));
}
