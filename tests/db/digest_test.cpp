#include <catch2/catch.hpp>

#include "db/database.hpp"
#include "db/digest.hpp"
#include "support/db_files.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;

namespace {

// a run with two individuals, inserted in the given order, with a given wall time
std::string digest_of(const std::filesystem::path& path, bool reversed, double wall_time,
                      double reward = 0.25, int pickups = 2) {
    auto connection = db::open_database(path, db::OpenMode::create);
    connection.exec(
        "INSERT INTO run (id, task, seed, config, status, generations, program_version, created) "
        "VALUES (1, 'source', 7, '{}', 'finished', 1, 'x', 'now')");
    connection.exec("INSERT INTO generation VALUES (1, 0, 0.25, 0.1, 0.1, '[2]', 1.0, 2.0, 2, " +
                    std::to_string(wall_time) + ", 0.5, 0, 0.1, 0.01, " +
                    std::to_string(wall_time / 10) + ")");
    const std::string columns =
        "INSERT INTO individual (run_id, id, generation, parent_id, reward, fitness, diversity, r_max, "
        "balls, "
        "steps, presses, pickups, carry_steps, basket_releases) VALUES ";
    const std::string a = columns + "(1, 1, 0, NULL, " + std::to_string(reward) +
                          ", 0.25, 3.5, NULL, 6, 12000, 3, " + std::to_string(pickups) + ", 400, 6)";
    const std::string b = columns + "(1, 2, 0, NULL, 0.0, 0.0, 3.5, NULL, 0, 101, 0, 0, 0, 0)";
    connection.exec(reversed ? b + ";" + a : a + ";" + b);
    return db::run_digest(connection);
}

}  // namespace

TEST_CASE("the run digest ignores row order and timings but not results", "[db][digest]") {
    test::TempDir dir;
    const auto base = digest_of(dir / "a.db", false, 1.0);
    CHECK(base.size() == 32);
    // same content inserted in another order, another wall time and date
    CHECK(digest_of(dir / "b.db", true, 99.0) == base);
    // one objective differs
    CHECK(digest_of(dir / "c.db", false, 1.0, 0.5) != base);
    // one milestone differs
    CHECK(digest_of(dir / "d.db", false, 1.0, 0.25, 3) != base);
}

TEST_CASE("a file of schema 7 reads its KB score as r_max, read-only and migrated, with its digest",
          "[db][digest][migrate]") {
    test::TempDir dir;
    const auto path = dir / "seven.db";
    digest_of(path, false, 1.0);
    test::raw_exec(path, "UPDATE individual SET r_max = 0.125 WHERE id = 1");
    const std::string recorded = [&] {
        auto connection = db::open_database(path, db::OpenMode::read_only);
        return db::run_digest(connection);
    }();
    // the file as schema 7 wrote it: the score in a column named shaping
    test::raw_exec(path, "ALTER TABLE individual RENAME COLUMN r_max TO shaping; PRAGMA user_version = 7");
    const auto score = [](db::Connection& connection, const std::string& column) {
        auto statement = connection.prepare("SELECT " + column + " FROM individual WHERE id = 1");
        REQUIRE(statement.step());
        return statement.column_double(0);
    };
    {
        auto connection = db::open_database(path, db::OpenMode::read_only);
        CHECK(score(connection, "r_max") == 0.125);
        CHECK(score(connection, "shaping") == 0.125);
        CHECK(db::run_digest(connection) == recorded);
        CHECK(connection.query_int("PRAGMA user_version") == 7);  // read-only: the file is not migrated
    }
    {
        auto connection = db::open_database(path, db::OpenMode::read_write);
        CHECK(connection.query_int("PRAGMA user_version") >= 8);
        CHECK(score(connection, "r_max") == 0.125);
        CHECK(connection.query_int("SELECT count(*) FROM pragma_table_info('individual') WHERE name = 'shaping'") ==
              0);
        CHECK(db::run_digest(connection) == recorded);
    }
}
