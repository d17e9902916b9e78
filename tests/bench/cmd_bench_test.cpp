#include <catch2/catch.hpp>
#include <cstdlib>

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
    CHECK_THAT(result.out, StartsWith("case,baseline_per_s,candidate_per_s,ratio\n"));
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
    CHECK_THAT(result.out, StartsWith("case,baseline_per_s,candidate_per_s,ratio\nnn,"));
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
