#include <catch2/catch.hpp>
#include <filesystem>

#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using Catch::Matchers::Contains;
using stepstone::test::run_cli;
using stepstone::test::TempDir;

TEST_CASE("simulate writes one CSV row per step and the same file on every run",
          "[cli][simulate][determinism]") {
    const TempDir dir;
    const auto a = (dir / "a.csv").string();
    const auto b = (dir / "b.csv").string();
    const std::vector<std::string> args{"simulate", "--task",  "target", "--controller", "random", "--seed",
                                        "5",        "--steps", "50",     "--starts",     "2",      "--csv"};
    auto with = [&](const std::string& file) {
        auto v = args;
        v.push_back(file);
        return v;
    };
    const auto first = run_cli(with(a));
    REQUIRE(first.exit_code == 0);
    CHECK_THAT(first.out, Contains("reward"));
    REQUIRE(run_cli(with(b)).exit_code == 0);
    const auto text = stepstone::test::read_file(a);
    CHECK(text == stepstone::test::read_file(b));
    // header + 2 starts x 50 steps (a random controller rarely stays still)
    CHECK(std::count(text.begin(), text.end(), '\n') == 101);
    CHECK(text.rfind("start,step,x,y,heading,laser_p45", 0) == 0);
    // starts are numbered 1 and 2 (render --start's numbers), steps from 0
    CHECK_THAT(text, Contains("\n1,0,") && Contains("\n1,49,") && Contains("\n2,0,") && Contains("\n2,49,"));
    CHECK_FALSE(text.find("\n0,") != std::string::npos);
}

TEST_CASE("simulate refuses an existing file unless forced", "[cli][simulate][errors]") {
    const TempDir dir;
    const auto file = dir / "out.csv";
    stepstone::test::write_file(file, "keep me\n");
    const auto run = run_cli({"simulate", "--steps", "10", "--starts", "1", "--csv", file.string()});
    CHECK(run.exit_code == 2);
    REQUIRE(run.err_lines().size() == 1);
    CHECK_THAT(run.err, Contains("out.csv") && Contains("--force"));
    CHECK(stepstone::test::read_file(file) == "keep me\n");
    CHECK(run_cli({"simulate", "--steps", "10", "--starts", "1", "--csv", file.string(), "--force"})
              .exit_code == 0);
    CHECK(stepstone::test::read_file(file) != "keep me\n");
}

TEST_CASE("simulate rejects bad flag values with one line naming the flag", "[cli][simulate][errors]") {
    const TempDir dir;
    const auto file = (dir / "x.csv").string();
    for (const auto& [flag, value] : std::vector<std::pair<std::string, std::string>>{
             {"--task", "middle"}, {"--controller", "smart"}, {"--steps", "0"}, {"--starts", "4"}}) {
        const auto run = run_cli({"simulate", flag, value, "--csv", file});
        CHECK(run.exit_code == 2);
        REQUIRE(run.err_lines().size() == 1);
        CHECK_THAT(run.err, Contains(flag));
    }
    CHECK_FALSE(std::filesystem::exists(file));
    CHECK(run_cli({"simulate", "--help"}).out.find("Example:") != std::string::npos);
}
