// stepstone campaign and stepstone stats, end to end on tiny campaigns.
#include "exp/campaign/campaign.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "kb/oracle.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// one source run feeding a KB every generation, then 5 treatments x 2 seeds
std::string campaign_json(int target_generations, int steps = 200) {
    return R"({
  "source": {
    "config": {
      "task": {"kind": "source", "steps_per_start": 200, "starts": 1},
      "ea": {"population_size": 8},
      "kb": {"segment_width": 20, "delta": 1.83, "period": 1}
    },
    "seeds": [4],
    "generations": 3
  },
  "kb": {"from": "best"},
  "randomize_seed": 9,
  "target": {
    "config": {"task": {"kind": "target", "steps_per_start": )" +
           std::to_string(steps) + R"(, "starts": 1}, "ea": {"population_size": 8}},
    "runs": 2,
    "generations": )" +
           std::to_string(target_generations) + R"(
  }
})";
}

test::CliResult campaign(const test::TempDir& dir, const std::string& name, const std::vector<std::string>& extra) {
    std::vector<std::string> args{"campaign", (dir / "c.json").string(), "--dir", (dir / name).string(), "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_cli(args);
}

// campaign_run.id -> digest, for the runs recorded finished
std::map<std::int64_t, std::string> digests(const std::filesystem::path& dir) {
    auto connection = db::open_database(dir / "campaign.db", db::OpenMode::read_only);
    auto rows = connection.prepare("SELECT id, digest FROM campaign_run WHERE status = 'finished' ORDER BY id");
    std::map<std::int64_t, std::string> out;
    while (rows.step()) out[rows.column_int(0)] = rows.column_text(1);
    return out;
}

std::int64_t finished_runs(const std::filesystem::path& dir) {
    try {
        auto connection = db::open_database(dir / "campaign.db", db::OpenMode::read_only);
        return connection.query_int("SELECT count(*) FROM campaign_run WHERE status = 'finished'").value_or(0);
    } catch (const std::exception&) {
        return 0;
    }
}

// every generation of a run file gets best_reward = value (its best-of-run at any generation)
void set_best(const std::filesystem::path& run, double value) {
    auto connection = db::open_database(run, db::OpenMode::read_write);
    auto update = connection.prepare("UPDATE generation SET best_reward = ?1");
    update.bind(1, value);
    update.step();
}

// best-of-run rewards chosen by hand for seeds 1 and 2 of each treatment
void set_hand_bests(const std::filesystem::path& camp) {
    const std::map<std::string, std::pair<double, double>> best = {{"none", {0.125, 0.25}},
                                                                   {"sum", {0.625, 0.75}},
                                                                   {"mo", {0.375, 0.875}},
                                                                   {"sum-rand", {0.0, 0.0}},
                                                                   {"mo-rand", {0.0, 0.5}}};
    for (const auto& [treatment, values] : best) {
        set_best(camp / "target" / treatment / "seed-1.db", values.first);
        set_best(camp / "target" / treatment / "seed-2.db", values.second);
    }
}

// r_max by hand for the sum runs (seed 1: 0.875 before generation 2, 0.25 in
// it; seed 2: 0.75 throughout), and 3 ball-collecting policies in mo seed 1
void set_hand_signal(const std::filesystem::path& camp) {
    {
        auto connection = db::open_database(camp / "target" / "sum" / "seed-1.db", db::OpenMode::read_write);
        connection.exec("UPDATE individual SET shaping = CASE WHEN generation = 2 THEN 0.25 ELSE 0.875 END");
    }
    {
        auto connection = db::open_database(camp / "target" / "sum" / "seed-2.db", db::OpenMode::read_write);
        connection.exec("UPDATE individual SET shaping = 0.75");
    }
    auto connection = db::open_database(camp / "target" / "mo" / "seed-1.db", db::OpenMode::read_write);
    connection.exec(
        "UPDATE individual SET balls = CASE WHEN id IN (SELECT id FROM individual ORDER BY id LIMIT 3) "
        "THEN 2 ELSE 0 END");
}

}  // namespace

