// A run's status and a campaign run's step: enums in the code, text in the
// files. Their texts are written here by hand (docs/development.md, the schema's
// CHECK constraints), and an unknown stored text must be refused naming it.
#include "runs/run_status.hpp"

#include <catch2/catch.hpp>
#include <utility>

#include "core/error.hpp"
#include "db/database.hpp"
#include "runs/run_store.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE(
    "every status and step has its text both ways, and an unknown text is refused naming the column and the "
    "text",
    "[runs][status]") {
    const std::vector<std::pair<runs::RunStatus, std::string>> statuses = {
        {runs::RunStatus::pending, "pending"},
        {runs::RunStatus::running, "running"},
        {runs::RunStatus::finished, "finished"},
        {runs::RunStatus::failed, "failed"}};
    for (const auto& [status, text] : statuses) {
        INFO(text);
        CHECK(runs::to_string(status) == text);
        CHECK(runs::parse_run_status(text, "run.status") == status);
    }
    const std::vector<std::pair<runs::CampaignStep, std::string>> steps = {
        {runs::CampaignStep::source, "source"}, {runs::CampaignStep::target, "target"}};
    for (const auto& [step, text] : steps) {
        INFO(text);
        CHECK(runs::to_string(step) == text);
        CHECK(runs::parse_campaign_step(text, "campaign_run.step") == step);
    }
    // the caller's name for the column, the accepted texts, then the text found
    CHECK_THROWS_AS(runs::parse_run_status("done", "a.db: run.status"), DatabaseError);
    CHECK_THROWS_WITH(runs::parse_run_status("done", "a.db: run.status"),
                      "a.db: run.status must be one of pending|running|finished|failed, got \"done\"");
    CHECK_THROWS_AS(runs::parse_campaign_step("", "c.db: campaign_run.step"), DatabaseError);
    CHECK_THROWS_WITH(runs::parse_campaign_step("Source", "c.db: campaign_run.step"),
                      "c.db: campaign_run.step must be one of source|target, got \"Source\"");
}

TEST_CASE("a run file holding an unknown status is refused when read, naming the file and the column",
          "[runs][status]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "run.db", db::OpenMode::create);
    runs::RunRecord run;
    run.task = "source";
    run.config = nlohmann::json::object();
    runs::insert_run(connection, run, "test");
    CHECK(runs::load_run(connection).status == runs::RunStatus::running);
    // the schema's CHECK refuses it too; a file written by other means may still hold it
    connection.exec("PRAGMA ignore_check_constraints = ON; UPDATE run SET status = 'paused'");
    CHECK_THROWS_AS(runs::load_run(connection), DatabaseError);
    CHECK_THROWS_WITH(runs::load_run(connection),
                      Contains("run.db: run.status must be one of pending|running|finished|failed") &&
                          Contains("\"paused\""));
}
