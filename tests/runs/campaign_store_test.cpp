// campaign.db (lib/runs/campaign_store.cpp): a plan written by hand, read back
// in plan order with its runs' rows as they are updated, what a run file says
// about itself, and a folder that holds no campaign.
#include "runs/campaign_store.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "db/database.hpp"
#include "runs/run_store.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

runs::CampaignConfig target_only() {
    return runs::CampaignConfig::from_json(
        nlohmann::json::parse(R"({"target": {"config": {"task": {"kind": "target"}},
                                                                     "treatments": ["none"]}})"),
        "c.json", std::filesystem::current_path());
}

}  // namespace

TEST_CASE("campaign.db lists the planned runs in plan order, pending, and keeps each row as updated",
          "[runs][campaign][store]") {
    test::TempDir dir;
    const auto config = target_only();
    // step, treatment, seed, file, generations: not plan_runs' order, so the stored order shows
    const std::vector<runs::PlannedRun> plan{
        {runs::CampaignStep::target, runs::Treatment::sum, 2, "target/sum/seed-2.db", 5},
        {runs::CampaignStep::source, runs::Treatment::none, 4, "source/seed-4.db", 3},
        {runs::CampaignStep::target, runs::Treatment::mo_rand, 1, "target/mo-rand/seed-1.db", 5}};
    runs::create_campaign_db(dir / "campaign.db", config, plan);

    auto index = runs::load_campaign(dir.path());
    CHECK(index.config == config.to_json());
    REQUIRE(index.runs.size() == 3);
    for (std::size_t k = 0; k < 3; ++k) {
        INFO(plan[k].file);
        CHECK(index.runs[k].run.step == plan[k].step);
        CHECK(index.runs[k].run.treatment == plan[k].treatment);
        CHECK(index.runs[k].run.seed == plan[k].seed);
        CHECK(index.runs[k].run.file == plan[k].file);
        CHECK(index.runs[k].run.generations == plan[k].generations);
        CHECK(index.runs[k].status == runs::RunStatus::pending);
    }

    // the second run (campaign_run.id 2) finishes, the third fails
    auto states = index.runs;
    CHECK((states[0].id == 1 && states[1].id == 2 && states[2].id == 3));
    {
        auto connection = db::open_database(dir / "campaign.db", db::OpenMode::read_write);
        states[1].status = runs::RunStatus::finished;
        states[1].generations_done = 3;
        states[1].best_reward = 0.5;
        runs::update_run_row(connection, states[1], std::string("d1g3st"), 1.5, std::nullopt);
        states[2].status = runs::RunStatus::failed;
        runs::update_run_row(connection, states[2], std::nullopt, 0.25, std::string("evolve: no space left"));
    }
    index = runs::load_campaign(dir.path());
    CHECK(index.runs[0].status == runs::RunStatus::pending);
    CHECK(index.runs[1].status == runs::RunStatus::finished);
    CHECK(index.runs[2].status == runs::RunStatus::failed);
    // the one model reads back what was written: progress, reward, digest, time and error
    CHECK((index.runs[1].generations_done == 3 && index.runs[1].best_reward == 0.5 &&
           index.runs[1].digest == "d1g3st" && index.runs[1].wall_time == 1.5 && index.runs[1].error.empty()));
    CHECK((index.runs[2].error == "evolve: no space left" && index.runs[2].digest.empty() &&
           !index.runs[2].best_reward && index.runs[2].wall_time == 0.25));
    CHECK((index.runs[0].generations_done == -1 && !index.runs[0].best_reward));
    auto connection = db::open_database(dir / "campaign.db", db::OpenMode::read_only);
    auto row = connection.prepare(
        "SELECT generations_done, best_reward, digest, wall_time FROM campaign_run WHERE file = "
        "'source/seed-4.db'");
    REQUIRE(row.step());
    CHECK(row.column_int(0) == 3);
    CHECK(row.column_double(1) == 0.5);
    CHECK(row.column_text(2) == "d1g3st");
    CHECK(row.column_double(3) == 1.5);
    CHECK(connection.query_int("SELECT count(*) FROM campaign_run WHERE error = 'evolve: no space left' AND "
                               "file = 'target/mo-rand/seed-1.db'") == 1);
}

TEST_CASE("a run file says how far it got and its best reward, a missing one nothing",
          "[runs][campaign][store]") {
    test::TempDir dir;
    CHECK_FALSE(runs::read_run_file(dir / "missing.db"));
    {
        auto connection = db::open_database(dir / "run.db", db::OpenMode::create);
        runs::RunRecord run;
        run.task = "target";
        run.config = nlohmann::json::object();
        run.generations = 5;
        run.id = runs::insert_run(connection, run, "test");
        for (const auto& [generation, best] : {std::pair{0, 0.25}, std::pair{1, 0.625}}) {
            runs::GenerationWrite write;
            write.stats.generation = generation;
            write.stats.best_reward = best;
            write.checkpoint = nlohmann::json::object();
            runs::write_generation(connection, run, write);
        }
    }
    const auto state = runs::read_run_file(dir / "run.db");
    REQUIRE(state);
    CHECK_FALSE(state->finished);
    CHECK(state->generations_done == 1);
    CHECK(state->best_reward == 0.625);
}

TEST_CASE("a folder without campaign.db is no campaign, and a demo folder points to its campaign",
          "[runs][campaign][store][errors]") {
    test::TempDir dir;
    CHECK_THROWS_AS(runs::load_campaign(dir.path()), DataError);
    CHECK_THROWS_WITH(runs::load_campaign(dir.path()), Contains("no campaign here (campaign.db is missing)"));
    std::filesystem::create_directories(dir / "campaign");
    runs::create_campaign_db(dir / "campaign" / "campaign.db", target_only(), {});
    CHECK_THROWS_WITH(runs::load_campaign(dir.path()),
                      Contains("; the campaign is in " + (dir / "campaign").string()));
    CHECK(runs::load_campaign(dir / "campaign").runs.empty());
}