TEST_CASE("campaign runs every step, and each run equals the same evolve run alone", "[exp][campaign][cli]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(2));
    const auto result = campaign(dir, "camp", {"--jobs", "2"});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("runs 11") && Contains("finished 11") && Contains("failed 0"));
    const auto camp = dir / "camp";
    for (const char* file : {"campaign.db", "kb/kb.db", "kb/kb-rand.db", "source/seed-4.db", "target/none/seed-1.db",
                             "target/sum/seed-2.db", "target/mo/seed-1.db", "target/sum-rand/seed-2.db",
                             "target/mo-rand/seed-1.db"}) {
        INFO(file);
        CHECK(std::filesystem::exists(camp / file));
    }
    CHECK(digests(camp).size() == 11);

    // the sum run of seed 2, made by hand with the campaign's own KB, is the same run
    const auto alone = test::run_cli({"evolve", "--config", (camp / "config" / "target.json").string(), "--db",
                                      (dir / "alone.db").string(), "--seed", "2", "--generations", "2", "--kb",
                                      (camp / "kb" / "kb.db").string(), "--treatment", "sum", "--quiet"});
    REQUIRE(alone.exit_code == 0);
    CHECK(test::file_digest(dir / "alone.db") == test::file_digest(camp / "target" / "sum" / "seed-2.db"));

    // a second start in the same directory is refused; --resume has nothing left to do
    const auto again = campaign(dir, "camp", {});
    CHECK(again.exit_code == 2);
    CHECK_THAT(again.err, Contains("already holds a campaign") && Contains("--resume"));
    const auto resumed = campaign(dir, "camp", {"--resume"});
    CHECK(resumed.exit_code == 0);
    CHECK_THAT(resumed.out, Contains("already_finished 11"));
}

