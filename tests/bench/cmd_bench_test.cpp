#include <catch2/catch.hpp>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "exp/parallel/mpi.hpp"
#include "support/run_cli.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

TEST_CASE("bench with an unknown case is a one-line config error with exit 2", "[bench][cli][errors]") {
    auto result = test::run_cli({"bench", "no-such-case", "--quick"});
    CHECK(result.exit_code == 2);
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(result.err_lines()[0], StartsWith("stepstone: error: "));
    CHECK_THAT(result.err_lines()[0], Contains("no-such-case"));
    CHECK(result.out.empty());
}

TEST_CASE("bench --help shows an example and --list names the cases of this build", "[bench][cli]") {
    auto result = test::run_cli({"bench", "--help"});
    CHECK(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("Example:"));
    CHECK_THAT(result.out, Contains("stepstone bench"));
    result = test::run_cli({"bench", "--list"});
    CHECK(result.exit_code == 0);
}

TEST_CASE("bench --csv prints the header the docs promise", "[bench][cli]") {
    // an empty selection is impossible from the CLI, so run the cheapest real
    // run: every case of this build, quick
    // the `mpi` case starts mpirun: CI runs as root on few cores
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    ::setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
    auto result = test::run_cli({"bench", "--quick", "--csv"});
    CHECK(result.exit_code == 0);
    CHECK_THAT(result.out,
               StartsWith("case,baseline_per_s,candidate_per_s,ratio,ratio_min,ratio_max,rounds\n"));
    // serve is one case with a parameter: a row a client count, and no other serve rows
    CHECK_THAT(result.out, Contains("\nserve/1,") && Contains("\nserve/2,") && Contains("\nserve/8,"));
    CHECK_THAT(result.out, !Contains("\nserve,") && !Contains("serve-"));
    // every row that ran: its ratio within its rounds' least and greatest, over 3 rounds (--quick)
    std::istringstream lines(result.out);
    std::string line;
    std::getline(lines, line);
    int rows = 0;
    while (std::getline(lines, line)) {
        if (line.ends_with(",,,,,,")) continue;  // a case that cannot run here (mpi without mpirun)
        std::vector<std::string> fields;
        std::istringstream cells(line);
        for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
        INFO(line);
        REQUIRE(fields.size() == 7);
        const double ratio = std::stod(fields[3]);
        CHECK(std::stod(fields[4]) <= ratio);
        CHECK(ratio <= std::stod(fields[5]));
        CHECK(fields[6] == "3");
        ++rows;
    }
    CHECK(rows >= 10);
}

TEST_CASE("bench selects a case with a parameter whole or by one row, and targets it the same way",
          "[bench][cli]") {
    auto list = test::run_cli({"bench", "--list"});
    REQUIRE(list.exit_code == 0);
    CHECK_THAT(list.out, Contains("\nserve/1 ") && Contains("\nserve/2 ") && Contains("\nserve/8 "));
    CHECK_THAT(list.out, Contains("by 8 concurrent clients"));

    // one row, judged against a target given to the whole case: 10^9x is out of reach
    auto result = test::run_cli({"bench", "serve/2", "--quick", "--csv", "--target", "serve=1e9"});
    INFO(result.out << result.err);
    CHECK(result.exit_code == 1);
    CHECK_THAT(result.out, Contains("\nserve/2,") && !Contains("serve/1") && !Contains("serve/8"));
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(result.err_lines()[0],
               Contains("1 case fell short of its target: serve/2 ") && Contains("< 1e+09x"));

    // a row's own target after the case's: the row's wins for that row
    result =
        test::run_cli({"bench", "serve", "--quick", "--target", "serve=1e9", "--target", "serve/8=0.001"});
    INFO(result.out << result.err);
    CHECK(result.exit_code == 1);
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(result.err_lines()[0], Contains("2 cases fell short of their targets: serve/1 ") &&
                                          Contains("serve/2 ") && !Contains("serve/8"));

    for (const char* bad : {"serve/3", "serve/", "sim/1"}) {
        result = test::run_cli({"bench", bad, "--quick"});
        INFO(bad);
        CHECK(result.exit_code == 2);
        REQUIRE(result.err_lines().size() == 1);
        CHECK_THAT(result.err_lines()[0], StartsWith("stepstone: error: unknown bench case"));
    }
}

TEST_CASE("a case that cannot run prints its row with the reason and the others still run", "[bench][cli]") {
    if (!stepstone::mpi::built()) {
        WARN("this build has no MPI case: nothing to check");
        return;
    }
    // no mpirun on PATH: the mpi case cannot start, nn still runs and reports
    const std::string path = std::getenv("PATH") ? std::getenv("PATH") : "";
    ::setenv("PATH", "/nonexistent", 1);
    auto result = test::run_cli({"bench", "mpi", "nn", "--quick"});
    ::setenv("PATH", path.c_str(), 1);
    INFO(result.out << result.err);
    CHECK(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("mpi ") &&
                               Contains("not run: bench mpi: mpirun -np 2 stepstone evolve --mpi failed"));
    const auto nn = result.out.find("\nnn ");
    REQUIRE(nn != std::string::npos);
    const std::string nn_row = result.out.substr(nn + 1, result.out.find('\n', nn + 1) - nn - 1);
    CHECK_THAT(nn_row, !Contains("not run") && Contains("x "));
}

TEST_CASE("bench exits 1 after the whole table when a case falls short of its target", "[bench][cli]") {
    // nn's ratio is some finite positive number: below 10^9x, above 0.01x, whatever the machine
    auto result = test::run_cli({"bench", "nn", "sim", "--quick", "--target", "nn=1e9"});
    INFO(result.out << result.err);
    CHECK(result.exit_code == 1);
    CHECK_THAT(result.out,
               Contains("\nnn ") && Contains("1e+09x") && Contains("\nsim "));  // every row, nn's new target
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(
        result.err_lines()[0],
        StartsWith("stepstone: error: bench: 1 case fell short of its target: nn ") && Contains("< 1e+09x"));

    result = test::run_cli({"bench", "nn", "--quick", "--csv", "--target", "nn=0.01"});
    INFO(result.out << result.err);
    CHECK(result.exit_code == 0);
    CHECK(result.err.empty());
    CHECK_THAT(result.out,
               StartsWith("case,baseline_per_s,candidate_per_s,ratio,ratio_min,ratio_max,rounds\nnn,"));
}

TEST_CASE("a --target that is not CASE=RATIO of a case of this build is refused before anything runs",
          "[bench][cli][errors]") {
    for (const char* bad : {"nn", "nn=", "nn=abc", "nn=0", "nn=-2", "nn=inf", "nn=3x", "no-such-case=2"}) {
        const auto result = test::run_cli({"bench", "nn", "--quick", "--target", bad});
        INFO(bad << ": " << result.out << result.err);
        CHECK(result.exit_code == 2);
        REQUIRE(result.err_lines().size() == 1);
        CHECK_THAT(result.err_lines()[0], StartsWith("stepstone: error: --target"));
        CHECK(result.out.empty());
    }
}
