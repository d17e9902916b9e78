#include <catch2/catch.hpp>

#include "core/embedded.hpp"
#include "db/database.hpp"
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