TEST_CASE("a campaign with kb.delta uses the best source run's KB coarsened to that delta",
          "[exp][campaign][cli][coarsen]") {
    test::TempDir dir;
    auto json = campaign_json(1);
    const std::string from = R"("kb": {"from": "best"})";
    json.replace(json.find(from), from.size(), R"("kb": {"from": "best", "delta": 4})");
    test::write_file(dir / "c.json", json);
    const auto result = campaign(dir, "camp", {"--jobs", "2"});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    const auto camp = dir / "camp";
    // the expectation: the source run's stored KB coarsened by the linear-scan KB of
    // tests/kb/oracle.hpp (its segments observed in id order under delta 4, carrying their
    // statistics, as docs/knowledge_base.md describes), not by the library's coarsened().
    // This tiny source run scores nothing, so every cum_reward is 0 and the counts carry the
    // check; kb_cli's kb export --delta test gives the same coarsening rewards that differ
    auto source = db::open_database(camp / "source" / "seed-4.db", db::OpenMode::read_only);
    const auto fine = db::load_kb(source, "run").kb;
    ::kbtest::OracleKb expected;
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

TEST_CASE("a campaign killed mid-way and resumed gives the digests of an uninterrupted one", "[exp][campaign][cli][resume][slow]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(6, 1000));
    REQUIRE(campaign(dir, "whole", {"--jobs", "2"}).exit_code == 0);

    const auto killed = dir / "killed";
    test::run_cli_killed_when({"campaign", (dir / "c.json").string(), "--dir", killed.string(), "--jobs", "1",
                               "--quiet"},
                              [&] { return finished_runs(killed) >= 4; });
    const auto done_before = finished_runs(killed);
    CHECK(done_before >= 4);
    CHECK(done_before < 11);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the orphaned run gets its SIGTERM

    const auto resumed = campaign(dir, "killed", {"--resume", "--jobs", "2"});
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    const auto after = digests(killed);
    const auto whole = digests(dir / "whole");
    CHECK(after.size() == 11);
    for (const auto& [id, digest] : whole) {
        INFO("campaign_run " << id << " (" << done_before << " finished before the kill)");
        CHECK(after.count(id) == 1);
        if (after.count(id)) CHECK(after.at(id) == digest);
    }
}

TEST_CASE("stats on a campaign: success counts, quartiles and tests by hand", "[exp][campaign][stats][cli]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(2));
    REQUIRE(campaign(dir, "camp", {"--jobs", "2"}).exit_code == 0);
    const auto camp = dir / "camp";
    set_hand_bests(camp);
    set_hand_signal(camp);
    const auto result = test::run_cli({"stats", camp.string(), "--runs-csv", (dir / "runs.csv").string(),
                                       "--tests-csv", (dir / "tests.csv").string(), "--csv",
                                       (dir / "success.csv").string()});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);

    const auto runs = test::read_file(dir / "runs.csv");
    CHECK_THAT(runs,
               Contains("treatment,seed,generation,best_reward,success,policies,ball_policies,mean_r_max\n"));
    // population 8: generation 0 evaluates 2 x 8 (ea.initial_multiplier), generations 1 and 2 eight
    // children each, so 32 policies; mean r_max over generations 0-2 (the window of 10 reaches
    // back to 0): sum seed 1 (24 x 0.875 + 8 x 0.25) / 32 = 0.71875, seed 2 0.75
    CHECK_THAT(runs, Contains("none,1,2,0.125,0,32,0,\n") && Contains("sum,2,2,0.75,1,32,0,0.75\n") &&
                         Contains("mo-rand,2,2,0.5,1,32,0,"));
    CHECK_THAT(runs, Contains("sum,1,2,0.625,1,32,0,0.71875\n") && Contains("mo,1,2,0.375,0,32,3,"));
    // the text: sum's r_max is the mean of its runs' (0.71875 + 0.75) / 2 = 0.734375 (%.4g: 0.7344),
    // none has no KB, mo's 3 ball-collecting policies are counted
    CHECK_THAT(result.out, Contains("none              -           64          0\n") &&
                               Contains("sum          0.7344           64          0\n") &&
                               Contains("mo  ") && Contains("64          3\n"));
    // --signal-window 1: generation 2 alone, so sum's runs give 0.25 and 0.75
    const auto last = test::run_cli({"stats", camp.string(), "--signal-window", "1"});
    REQUIRE(last.exit_code == 0);
    CHECK_THAT(last.out,
               Contains("mean r_max of generations 2-2") && Contains("sum             0.5           64"));
    const auto bad = test::run_cli({"stats", camp.string(), "--signal-window", "0"});
    CHECK(bad.exit_code == 2);
    CHECK_THAT(bad.err, Contains("--signal-window must be >= 1, got 0"));
    // success (>= 0.5) by generation: every generation holds the same best here
    CHECK(test::read_file(dir / "success.csv") ==
          "generation,none,sum,mo,sum-rand,mo-rand\n0,0,2,1,0,1\n1,0,2,1,0,1\n2,0,2,1,0,1\n");

    const auto tests = test::read_file(dir / "tests.csv");
    CHECK_THAT(tests, Contains("treatment_a,treatment_b,n_a,n_b,u,p,p_holm,a12,method,p_auto,p_se\n"));
    // 2 runs an arm: every p is the permutation p (SciPy's exact p where no value ties)
    // none {0.125, 0.25} vs sum {0.625, 0.75}: U = 0, no ties: p = 2 x 1/C(4,2) = 1/3; A12 = 0
    CHECK_THAT(tests, Contains("none,sum,2,2,0,0.333333333333333"));
    // none vs mo {0.375, 0.875}: U = 0 again
    CHECK_THAT(tests, Contains("none,mo,2,2,0,0.333333333333333"));
    // sum vs mo: 0.625 > 0.375, 0.75 > 0.375, the others lose: U = 2 = n_a n_b / 2, p = 1, A12 = 0.5
    CHECK_THAT(tests, Contains("sum,mo,2,2,2,1,1,0.5,permutation,1,\n"));
    // sum-rand {0, 0} vs mo-rand {0, 0.5}: U = 2 x 0.5 = 1 (each 0 ties with mo-rand's 0). Permutation:
    // mid-ranks 2, 2 | 2, 4, sum-rand's rank sum 4 against a mean of 5; the 6 relabellings give 4
    // (3 ways) or 6 (3 ways), all as far from 5: p = 1. The normal approximation (p_auto): U_b = 3,
    // tie term t = 3 zeros: sigma^2 = 4/12 (5 - (27 - 3)/(4 x 3)) = 1, z = (3 - 2 - 0.5) / 1 = 0.5,
    // p = erfc(0.5 / sqrt 2) = 0.6170750774519738 (Python's math.erfc)
    CHECK_THAT(tests, Contains("sum-rand,mo-rand,2,2,1,1,1,0.25,permutation,0.61707507745197"));
    CHECK_THAT(result.out, Contains("sum            2        2"));
}

