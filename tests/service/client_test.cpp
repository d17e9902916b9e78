// The standard-library Python client against a live server gives the
// in-process r_max.

#include <catch2/catch.hpp>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "exp/kb_apply.hpp"
#include "report/runs.hpp"
#include "runs/replay.hpp"
#include "server_process.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;

TEST_CASE("the Python client shapes a behaviour and prints the in-process r_max", "[service]") {
    REQUIRE(std::system("python3 --version > /dev/null 2>&1") == 0);  // scripts/setup-deps installs python3
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    // the file as a user gets it: stepstone replay --behaviour-json, read back bit for bit
    const auto replayed = test::run_cli(
        {"replay", (dir / "run.db").string(), "--behaviour-json", (dir / "behaviour.json").string()});
    INFO(replayed.err);
    REQUIRE(replayed.exit_code == 0);
    const auto behaviour = runs::replay_behaviour(dir / "run.db", "best");
    const auto document = nlohmann::json::parse(test::read_file(dir / "behaviour.json"));
    REQUIRE(document["behaviour"].size() * 15 == behaviour.size());
    CHECK(document["start"] == 1);
    for (std::size_t r = 0; r < document["behaviour"].size(); ++r) {
        for (std::size_t c = 0; c < 15; ++c) {
            REQUIRE(document["behaviour"][r][c].get<float>() == behaviour[r * 15 + c]);
        }
    }
    // an existing file is kept without --force
    CHECK(test::run_cli(
              {"replay", (dir / "run.db").string(), "--behaviour-json", (dir / "behaviour.json").string()})
              .exit_code != 0);
    const auto expected = exp::shape_policy(dir / "run.db", dir / "run.db", "best", "run");

    servicetest::ServerProcess server({(dir / "run.db").string()}, dir.path());
    const std::string command = std::string("python3 ") + STEPSTONE_SOURCE_DIR +
                                "/examples/python/kb_client.py --url http://127.0.0.1:" + std::to_string(server.port()) +
                                " --kb run --behaviour '" + (dir / "behaviour.json").string() + "' > '" +
                                (dir / "client.out").string() + "' 2>&1";
    REQUIRE(std::system(command.c_str()) == 0);
    const auto out = test::read_file(dir / "client.out");
    CAPTURE(out);
    const auto at = out.find("r_max ");
    REQUIRE(at != std::string::npos);
    // Python prints the shortest text that reads back as the same double
    CHECK(std::stod(out.substr(at + 6)) == expected.r_max);
    CHECK(out.find("kb run: ") == 0);

    // a refusal is one line naming the problem
    const std::string bad = std::string("python3 ") + STEPSTONE_SOURCE_DIR +
                            "/examples/python/kb_client.py --url http://127.0.0.1:" + std::to_string(server.port()) +
                            " --kb nope --behaviour '" + (dir / "behaviour.json").string() + "' > '" +
                            (dir / "bad.out").string() + "' 2>&1";
    CHECK(std::system(bad.c_str()) != 0);
    CHECK(test::read_file(dir / "bad.out") == "kb_client: HTTP 404: no knowledge base \"nope\" here\n");
}
