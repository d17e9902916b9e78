// A KB applied to a run's stored policies (lib/exp/kb_apply.cpp), with a KB
// whose matches are known without the code under test: two segments, all 0
// and all 5, under match = nearest. Every robot value lies in [0, 1], so every
// policy segment matches the zero segment and r_max is its average.
#include "exp/kb_apply.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "db/database.hpp"
#include "exp/shaped_runs.hpp"
#include "support/kb_fixtures.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("shape gives a stored policy the zero segment's average in every segment and as r_max",
          "[exp][kb][shape]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");  // one start of kbtest::kRunSteps = 200 steps
    exptest::write_kb(dir / "kb.db", exptest::two_segment_kb(0.3, 0.9));
    const auto shaping = exp::shape_policy(dir / "kb.db", dir / "run.db", "best");
    CHECK(shaping.kb_name == "hand");
    CHECK(shaping.max_average == 0.9);
    CHECK(shaping.r_max == 0.3);
    REQUIRE(shaping.segments.size() == kbtest::kRunSteps / 20);
    for (const auto& segment : shaping.segments) {
        CHECK(segment.id == std::optional<std::size_t>(0));
        CHECK(segment.average_reward == 0.3);
    }
    auto connection = db::open_database(dir / "run.db", db::OpenMode::read_only);
    auto reward = connection.prepare("SELECT reward FROM individual WHERE id = :id");
    reward.bind(":id", shaping.individual_id);
    REQUIRE(reward.step());
    CHECK(shaping.stored_reward == reward.column_double(0));
}

TEST_CASE("annotate writes a row per stored policy and segment, copies the KB once, and refuses a taken name",
          "[exp][kb][annotate]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db", /*retain_all=*/true);
    exptest::write_kb(dir / "kb.db", exptest::two_segment_kb(0.3, 0.9));
    const auto first = exp::annotate_run(dir / "run.db", dir / "kb.db", exp::PolicySet::all);
    CHECK(first.kb_name == "hand");
    CHECK(first.copied);
    // retain all: 16 random policies, then 8 children in each of 3 generations
    CHECK(first.individuals.size() == 16 + 3 * 8);
    CHECK(first.rows == first.individuals.size() * (kbtest::kRunSteps / 20));
    {
        auto connection = db::open_database(dir / "run.db", db::OpenMode::read_only);
        const std::string rows =
            "SELECT count(*) FROM policy_segment WHERE kb_id = " + std::to_string(first.kb_id);
        CHECK(connection.query_int(rows) == static_cast<std::int64_t>(first.rows));
        CHECK(connection.query_int(rows + " AND kb_segment_id = 0 AND average_reward = 0.3") ==
              static_cast<std::int64_t>(first.rows));
    }
    // the same KB again: found in the run file, not copied twice
    const auto again = exp::annotate_run(dir / "run.db", dir / "kb.db", exp::PolicySet::best);
    CHECK_FALSE(again.copied);
    CHECK(again.kb_id == first.kb_id);
    // another KB under the name "hand": refused; under another name: copied
    exptest::write_kb(dir / "other.db", exptest::two_segment_kb(0.1, 0.9));
    CHECK_THROWS_AS(exp::annotate_run(dir / "run.db", dir / "other.db", exp::PolicySet::best),
                    exp::KbNameTaken);
    CHECK(exp::annotate_run(dir / "run.db", dir / "other.db", exp::PolicySet::best, "", "control").copied);

    CHECK(exp::parse_policy_set("front", "--individuals") == exp::PolicySet::front);
    CHECK_THROWS_WITH(exp::parse_policy_set("some", "--individuals"),
                      "--individuals must be one of best|front|all, got \"some\"");
}