TEST_CASE("stats --available compares the runs that have reached the generation and lists the others",
          "[exp][campaign][stats][cli]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(2));
    REQUIRE(campaign(dir, "camp", {"--jobs", "2"}).exit_code == 0);
    const auto camp = dir / "camp";
    set_hand_bests(camp);
    // as a running campaign leaves them: one run not started, one at generation 0 of 2
    std::filesystem::remove(camp / "target" / "mo" / "seed-2.db");
    {
        auto connection = db::open_database(camp / "target" / "sum" / "seed-1.db", db::OpenMode::read_write);
        connection.exec("DELETE FROM generation WHERE generation > 0");
    }
    REQUIRE(test::run_cli({"stats", camp.string()}).exit_code == 1);  // without the flag: refused

    const auto result =
        test::run_cli({"stats", camp.string(), "--available", "--runs-csv", (dir / "runs.csv").string(),
                       "--tests-csv", (dir / "tests.csv").string()});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("2 target runs not yet at generation 2 left out") &&
                               Contains("target/sum/seed-1.db") && Contains("target/mo/seed-2.db"));
    const auto runs = test::read_file(dir / "runs.csv");
    CHECK(std::count(runs.begin(), runs.end(), '\n') == 1 + 8);
    CHECK_THAT(runs, Contains("sum,2,2,0.75,1,32,") && Contains("mo,1,2,0.375,0,32,"));
    CHECK_THAT(runs, !Contains("sum,1,") && !Contains("mo,2,"));
    // none {0.125, 0.25} vs sum {0.75}: U = 0, exact p = 2 x 1/C(3,1) = 2/3
    const auto tests = test::read_file(dir / "tests.csv");
    CHECK_THAT(tests, Contains("none,sum,2,1,0,0.66666666666666"));

    // generation 2 is the last the runs are asked for; 0 reached by every started run
    const auto beyond = test::run_cli({"stats", camp.string(), "--available", "--generation", "7"});
    CHECK(beyond.exit_code == 2);
    CHECK(beyond.err_lines().size() == 1);
    CHECK_THAT(beyond.err,
               Contains("--generation 7 is beyond the 2 generations") && Contains("use --generation 2"));
    // every run back at generation 0: none has reached 1 yet
    for (const auto& entry : std::filesystem::recursive_directory_iterator(camp / "target")) {
        if (entry.path().extension() != ".db") continue;
        auto connection = db::open_database(entry.path(), db::OpenMode::read_write);
        connection.exec("DELETE FROM generation WHERE generation > 0");
    }
    const auto none_reached = test::run_cli({"stats", camp.string(), "--available", "--generation", "1"});
    CHECK(none_reached.exit_code == 1);
    CHECK(none_reached.err_lines().size() == 1);
    CHECK_THAT(none_reached.err, Contains("no target run has reached generation 1 yet"));
}

TEST_CASE("stats reports a missing, corrupt or unfinished run file", "[exp][campaign][stats][cli][errors]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(2));
    REQUIRE(campaign(dir, "camp", {"--jobs", "2"}).exit_code == 0);
    const auto camp = dir / "camp";

    SECTION("threshold outside [0, 1]") {
        const auto result = test::run_cli({"stats", camp.string(), "--threshold", "1.5"});
        CHECK(result.exit_code == 2);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains("--threshold must be within [0, 1]"));
    }
    SECTION("a generation beyond the runs' last") {
        // resuming cannot reach it: a usage error naming the last one
        const auto result = test::run_cli({"stats", camp.string(), "--generation", "5"});
        CHECK(result.exit_code == 2);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err,
                   Contains("--generation 5 is beyond the 2 generations") && Contains("use --generation 2"));
    }
    SECTION("a generation an unfinished run has not reached") {
        {
            auto connection =
                db::open_database(camp / "target" / "sum" / "seed-1.db", db::OpenMode::read_write);
            connection.exec("DELETE FROM generation WHERE generation > 0");
        }
        const auto result = test::run_cli({"stats", camp.string(), "--generation", "2"});
        CHECK(result.exit_code == 1);
        CHECK_THAT(result.err, Contains("has reached generation 0 of 2") && Contains("resume the campaign"));
    }
    SECTION("a missing run file") {
        std::filesystem::remove(camp / "target" / "mo" / "seed-2.db");
        const auto result = test::run_cli({"stats", camp.string()});
        CHECK(result.exit_code == 1);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains("target/mo/seed-2.db") && Contains("missing"));
    }
    SECTION("a corrupt run file") {
        test::write_file(camp / "target" / "sum" / "seed-1.db", std::string(4096, 'x'));
        const auto result = test::run_cli({"stats", camp.string()});
        CHECK(result.exit_code == 1);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains("seed-1.db"));
    }
    SECTION("a run file swapped with another") {
        std::filesystem::copy_file(camp / "target" / "sum" / "seed-1.db", camp / "target" / "mo" / "seed-1.db",
                                   std::filesystem::copy_options::overwrite_existing);
        const auto result = test::run_cli({"stats", camp.string()});
        CHECK(result.exit_code == 1);
        CHECK_THAT(result.err, Contains("campaign.db expects seed 1 treatment mo"));
    }
}

