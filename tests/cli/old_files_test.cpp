// A run file made by stepstone 0.1.0 (commit 9c53c41, libm the default, its stored
// config without "math"), kept as tests/data/old_libm_run.db with the config that
// made it (old_libm_run.json, seed 7, generations 0-3). Its digests were printed
// by that build: 07906dd4... for the file, 5a09a250... for the same config run to
// generation 5. This build must read it as libm, replay it and resume it to them.

#include <catch2/catch.hpp>
#include <string>

#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

const fs::path kData = fs::path(STEPSTONE_SOURCE_DIR) / "tests" / "data";
constexpr const char* kDigestAt3 = "07906dd4e66d6dfc03a72795c2d6704f";
constexpr const char* kDigestAt5 = "5a09a2507708c32e6d968a93b88439dd";
constexpr const char* kFingerprint = "801062b8564c7d29";  // the math library of the machine that made it

std::string digest(const fs::path& run) {
    const auto result = test::run_cli({"db", "digest", run.string()});
    REQUIRE(result.exit_code == 0);
    return result.out.substr(0, 32);
}

}  // namespace

TEST_CASE("a run file of 0.1.0 (libm) keeps its digest, replays and resumes as libm", "[cli][determinism]") {
    test::TempDir dir;
    fs::copy_file(kData / "old_libm_run.db", dir / "run.db");
    CHECK(digest(dir / "run.db") == kDigestAt3);  // schema 6, read as it is (a seeding source may be one)
    REQUIRE(test::run_cli({"db", "migrate", (dir / "run.db").string()}).exit_code == 0);
    CHECK(digest(dir / "run.db") == kDigestAt3);  // migration adds no content
    const auto replay = test::run_cli({"replay", (dir / "run.db").string()});
    INFO(replay.out << replay.err);
    const auto version = test::run_cli({"--version"});
    if (version.out.find(kFingerprint) == std::string::npos) {
        WARN(
            "this machine's math library rounds otherwise than the one that made the file: only its content "
            "is compared");
        return;
    }
    CHECK(replay.exit_code == 0);  // the stored rewards come back: libm, as stored
    // resumed from its stored config, and from the config that made it (which names no math)
    fs::copy_file(dir / "run.db", dir / "again.db");
    REQUIRE(test::run_cli(
                {"evolve", "--db", (dir / "run.db").string(), "--resume", "--generations", "5", "--quiet"})
                .exit_code == 0);
    CHECK(digest(dir / "run.db") == kDigestAt5);
    const auto with_config =
        test::run_cli({"evolve", "--config", (kData / "old_libm_run.json").string(), "--db",
                       (dir / "again.db").string(), "--resume", "--generations", "5", "--quiet"});
    INFO(with_config.err);
    REQUIRE(with_config.exit_code == 0);
    CHECK(digest(dir / "again.db") == kDigestAt5);
}
