// The standard-library Python client against a live server gives the
// in-process r_max.

#include <catch2/catch.hpp>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "exp/kb_apply.hpp"
#include "exp/replay.hpp"
#include "report/runs.hpp"
#include "server_process.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;

TEST_CASE("the Python client shapes a behaviour and prints the in-process r_max") {
    REQUIRE(std::system("python3 --version > /dev/null 2>&1") == 0);  // scripts/setup-deps installs python3
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    const auto behaviour = exp::replay_behaviour(dir / "run.db", "best");
    nlohmann::json rows = nlohmann::json::array();
    for (std::size_t r = 0; r < behaviour.size() / 15; ++r) {
        rows.push_back(std::vector<float>(behaviour.begin() + static_cast<long>(r * 15),
                                          behaviour.begin() + static_cast<long>((r + 1) * 15)));
    }
    test::write_file(dir / "behaviour.json", nlohmann::json{{"behaviour", rows}}.dump());
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