TEST_CASE("bad campaign input: one line, exit 2, nothing started", "[exp][campaign][cli][errors]") {
    test::TempDir dir;
    struct Case {
        std::string json;
        std::string message;
    };
    const std::vector<Case> cases = {
        {R"({"target": {"config": {"task": {"kind": "target"}}, "treatments": ["sum", "best"]}, "kb": {"file": "k.db"}})",
         "target.treatments must be one of none, sum, mo, sum-rand, mo-rand, got \"best\""},
        {R"({"target": {"config": {"task": {"kind": "target"}}, "treatments": ["sum"]}})", "needs kb.file"},
        {R"({"target": {"config": {"task": {"kind": "target"}}}, "kb": {"file": "nowhere.db"}})", "does not exist"},
        {R"({"source": {"config": {"task": {"kind": "source"}}}, "target": {"config": {"task": {"kind": "target"}}}})",
         "source.config has no kb block"},
        {R"({"target": {"config": {"task": {"kind": "target"}}, "treatments": ["none"], "seeds": [1, 1]}})",
         "target.seeds repeats a seed"},
        {R"({"target": {"config": "missing.json", "treatments": ["none"]}})", "missing.json"},
        {R"({"target": {"config": {"task": {"kind": "target"}}, "treatments": ["none"], "gens": 3}})",
         "target.gens: unknown key"},
    };
    for (const auto& c : cases) {
        INFO(c.json);
        test::write_file(dir / "c.json", c.json);
        const auto result = campaign(dir, "camp", {});
        CHECK(result.exit_code == 2);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains(c.message));
        CHECK(!std::filesystem::exists(dir / "camp"));
    }

    // resuming with another config is refused and leaves the campaign as it was
    test::write_file(dir / "c.json", campaign_json(1));
    REQUIRE(campaign(dir, "camp", {}).exit_code == 0);
    const auto before = digests(dir / "camp");
    test::write_file(dir / "c.json", campaign_json(2));
    const auto changed = campaign(dir, "camp", {"--resume"});
    CHECK(changed.exit_code == 2);
    CHECK_THAT(changed.err, Contains("the config differs from the campaign's at target.generations"));
    CHECK(digests(dir / "camp") == before);
}

TEST_CASE("campaign --dry-run prints the plan and its cost without touching the disk", "[exp][campaign][cli]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(2));
    const auto result = test::run_cli({"campaign", (dir / "c.json").string(), "--dry-run"});
    REQUIRE(result.exit_code == 0);
    // 1 source run: (2 + 3) x 8 = 40 evaluations; 10 target runs: (2 + 2) x 8 = 32 each
    CHECK_THAT(result.out, Contains("11 runs, 360 evaluations"));
    // 40 x 200 + 320 x 200 steps (one start each)
    CHECK_THAT(result.out, Contains("at most 7.2e+04 robot steps"));
    // nothing but the config in the directory
    CHECK(std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator()) == 1);
}

