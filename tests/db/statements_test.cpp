#include <catch2/catch.hpp>

#include "core/embedded.hpp"
#include "core/error.hpp"
#include "db/database.hpp"
#include "db/inspect.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;

TEST_CASE("every statement of sql/ prepares against a freshly migrated database", "[db][sql]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "fresh.db", db::OpenMode::create);
    REQUIRE(!sql_files().empty());
    for (const auto& file : sql_files()) {
        INFO(file.path);
        CHECK(!connection.prepare_all(file.text).empty());
    }
}

TEST_CASE("every parameter of sql/ has a name, so that code binds it by name", "[db][sql]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "fresh.db", db::OpenMode::create);
    for (const auto& file : sql_files()) {
        for (auto& statement : connection.prepare_all(file.text)) {
            for (int i = 1; i <= statement.parameter_count(); ++i) {
                INFO(file.path << " parameter " << i);
                CHECK(statement.parameter_name(i).rfind(':', 0) == 0);
            }
        }
    }
}

TEST_CASE("a parameter name the statement does not have is refused, naming it", "[db][statement]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "s.db", db::OpenMode::create);
    auto select = connection.prepare(db::sql("db/meta_get.sql"));
    CHECK_THROWS_AS(select.bind(":kee", "x"), DatabaseError);
    CHECK_THROWS_WITH(select.bind(":kee", "x"), Catch::Matchers::Contains("no parameter :kee"));
    CHECK_THROWS_WITH(select.bind_null(":value"), Catch::Matchers::Contains("no parameter :value"));
    CHECK_NOTHROW(select.bind(":key", "x"));
}

TEST_CASE("a statement run with a parameter left unbound throws, naming it", "[db][statement]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "s.db", db::OpenMode::create);
    auto set = connection.prepare(db::sql("db/meta_set.sql"));
    set.bind(":key", "k");
    CHECK_THROWS_WITH(set.step(), Catch::Matchers::Contains("parameter :value is not bound"));
    CHECK(db::meta_value(connection, "k").empty());  // nothing was written

    // an explicit NULL counts as bound; reset() forgets every binding
    auto insert = connection.prepare("INSERT INTO meta (key, value) VALUES (:key, :value)");
    insert.bind(":key", "k").bind_null(":value");
    CHECK_THROWS_AS(insert.run(), DatabaseError);  // value is NOT NULL in the schema: SQLite refuses it
    insert.reset();
    insert.bind(":value", "v");
    CHECK_THROWS_WITH(insert.run(), Catch::Matchers::Contains("parameter :key is not bound"));
    insert.reset();
    insert.bind(":key", "k").bind(":value", "v").run();
    CHECK(db::meta_value(connection, "k") == "v");

    // positional parameters are named by their index
    auto positional = connection.prepare("SELECT ?1 + ?2");
    positional.bind(1, 1);
    CHECK_THROWS_WITH(positional.step(), Catch::Matchers::Contains("parameter ?2 is not bound"));
}

TEST_CASE("columns are found by name", "[db][statement]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "s.db", db::OpenMode::create);
    auto select = connection.prepare(db::sql("kb/select_kbs.sql"));
    CHECK(select.column("id") == 0);
    CHECK(select.column("randomized_seed") == select.column_count() - 1);
    CHECK_THROWS_WITH(select.column("seed"), Catch::Matchers::Contains("no column seed"));
}

TEST_CASE("every query of queries/ prepares against a freshly migrated database", "[db][sql]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "fresh.db", db::OpenMode::create);
    for (const auto& file : query_files()) {
        INFO(file.path);
        CHECK(!connection.prepare_all(file.text).empty());
    }
}

TEST_CASE("statements bind and read back every column type", "[db][statement]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "s.db", db::OpenMode::create);
    connection.exec("CREATE TEMP TABLE t (i INTEGER, d REAL, s TEXT, b BLOB, n INTEGER)");
    const std::byte blob[] = {std::byte{1}, std::byte{0}, std::byte{255}};
    auto insert = connection.prepare("INSERT INTO t VALUES (:i, :d, :s, :b, :n)");
    insert.bind(insert.parameter(":i"), std::int64_t{1} << 40)
        .bind(insert.parameter(":d"), 0.1)
        .bind(insert.parameter(":s"), std::string_view("h\xc3\xa9"))
        .bind_blob(insert.parameter(":b"), blob)
        .bind_null(insert.parameter(":n"))
        .run();
    auto select = connection.prepare("SELECT i, d, s, b, n FROM t");
    REQUIRE(select.step());
    CHECK(select.column_int(0) == (std::int64_t{1} << 40));
    CHECK(select.column_double(1) == 0.1);
    CHECK(select.column_text(2) == "h\xc3\xa9");
    auto got = select.column_blob(3);
    REQUIRE(got.size() == 3);
    CHECK(got[2] == std::byte{255});
    CHECK(select.is_null(4));
    CHECK(!select.step());
}
