#include <catch2/catch.hpp>
#include <cstdlib>

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