TEST_CASE("every example campaign parses, and the demo's KB fixture loads with rewards spread over a range",
          "[exp][campaign][examples]") {
    const std::filesystem::path examples = std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples";
    int parsed = 0;
    for (const auto& entry : std::filesystem::directory_iterator(examples)) {
        const auto name = entry.path().filename().string();
        if (name.rfind("campaign_", 0) != 0 || entry.path().extension() != ".json") continue;
        INFO(name);
        CHECK_NOTHROW(runs::CampaignConfig::load(entry.path()));
        ++parsed;
    }
    CHECK(parsed >= 3);
    const auto replication = runs::CampaignConfig::load(examples / "campaign_replication.json");
    REQUIRE(replication.source);
    CHECK(replication.source->config.ea.population_size == 200);  // the paper's source run
    CHECK(replication.source->generations == 4000);
    CHECK(replication.treatments.size() == 5);
    CHECK(replication.target.config.task.starts == 3);

    // the quick campaign's KB is the shipped fixture: a paper-size source run's KB, coarsened
    const auto quick = runs::CampaignConfig::load(examples / "campaign_quick.json");
    REQUIRE(quick.kb_from == runs::KbFrom::file);
    CHECK(quick.kb_file.extension() == ".gz");
    CHECK(std::filesystem::file_size(quick.kb_file) < (1u << 20));  // committed: under 1 MiB
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
    "SIGTERM stops a campaign cleanly: runs end their generation, nothing is left running, resume equals "
    "whole",
    "[exp][campaign][cli][resume][signals]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(60, 1000));
    REQUIRE(campaign(dir, "whole", {"--jobs", "2"}).exit_code == 0);

    const auto stopped = dir / "stopped";
    double seconds = -1;
    const auto result = test::run_cli_signalled_when(
        {"campaign", (dir / "c.json").string(), "--dir", stopped.string(), "--jobs", "2", "--quiet"},
        [&] { return finished_runs(stopped) >= 2; }, [] {}, SIGTERM, &seconds);
    INFO(result.err);
    CHECK(result.exit_code == 130);
    CHECK(seconds < 10);  // each run ends the generation it is in (~0.05 s here), not the run
    const auto done_before = finished_runs(stopped);
    CHECK(done_before < 11);
    REQUIRE_FALSE(result.err_lines().empty());
    CHECK_THAT(result.err_lines().back(),
               Contains("campaign stopped with " + std::to_string(done_before) + " of 11 runs finished") &&
                   Contains("continue with --resume"));
    {
        auto connection = db::open_database(stopped / "campaign.db", db::OpenMode::read_only);
        CHECK(connection.query_int(
                  "SELECT count(*) FROM campaign_run WHERE status IN ('running', 'failed')") == 0);
    }
    // every file closed as evolve closes it on a stop: no WAL beside any of them
    for (const auto& entry : std::filesystem::recursive_directory_iterator(stopped)) {
        const auto name = entry.path().filename().string();
        INFO(entry.path());
        CHECK_FALSE((name.ends_with("-wal") || name.ends_with("-shm")));
    }
    const auto resumed = campaign(dir, "stopped", {"--resume", "--jobs", "2"});
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    CHECK(digests(stopped) == digests(dir / "whole"));
}

TEST_CASE("a campaign keeps kb.file as its config gives it, and resumes one that stored the absolute path",
          "[exp][campaign][cli][kb]") {
    test::TempDir dir;
    const auto fixture = std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples/fixtures/demo_kb.db.gz";
    const std::string given = std::filesystem::relative(fixture, dir.path()).string();
    REQUIRE(given.rfind("..", 0) == 0);  // a relative path, from the config's folder
    test::write_file(
        dir / "c.json",
        R"({"kb": {"file": ")" + given +
            R"("}, "target": {"config": {"task": {"kind": "target", "steps_per_start": 100, "starts": 1}, "ea": {"population_size": 8}}, "runs": 1, "generations": 1, "treatments": ["sum"]}})");
    const auto made = campaign(dir, "camp", {});
    INFO(made.err);
    REQUIRE(made.exit_code == 0);
    const auto text_of = [&](const std::string& sql) {
        auto connection = db::open_database(dir / "camp" / "campaign.db", db::OpenMode::read_only);
        auto row = connection.prepare(sql);
        REQUIRE(row.step());
        return row.column_text(0);
    };
    const auto stored_config = [&] { return nlohmann::json::parse(text_of("SELECT config FROM campaign")); };
    CHECK(stored_config()["kb"]["file"] == given);
    CHECK(text_of("SELECT made_from FROM campaign_kb WHERE name = 'kb'") == "copy of " + given);
    // a campaign made before: its campaign.db holds the absolute path of the same file
    {
        auto connection = db::open_database(dir / "camp" / "campaign.db", db::OpenMode::read_write);
        auto config = stored_config();
        config["kb"]["file"] = std::filesystem::weakly_canonical(fixture).string();
        auto update = connection.prepare("UPDATE campaign SET config = :config");
        update.bind(":config", config.dump()).step();
    }
    const auto resumed = campaign(dir, "camp", {"--resume"});
    INFO(resumed.err);
    CHECK(resumed.exit_code == 0);
}
