// The campaign's KB step (lib/exp/campaign/campaign_kb.cpp): the best source
// run's KB coarsened to kb.delta, checked against a coarsening written in the
// test, its randomized twin, and the shipped gzipped KB fixture.
#include "exp/campaign/campaign_kb.hpp"

#include <algorithm>
#include <catch2/catch.hpp>

#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "kb/oracle.hpp"
#include "nn/genome.hpp"
#include "runs/campaign_config.hpp"
#include "support/campaigns.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("a campaign with kb.delta uses the best source run's KB coarsened to that delta",
          "[exp][campaign][cli][coarsen]") {
    test::TempDir dir;
    auto json = test::tiny_campaign_json(1);
    const std::string from = R"("kb": {"from": "best"})";
    json.replace(json.find(from), from.size(), R"("kb": {"from": "best", "delta": 4})");
    test::write_file(dir / "c.json", json);
    const auto result = test::run_campaign(dir, "camp", {"--jobs", "2"});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    const auto camp = dir / "camp";
    // the expectation: the source run's stored KB coarsened by the linear-scan KB of
    // tests/kb/oracle.hpp (its segments observed in id order under delta 4, carrying their
    // statistics, as docs/knowledge_base.md describes), not by the library's coarsened().
    // This tiny source run scores nothing, so every cum_reward is 0 and the counts carry the
    // check; tests/cli/kb's kb export --delta test gives the same coarsening rewards that differ
    auto source = db::open_database(camp / "source" / "seed-4.db", db::OpenMode::read_only);
    const auto fine = db::load_kb(source, "run").kb;
    kboracle::OracleKb expected;
    expected.dim = fine.params().dim();
    expected.delta = 4.0;
    std::uint64_t fine_count = 0;
    for (std::size_t i = 0; i < fine.size(); ++i) {
        expected.add(fine.segment(i).data(), fine.record(i).cum_reward, fine.record(i).count);
        fine_count += fine.record(i).count;
    }
    auto used = db::open_database(camp / "kb" / "kb.db", db::OpenMode::read_only);
    const auto kb = db::load_kb(used).kb;
    CHECK(kb.params().delta == 4.0);
    CHECK(kb.params().segment_width == fine.params().segment_width);
    REQUIRE(kb.size() == expected.size());
    CHECK(kb.size() < fine.size());  // the larger delta folded segments together
    std::uint64_t count = 0;
    for (std::size_t i = 0; i < kb.size(); ++i) {
        CAPTURE(i);
        const auto segment = kb.segment(i);
        CHECK(std::equal(segment.begin(), segment.end(),
                         expected.values.begin() + static_cast<std::ptrdiff_t>(i * expected.dim)));
        CHECK(kb.record(i).cum_reward == Approx(expected.cum_reward[i]).epsilon(1e-12));
        CHECK(kb.record(i).count == expected.count[i]);
        count += kb.record(i).count;
    }
    CHECK(count == fine_count);  // every observation of the source run is kept, none counted twice
    // the randomized twin is made from the coarse KB: the same segments, each of count 1
    auto rand = db::open_database(camp / "kb" / "kb-rand.db", db::OpenMode::read_only);
    const auto twin = db::load_kb(rand).kb;
    REQUIRE(twin.size() == kb.size());
    CHECK(std::equal(twin.values().begin(), twin.values().end(), kb.values().begin()));
    for (std::size_t i = 0; i < twin.size(); ++i) CHECK(twin.record(i).count == 1);
}

TEST_CASE("the demo's KB fixture gunzips to a KB with rewards spread over a range, and other data is refused",
          "[exp][campaign][examples]") {
    const std::filesystem::path examples = std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples";
    // the quick campaign's KB is the shipped fixture: a paper-size source run's KB, coarsened
    const auto quick = runs::CampaignConfig::load(examples / "campaign_quick.json");
    test::TempDir dir;
    exp::gunzip_file(quick.kb_file, dir / "fixture.db");
    auto connection = db::open_database(dir / "fixture.db", db::OpenMode::read_only);
    const auto fixture = db::load_kb(connection);  // validated on load like any KB
    CHECK(fixture.kb.params().channels == 15);
    CHECK(fixture.kb.params().segment_width == 20);
    CHECK(!fixture.randomized_seed);
    CHECK(fixture.kb.max_average() >= 3.0 / 24);  // segments of policies that scored several balls
    REQUIRE(fixture.kb.sources().size() == 1);
    CHECK(fixture.kb.sources()[0].last_generation == 4000);
    CHECK_THROWS_WITH(exp::gunzip_file(examples / "campaign_quick.json", dir / "x.db"),
                      Catch::Contains("campaign_quick.json: not whole gzip data"));
    CHECK_FALSE(std::filesystem::exists(dir / "x.db"));
}

TEST_CASE(
    "the demo's seed fixture: a paper-size source run's 100 best policies, a finished run of 12 -> 3 "
    "networks",
    "[exp][campaign][examples][seed]") {
    const std::filesystem::path examples = std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples";
    const auto quick = runs::CampaignConfig::load(examples / "campaign_quick.json");
    REQUIRE(quick.seed);
    REQUIRE(quick.seed->from_file);
    CHECK(quick.seed->with == runs::SeedWith::best);
    CHECK(quick.seed->count == 100);
    CHECK(quick.target.config.ea.population_size == 100);  // every seed has a place in generation 0
    CHECK(quick.seed->file.extension() == ".gz");
    CHECK(std::filesystem::file_size(quick.seed->file) < (1u << 20));  // committed: under 1 MiB

    test::TempDir dir;
    exp::gunzip_file(quick.seed->file, dir / "seeds.db");
    auto connection = db::open_database(dir / "seeds.db", db::OpenMode::read_only);
    CHECK(connection.query_int("SELECT count(*) FROM run WHERE status = 'finished'").value_or(-1) == 1);
    CHECK(connection.query_int("SELECT generations_done FROM run").value_or(-1) == 4000);
    // E1's source run of seed 1 (docs/results.md section 1) reached 0.375 (9 balls of 24) and
    // stored more than 100 genomes at it: the 100 best are all at that reward
    CHECK(connection.query_int("SELECT count(*) FROM individual WHERE reward = 9.0 / 24").value_or(-1) ==
          100);
    auto select = connection.prepare("SELECT genome FROM genome");
    int genomes = 0;
    while (select.step()) {
        const auto genome = nn::Genome::from_json(nlohmann::json::parse(select.column_text(0)));
        CHECK(genome.input_count() == 12);
        CHECK(genome.output_count() == 3);
        ++genomes;
    }
    CHECK(genomes == 100);
}
