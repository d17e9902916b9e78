// core/mpi.cpp as compiled into a binary built without Open MPI.
#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "exp/parallel/mpi.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("without Open MPI, --mpi is refused in one line that says how to get it", "[mpi][errors]") {
    CHECK_FALSE(mpi::built());
    CHECK_THROWS_MATCHES(
        mpi::require_built(), ConfigError, Catch::Matchers::Predicate<ConfigError>([](const ConfigError& e) {
            const std::string what = e.what();
            return what.find("built without Open MPI") != std::string::npos &&
                   what.find("libopenmpi-dev") != std::string::npos && what.find('\n') == std::string::npos;
        }));
    CHECK_THROWS_AS(mpi::Session(), ConfigError);
}
