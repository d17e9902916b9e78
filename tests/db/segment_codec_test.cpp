// Stored segments: the packed form's bytes by hand, lossless round trips, the
// refusals, SQL's segment_floats, and digests that do not see the form.

#include "db/segment_codec.hpp"

#include <bit>
#include <catch2/catch.hpp>
#include <cstring>
#include <limits>
#include <random>

#include "db/database.hpp"
#include "db/digest.hpp"
#include "db/kb_store.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using db::pack_segment;
using db::unpack_segment;

namespace {

std::vector<std::byte> bytes(std::initializer_list<int> list) {
    std::vector<std::byte> out;
    for (int b : list) out.push_back(static_cast<std::byte>(b));
    return out;
}

std::vector<std::uint32_t> bits(std::span<const float> values) {
    std::vector<std::uint32_t> out;
    for (float v : values) out.push_back(std::bit_cast<std::uint32_t>(v));
    return out;
}

// a behaviour-like segment: channels 0-2 and 12-14 continuous, 3-11 binary (as the paper's inputs)
std::vector<float> paper_like_segment(std::uint32_t seed, std::size_t width = 20) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> values(width * 15);
    for (std::size_t r = 0; r < width; ++r) {
        for (std::size_t c = 0; c < 15; ++c) {
            const bool binary = c >= 3 && c <= 11;
            values[r * 15 + c] = binary ? static_cast<float>(rng() % 2) : u(rng);
        }
    }
    return values;
}

}  // namespace

TEST_CASE("a packed segment holds the bytes the format describes", "[db][kb]") {
    // width 3, channels 2, row-major: channel 0 = 0.5, 0.25, 1.0 (not binary), channel 1 = 1, 0, 1 (binary)
    const std::vector<float> values{0.5f, 1.0f, 0.25f, 0.0f, 1.0f, 1.0f};
    // 'P', mask 0b10 (channel 1 binary), channel 1's steps 0 and 2 set (0b101), then channel 0's floats
    // 0.5 = 0x3F000000, 0.25 = 0x3E800000, 1.0 = 0x3F800000, little endian
    const auto expected =
        bytes({0x50, 0x02, 0x05, 0x00, 0x00, 0x00, 0x3F, 0x00, 0x00, 0x80, 0x3E, 0x00, 0x00, 0x80, 0x3F});
    const auto packed = pack_segment(values, 3, 2);
    CHECK(packed == expected);
    std::vector<float> back(6);
    REQUIRE(unpack_segment(packed, 3, 2, back));
    CHECK(bits(back) == bits(values));
}

TEST_CASE("segments read back bit for bit, packed or raw", "[db][kb]") {
    SECTION("the paper's shape: 9 binary channels pack to 510 bytes") {
        for (std::uint32_t seed = 1; seed <= 50; ++seed) {
            const auto values = paper_like_segment(seed);
            const auto packed = pack_segment(values, 20, 15);
            // 1 tag + 2 mask bytes + 9 channels x 3 bytes + 6 channels x 20 float32
            CHECK(packed.size() == 1 + 2 + 9 * 3 + 6 * 80);
            std::vector<float> back(300);
            REQUIRE(unpack_segment(packed, 20, 15, back));
            CHECK(bits(back) == bits(values));
        }
    }
    SECTION("-0.0, a denormal and 1.0 among other values are kept as they are") {
        auto values = paper_like_segment(7);
        values[3] = -0.0f;  // channel 3 is no longer binary: -0.0 is not +0.0
        values[16] = std::numeric_limits<float>::denorm_min();
        values[30] = 1.0f;
        const auto packed = pack_segment(values, 20, 15);
        CHECK(packed.size() == 1 + 2 + 8 * 3 + 7 * 80);
        std::vector<float> back(300);
        REQUIRE(unpack_segment(packed, 20, 15, back));
        CHECK(bits(back) == bits(values));
    }
    SECTION("with nothing binary the raw form is shorter and is kept") {
        std::vector<float> values(300);
        for (std::size_t i = 0; i < values.size(); ++i) values[i] = 0.001f * static_cast<float>(i + 1);
        const auto stored = pack_segment(values, 20, 15);
        REQUIRE(stored.size() == 1200);
        CHECK(std::memcmp(stored.data(), values.data(), 1200) == 0);
        std::vector<float> back(300);
        REQUIRE(unpack_segment(stored, 20, 15, back));
        CHECK(bits(back) == bits(values));
    }
    SECTION("one step of one channel: a binary value packs to 3 bytes, another stays raw (4)") {
        const std::vector<float> one{1.0f}, half{0.5f};
        CHECK(pack_segment(one, 1, 1) == bytes({0x50, 0x01, 0x01}));
        CHECK(pack_segment(half, 1, 1).size() == 4);  // packed would be 1 + 1 + 4 bytes
    }
}

TEST_CASE("a blob that is neither form is refused", "[db][kb][errors]") {
    const auto good = pack_segment(paper_like_segment(3), 20, 15);
    std::vector<float> out(300);
    auto refuses = [&](std::vector<std::byte> blob) { return !unpack_segment(blob, 20, 15, out); };
    auto wrong_tag = good;
    wrong_tag[0] = std::byte{0x51};
    CHECK(refuses(wrong_tag));
    auto short_blob = good;
    short_blob.pop_back();
    CHECK(refuses(short_blob));
    auto stray_mask = good;
    stray_mask[2] |= std::byte{0x80};  // channel 15 of 15
    CHECK(refuses(stray_mask));
    auto stray_step = good;
    stray_step[3 + 2] |= std::byte{0x10};  // step 20 of the first binary channel's 3 bytes
    CHECK(refuses(stray_step));
    CHECK(refuses({}));
    CHECK_FALSE(refuses(good));
}

TEST_CASE("SQL reads stored segments as float32 and digests do not see the stored form", "[db][kb][digest]") {
    test::TempDir dir;
    kb::KnowledgeBase kb({20, 15, 0.5});
    const auto source = kb.add_source("run");
    for (std::uint32_t seed = 1; seed <= 30; ++seed) {
        const auto values = paper_like_segment(seed, 40);
        kb.observe(kb::as_segments(values, 300), 0.01 * seed, {source, seed});
    }
    auto connection = db::open_database(dir / "kb.db", db::OpenMode::create);
    db::insert_kb(connection, "run", kb);
    REQUIRE(connection.query_int("SELECT count(*) FROM kb_segment") == 60);
    CHECK(connection.query_int("SELECT max(length(segment_values)) FROM kb_segment") == 510);
    CHECK(connection.query_int("SELECT count(*) FROM kb_segment WHERE "
                               "length(segment_floats(segment_values, 20, 15)) = 1200") == 60);
    CHECK(connection.query_int("SELECT segment_floats(x'5000', 20, 15) IS NULL") == 1);

    // the same KB with every segment rewritten raw, as older files hold it: the same KB, the same digest
    const auto packed_digest = db::run_digest(connection);
    connection.exec("UPDATE kb_segment SET segment_values = segment_floats(segment_values, 20, 15)");
    REQUIRE(connection.query_int("SELECT min(length(segment_values)) FROM kb_segment") == 1200);
    CHECK(db::run_digest(connection) == packed_digest);
    const auto loaded = db::load_kb(connection);
    REQUIRE(loaded.kb.size() == kb.size());
    CHECK(bits(loaded.kb.values()) == bits(kb.values()));
    CHECK(db::kb_digest(loaded.kb, std::nullopt) == db::kb_digest(kb, std::nullopt));
}
