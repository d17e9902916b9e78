// The math fingerprint (core/math_fingerprint.hpp) as a user meets it: in
// --version, in a run file, and in the warning when a run is resumed on a
// machine whose math library rounds differently. The other machine is real:
// with GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA, glibc uses its build of sin, cos and
// pow without FMA instructions, as it does on a CPU that lacks them, and with
// STEPSTONE_NO_AVX2=1 stepstone runs the generic builds of its own kernels.
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "core/cpu.hpp"
#include "db/connection.hpp"
#include "db/database.hpp"
#include "db/inspect.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// glibc picks its FMA builds only on a CPU with FMA and AVX2; elsewhere the
// tunable changes nothing
bool cpu_has_fma() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("fma") && __builtin_cpu_supports("avx2");
}

// the stepstone binary as a machine without FMA and AVX2 runs it
test::CliResult run_elsewhere(const std::vector<std::string>& args) {
    std::vector<std::string> command{"/usr/bin/env", "GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA",
                                     "STEPSTONE_NO_AVX2=1", STEPSTONE_BINARY};
    command.insert(command.end(), args.begin(), args.end());
    return test::run_program(command);
}

// the 16 hex digits after "math fingerprint " in --version's line
std::string fingerprint_of(const test::CliResult& version) {
    const std::string marker = "math fingerprint ";
    const auto at = version.out.find(marker);
    if (at == std::string::npos) return "";
    return version.out.substr(at + marker.size(), 16);
}

// pinned to libm: the machine-dependent math whose fingerprint these tests follow
const char* kTiny = R"({"task": {"kind": "source", "steps_per_start": 100, "starts": 1},
  "ea": {"population_size": 8, "generations": 2}, "math": "libm"})";

}  // namespace

TEST_CASE(
    "the --version line names the math fingerprint (glibc's FMA build or its plain one) and the kernels' "
    "build",
    "[cli][determinism]") {
    const auto here = test::run_cli({"--version"});
    REQUIRE(here.exit_code == 0);
    const std::string fingerprint = fingerprint_of(here);
    CHECK(fingerprint.size() == 16);
    CHECK(fingerprint.find_first_not_of("0123456789abcdef") == std::string::npos);
    CHECK(fingerprint_of(test::run_cli({"--version"})) == fingerprint);
    if (!cpu_has_fma()) {
        WARN("this CPU lacks FMA or AVX2: glibc has no other build to switch to, nothing to compare");
        return;
    }
    const auto elsewhere = run_elsewhere({"--version"});
    REQUIRE(elsewhere.exit_code == 0);
    CHECK(fingerprint_of(elsewhere).size() == 16);
    CHECK(fingerprint_of(elsewhere) != fingerprint);
    // every module's own kernels: the AVX2 builds here (and AVX-512 ones where built and the CPU
    // has it), the generic ones there
    CHECK_THAT(here.out,
               Contains(avx512_kernels_allowed() ? "kernels avx2, avx-512 in core nn)" : "kernels avx2)"));
    CHECK_THAT(elsewhere.out, Contains("kernels generic)"));
}

TEST_CASE(
    "a run file keeps its machine's math fingerprint, and resumed on another kind of machine it warns and "
    "goes "
    "on",
    "[cli][determinism][resume]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", kTiny);
    const auto run = dir / "run.db";
    REQUIRE(test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db", run.string(), "--seed",
                           "3", "--quiet"})
                .exit_code == 0);
    const std::string here = fingerprint_of(test::run_cli({"--version"}));
    {
        auto connection = db::open_database(run, db::OpenMode::read_only);
        CHECK(db::meta_value(connection, "math_fingerprint") == here);
    }

    const auto info = test::run_cli({"db", "info", run.string()});
    CHECK_THAT(info.out, Contains("math            " + here + " (this machine: " + here + ")"));

    // resumed on this machine: no word about it
    const auto same =
        test::run_cli({"evolve", "--db", run.string(), "--resume", "--generations", "3", "--quiet"});
    REQUIRE(same.exit_code == 0);
    CHECK(same.err.empty());
    if (!cpu_has_fma()) {
        WARN("this CPU lacks FMA or AVX2: no other kind of machine to resume on");
        return;
    }

    // resumed elsewhere: one warning line naming both fingerprints, and the run goes on
    const auto elsewhere =
        run_elsewhere({"evolve", "--db", run.string(), "--resume", "--generations", "4", "--quiet"});
    INFO(elsewhere.err);
    REQUIRE(elsewhere.exit_code == 0);
    REQUIRE(elsewhere.err_lines().size() == 1);
    CHECK_THAT(elsewhere.err, Contains("warning") && Contains("rounds differently") && Contains(here) &&
                                  Contains("will not equal those of an uninterrupted run"));
    CHECK(test::generations_done(run) == 4);
    // the file still names the machine that started it
    auto connection = db::open_database(run, db::OpenMode::read_only);
    CHECK(db::meta_value(connection, "math_fingerprint") == here);
}

