#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// a KB of 2-step x 3-channel segments built from random policies
kb::KnowledgeBase random_kb(std::uint64_t seed, int policies) {
    kb::KbParams params;
    params.segment_width = 2;
    params.channels = 3;
    params.delta = 0.5;
    kb::KnowledgeBase base(params);
    const auto source = base.add_source("run-a");
    Rng rng(seed);
    for (int p = 0; p < policies; ++p) {
        std::vector<float> values(4 * 6);
        for (auto& v : values) v = static_cast<float>(rng.uniform());
        base.observe(kb::as_segments(values, 6), rng.uniform(), {source, p / 4});
    }
    return base;
}

}  // namespace

TEST_CASE("a stored KB loads back with identical segments, records and answers", "[db][kb]") {
    test::TempDir dir;
    const auto original = random_kb(3, 40);
    REQUIRE(original.size() > 10);
    {
        auto connection = db::open_database(dir / "kb.db", db::OpenMode::create);
        db::insert_kb(connection, "run", original);
    }
    auto connection = db::open_database(dir / "kb.db", db::OpenMode::read_only);
    const auto stored = db::load_kb(connection);
    CHECK(stored.name == "run");
    REQUIRE(stored.kb.size() == original.size());
    for (std::size_t i = 0; i < original.size(); ++i) {
        const auto a = original.segment(i);
        const auto b = stored.kb.segment(i);
        CHECK(std::equal(a.begin(), a.end(), b.begin()));
        CHECK(original.record(i).cum_reward == stored.kb.record(i).cum_reward);
        CHECK(original.record(i).count == stored.kb.record(i).count);
        CHECK(original.record(i).last.generation == stored.kb.record(i).last.generation);
    }
    REQUIRE(stored.kb.sources().size() == 1);
    CHECK(stored.kb.sources()[0].run == "run-a");
    // the average_reward column is cum_reward / count
    CHECK(connection.query_int("SELECT count(*) FROM kb_segment WHERE abs(average_reward - cum_reward / count) > 0") == 0);
    // the same query gives the same answer from both
    std::vector<float> query(6, 0.5f);
    CHECK(original.r_max(kb::as_segments(query, 6)) == stored.kb.r_max(kb::as_segments(query, 6)));
}

TEST_CASE("update_kb writes only new and re-credited segments and equals a full write", "[db][kb]") {
    test::TempDir dir;
    auto kb = random_kb(5, 8);
    auto incremental = db::open_database(dir / "inc.db", db::OpenMode::create);
    const auto id = db::insert_kb(incremental, "run", kb);
    const std::size_t before = kb.size();
    Rng rng(9);
    for (int p = 0; p < 8; ++p) {
        std::vector<float> values(4 * 6);
        for (auto& v : values) v = static_cast<float>(rng.uniform());
        kb.observe(kb::as_segments(values, 6), 0.25, {0, 7});
    }
    db::update_kb(incremental, id, kb, before, 7);
    auto full = db::open_database(dir / "full.db", db::OpenMode::create);
    db::insert_kb(full, "run", kb);
    const char* rows = "SELECT group_concat(id || ':' || cum_reward || ':' || count || ':' || last_generation || ':' || "
                       "hex(segment_values), ',') FROM (SELECT * FROM kb_segment ORDER BY id)";
    auto a = incremental.prepare(rows);
    auto b = full.prepare(rows);
    REQUIRE(a.step());
    REQUIRE(b.step());
    CHECK(a.column_text(0) == b.column_text(0));
}

TEST_CASE("a malformed stored segment is refused with the KB named", "[db][kb][errors]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "bad.db", db::OpenMode::create);
    db::insert_kb(connection, "run", random_kb(1, 4));
    connection.exec("UPDATE kb_segment SET segment_values = x'0000' WHERE id = 1");
    // each problem named as it is: the byte count, then an infinite sum
    CHECK_THROWS_WITH(db::load_kb(connection),
                      Contains("bad.db: knowledge base \"run\" segment 1 holds 2 value bytes: neither"));
    // (a count below 1 the schema's CHECK constraint refuses to store)
    connection.exec(
        "UPDATE kb_segment SET segment_values = (SELECT segment_values FROM kb_segment WHERE id = 0), "
        "cum_reward = 1e999 WHERE id = 1");
    CHECK_THROWS_WITH(db::load_kb(connection), Contains("segment 1 has a non-finite cum_reward (inf)"));
    CHECK_THROWS_WITH(db::load_kb(connection, "other"), Contains("no knowledge base named \"other\""));
    auto empty = db::open_database(dir / "empty.db", db::OpenMode::create);
    CHECK_THROWS_WITH(db::load_kb(empty), Contains("empty.db: holds no knowledge base"));
}