TEST_CASE("a replay that misses its stored reward names a run made by another math library",
          "[cli][determinism]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", kTiny);
    const auto run = dir / "run.db";
    REQUIRE(test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db", run.string(), "--seed",
                           "3", "--quiet"})
                .exit_code == 0);
    {
        // a stored reward no replay gives
        auto connection = db::open_database(run, db::OpenMode::read_write);
        connection.exec("UPDATE individual SET reward = 0.5");
    }
    const auto same = test::run_cli({"replay", run.string()});
    CHECK(same.exit_code == 1);
    CHECK_THAT(same.err, Contains("replays to reward 0, the run stored 0.5"));
    CHECK_THAT(same.err, !Contains("math library"));

    // the same miss in a run whose file names another machine's fingerprint
    {
        auto connection = db::open_database(run, db::OpenMode::read_write);
        db::set_meta_value(connection, "math_fingerprint", "00000000000000ff");
    }
    const auto other = test::run_cli({"replay", run.string()});
    CHECK(other.exit_code == 1);
    CHECK(other.err_lines().size() == 1);
    CHECK_THAT(other.err, Contains("replays to reward 0, the run stored 0.5") &&
                              Contains("math library rounds differently: math fingerprint 00000000000000ff"));
}

TEST_CASE(
    "a run on portable math, the default, gives the same digest under either math library, where on libm it "
    "may not",
    "[cli][determinism]") {
    if (!cpu_has_fma()) {
        WARN("this CPU lacks FMA or AVX2: glibc has no other build to compare with");
        return;
    }
    test::TempDir dir;
    // seed 6 of this config is one whose libm runs differ between glibc's builds (found by trying seeds 1-6)
    const std::string config = R"({"task": {"kind": "source", "steps_per_start": 1000, "starts": 1},
      "ea": {"population_size": 16, "generations": 8}, "seed": 6)";
    test::write_file(dir / "libm.json", config + R"(, "math": "libm"})");
    test::write_file(dir / "portable.json", config + R"(, "math": "portable"})");
    test::write_file(dir / "default.json", config + "}");
    const auto digests = [&](const std::string& name) {
        const auto args = [&](const std::string& db) {
            return std::vector<std::string>{"evolve", "--config",          (dir / (name + ".json")).string(),
                                            "--db",   (dir / db).string(), "--quiet"};
        };
        REQUIRE(test::run_cli(args(name + "-here.db")).exit_code == 0);
        REQUIRE(run_elsewhere(args(name + "-elsewhere.db")).exit_code == 0);
        return std::pair{test::run_cli({"db", "digest", (dir / (name + "-here.db")).string()}).out,
                         test::run_cli({"db", "digest", (dir / (name + "-elsewhere.db")).string()}).out};
    };
    const auto libm = digests("libm");
    CHECK(libm.first != libm.second);  // the hazard the portable functions remove
    const auto portable = digests("portable");
    CHECK(portable.first.size() == 33);
    CHECK(portable.first == portable.second);
    // and with the AVX2 builds where this machine would take AVX-512 ones
    REQUIRE(test::run_program({"/usr/bin/env", "STEPSTONE_NO_AVX512=1", STEPSTONE_BINARY, "evolve",
                               "--config", (dir / "portable.json").string(), "--db",
                               (dir / "portable-avx2.db").string(), "--quiet"})
                .exit_code == 0);
    CHECK(test::run_cli({"db", "digest", (dir / "portable-avx2.db").string()}).out == portable.first);
    CHECK(portable.first != libm.first);
    // a config that names no math is portable: one digest on both machines, the portable one
    const auto by_default = digests("default");
    CHECK(by_default.first == portable.first);
    CHECK(by_default.second == portable.first);

    // resumed on the other machine, a portable run has nothing to warn about
    const auto resumed = run_elsewhere(
        {"evolve", "--db", (dir / "portable-here.db").string(), "--resume", "--generations", "9", "--quiet"});
    CHECK(resumed.exit_code == 0);
    CHECK(resumed.err.empty());
}

TEST_CASE(
    "simulate --math portable: the simulator takes the portable functions, the same steps under either "
    "library",
    "[cli][determinism]") {
    test::TempDir dir;
    const auto simulate = [&](const std::string& math, const std::string& csv, bool elsewhere) {
        const std::vector<std::string> args{"simulate", "--controller", "scripted",          "--math",
                                            math,       "--csv",        (dir / csv).string()};
        const auto result = elsewhere ? run_elsewhere(args) : test::run_cli(args);
        REQUIRE(result.exit_code == 0);
        return test::read_file(dir / csv);
    };
    const std::string libm = simulate("libm", "libm.csv", false);
    const std::string portable = simulate("portable", "portable.csv", false);
    // the poses are written with 17 digits: the functions' last bits show within the first start
    CHECK(portable != libm);
    CHECK(portable.size() > 12000 * 20);
    if (cpu_has_fma()) CHECK(simulate("portable", "elsewhere.csv", true) == portable);

    const auto bad = test::run_cli({"simulate", "--math", "fast", "--csv", (dir / "x.csv").string()});
    CHECK(bad.exit_code == 2);
    CHECK_THAT(bad.err, Contains("--math must be libm or portable, got 'fast'"));
    CHECK(!std::filesystem::exists(dir / "x.csv"));
}
