#include "db/database.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cctype>
#include <functional>

#include "core/error.hpp"
#include "db/inspect.hpp"
#include "support/db_files.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

namespace fs = std::filesystem;

// the migration files of the source tree's schema/ folder, read from disk, by name
std::vector<fs::path> schema_files_on_disk() {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(fs::path(STEPSTONE_SOURCE_DIR) / "schema")) {
        if (entry.path().extension() == ".sql") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

// the identifier after each occurrence of `keyword` in `sql`
std::vector<std::string> names_after(const std::string& sql, const std::string& keyword) {
    std::vector<std::string> names;
    for (auto at = sql.find(keyword); at != std::string::npos; at = sql.find(keyword, at + 1)) {
        auto begin = at + keyword.size();
        while (begin < sql.size() && sql[begin] == ' ') ++begin;
        auto end = begin;
        while (end < sql.size() && (std::isalnum(static_cast<unsigned char>(sql[end])) || sql[end] == '_'))
            ++end;
        names.push_back(sql.substr(begin, end - begin));
    }
    return names;
}

// every table a schema file creates and every column it adds is in the database
void check_schema_applied(db::Connection& connection, const std::vector<fs::path>& files) {
    std::size_t checked = 0;
    for (const auto& file : files) {
        const std::string sql = test::read_file(file);
        CAPTURE(file.filename().string());
        for (const auto& table : names_after(sql, "CREATE TABLE ")) {
            CAPTURE(table);
            auto statement =
                connection.prepare("SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = ?1");
            statement.bind(1, table);
            REQUIRE(statement.step());
            CHECK(statement.column_int(0) == 1);
            ++checked;
        }
        // ALTER TABLE t ADD COLUMN c, or ALTER TABLE t RENAME COLUMN a TO c: c is in t (and a, renamed
        // by a later file than the one that made it, is not)
        const auto altered = names_after(sql, "ALTER TABLE ");
        const auto added = names_after(sql, "ADD COLUMN ");
        const auto renamed = names_after(sql, "RENAME COLUMN ");
        const auto renamed_to = names_after(sql, " TO ");
        REQUIRE(renamed.size() == renamed_to.size());
        REQUIRE(altered.size() == added.size() + renamed.size());
        const auto columns_named = [&](const std::string& table, const std::string& column) {
            auto statement = connection.prepare("SELECT count(*) FROM pragma_table_info(?1) WHERE name = ?2");
            statement.bind(1, table);
            statement.bind(2, column);
            REQUIRE(statement.step());
            return statement.column_int(0);
        };
        for (std::size_t i = 0; i < altered.size(); ++i) {
            const bool renaming = i >= added.size();
            const std::string& column = renaming ? renamed_to[i - added.size()] : added[i];
            CAPTURE(altered[i], column);
            CHECK(columns_named(altered[i], column) == 1);
            if (renaming) CHECK(columns_named(altered[i], renamed[i - added.size()]) == 0);
            ++checked;
        }
    }
    CHECK(checked >= 10);  // schema/ at the time of writing: 13 tables, 4 added columns
}

}  // namespace

TEST_CASE("the migrations are the schema folder's files, numbered 1 to their count", "[db][migrate]") {
    // counted on disk, not from the embedded list: a file left out of the build is missed here
    const auto files = schema_files_on_disk();
    REQUIRE(files.size() >= 6);  // 0001_init.sql to 0006_packed_segments.sql at the time of writing
    const auto& list = db::migrations();
    REQUIRE(list.size() == files.size());
    CHECK(db::latest_schema_version() == static_cast<int>(files.size()));
    for (std::size_t i = 0; i < files.size(); ++i) {
        const std::string name = files[i].filename().string();
        CAPTURE(name);
        const std::string number = std::to_string(i + 1);
        CHECK(name.substr(0, 5) == std::string(4 - number.size(), '0') + number + "_");
        CHECK(list[i].version == static_cast<int>(i) + 1);
        CHECK(list[i].name == name);
        CHECK(list[i].sql == test::read_file(files[i]));
    }
}

TEST_CASE("a new database has every migration applied: its version is the file count, its tables are there",
          "[db][migrate]") {
    const auto files = schema_files_on_disk();
    test::TempDir dir;
    auto connection = db::open_database(dir / "new.db", db::OpenMode::create);
    CHECK(connection.query_int("PRAGMA user_version") == static_cast<std::int64_t>(files.size()));
    check_schema_applied(connection, files);
}

TEST_CASE("a new database is stamped and migrated to the latest version", "[db][migrate]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "new.db", db::OpenMode::create);
    const auto info = db::database_info(connection);
    CHECK(info.application_id == db::kApplicationId);
    CHECK(info.schema_version == db::latest_schema_version());
    CHECK(connection.query_int("PRAGMA foreign_keys") == 1);
    db::set_meta_value(connection, "a", "b");
    CHECK(db::meta_value(connection, "a") == "b");
    CHECK_THROWS_WITH(db::open_database(dir / "new.db", db::OpenMode::create), Contains("new.db: already exists"));
}

TEST_CASE("an old stepstone database is migrated in place, refused read-only", "[db][migrate]") {
    test::TempDir dir;
    test::make_old_stepstone(dir / "old.db");
    CHECK_THROWS_WITH(db::open_database(dir / "old.db", db::OpenMode::read_only),
                      Contains("is older than this program"));
    {
        auto connection = db::open_database(dir / "old.db", db::OpenMode::read_write);
        CHECK(db::database_info(connection).schema_version == db::latest_schema_version());
        // version 0: every migration ran in place
        check_schema_applied(connection, schema_files_on_disk());
    }
    // a run file of schema 4 gets the milestone columns back, and the versions after it
    test::make_stepstone_db(dir / "four.db");
    test::make_schema4_run(dir / "four.db");
    {
        auto connection = db::open_database(dir / "four.db", db::OpenMode::read_write);
        CHECK(connection.query_int("PRAGMA user_version") ==
              static_cast<std::int64_t>(schema_files_on_disk().size()));
        check_schema_applied(connection, schema_files_on_disk());
    }
    auto connection = db::open_database(dir / "old.db", db::OpenMode::read_only);
    CHECK(db::table_counts(connection).size() >= 1);
}

TEST_CASE("a transaction rolls back when an exception escapes", "[db][transaction]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "t.db", db::OpenMode::create);
    try {
        db::Transaction transaction(connection);
        db::set_meta_value(connection, "lost", "1");
        throw std::runtime_error("boom");
    } catch (const std::runtime_error&) {
    }
    CHECK(db::meta_value(connection, "lost").empty());
    {
        db::Transaction transaction(connection);
        db::set_meta_value(connection, "kept", "1");
        transaction.commit();
    }
    CHECK(db::meta_value(connection, "kept") == "1");
}

TEST_CASE("foreign, newer, corrupt and non-database files are refused and left unchanged", "[db][errors]") {
    test::TempDir dir;
    struct Case {
        const char* name;
        std::function<void(const std::filesystem::path&)> make;
        const char* message;
    };
    const std::vector<Case> cases = {
        {"text.db", [](const auto& p) { test::write_file(p, "root:x:0:0:root:/root:/bin/bash\n"); },
         "text.db: not an SQLite database"},
        {"empty.db", [](const auto& p) { test::write_file(p, ""); }, "empty.db: empty file, not a stepstone database"},
        {"foreign.db", test::make_foreign_sqlite, "foreign.db: not a stepstone database (application_id 0x00000000"},
        {"newer.db", test::make_newer_stepstone, "newer.db: schema version"},
        {"truncated.db", test::make_truncated_stepstone, "truncated.db: truncated database"},
    };
    for (const auto& c : cases) {
        SECTION(c.name) {
            const auto path = dir / c.name;
            c.make(path);
            const std::string before = test::read_file(path);
            for (auto mode : {db::OpenMode::read_only, db::OpenMode::read_write}) {
                try {
                    db::open_database(path, mode);
                    FAIL("no exception for " << c.name);
                } catch (const DatabaseError& e) {
                    const std::string what = e.what();
                    CHECK_THAT(what, Contains(c.message));
                    CHECK(what.find('\n') == std::string::npos);
                }
            }
            CHECK(test::read_file(path) == before);
        }
    }
    CHECK_THROWS_WITH(db::open_database(dir / "absent.db", db::OpenMode::read_only), Contains("absent.db: no such file"));
}

TEST_CASE("a newer schema is named with both versions", "[db][errors]") {
    test::TempDir dir;
    test::make_newer_stepstone(dir / "n.db");
    const int latest = db::latest_schema_version();
    CHECK_THROWS_WITH(db::open_database(dir / "n.db", db::OpenMode::read_only),
                      Contains("schema version " + std::to_string(latest + 1) + " is newer than this program (" +
                               std::to_string(latest) + ")"));
}

TEST_CASE("an output database appears only when committed", "[db][output]") {
    test::TempDir dir;
    const auto out = dir / "out.db";
    {
        db::OutputDatabase output(out, false);
        db::set_meta_value(output.connection(), "x", "1");
        // not committed: nothing may be left, not even the temporary file
    }
    CHECK(!std::filesystem::exists(out));
    CHECK(std::filesystem::is_empty(dir.path()));
    {
        db::OutputDatabase output(out, false);
        db::set_meta_value(output.connection(), "x", "1");
        output.commit();
    }
    REQUIRE(std::filesystem::exists(out));
    CHECK(!std::filesystem::exists(dir / "out.db-wal"));
    auto connection = db::open_database(out, db::OpenMode::read_only);
    CHECK(db::meta_value(connection, "x") == "1");
    CHECK_THROWS_WITH(db::OutputDatabase(out, false),
                      Contains("out.db: already exists (use `force` to overwrite)"));
    CHECK_NOTHROW(db::OutputDatabase(out, true));
}

TEST_CASE("reading a finished output read-only leaves no file beside it", "[db][output]") {
    test::TempDir dir;
    {
        db::OutputDatabase output(dir / "out.db", false);
        db::set_meta_value(output.connection(), "x", "1");
        output.commit();
    }
    {
        auto connection = db::open_database(dir / "out.db", db::OpenMode::read_only);
        CHECK(db::meta_value(connection, "x") == "1");
    }
    // only the database itself: no -wal or -shm left by the reader
    std::size_t files = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path())) ++files;
    CHECK(files == 1);
}

TEST_CASE("replacing an output with force drops the old file's journals", "[db][output]") {
    test::TempDir dir;
    const auto out = dir / "out.db";
    test::make_stepstone_db(out);
    // a journal left by the replaced file must not be applied to the new one
    test::write_file(dir / "out.db-wal", "stale journal of the old file");
    {
        db::OutputDatabase output(out, true);
        db::set_meta_value(output.connection(), "new", "1");
        output.commit();
    }
    CHECK(!std::filesystem::exists(dir / "out.db-wal"));
    auto connection = db::open_database(out, db::OpenMode::read_only);
    CHECK(db::meta_value(connection, "new") == "1");
    CHECK(db::meta_value(connection, "key0").empty());
}

TEST_CASE("a file its writer closed beside a reader is folded back out of WAL mode by settle_journal",
          "[db][wal]") {
    test::TempDir dir;
    const auto path = dir / "run.db";
    {
        auto writer = db::open_database(path, db::OpenMode::create);
        db::start_writing(writer);
        db::set_meta_value(writer, "x", "1");
        // a reader holds the file as the writer closes: SQLite leaves the journal
        auto reader = db::open_database(path, db::OpenMode::read_only);
        CHECK(db::meta_value(reader, "x") == "1");
        writer.close();
    }
    REQUIRE((std::filesystem::exists(dir / "run.db-wal") || std::filesystem::exists(dir / "run.db-shm")));
    db::settle_journal(path);
    CHECK_FALSE(std::filesystem::exists(dir / "run.db-wal"));
    CHECK_FALSE(std::filesystem::exists(dir / "run.db-shm"));
    auto connection = db::open_database(path, db::OpenMode::read_only);
    CHECK(db::meta_value(connection, "x") == "1");
    // nothing beside the file: nothing to do, nothing created
    db::settle_journal(path);
    db::settle_journal(dir / "missing.db");
    CHECK_FALSE(std::filesystem::exists(dir / "missing.db"));
}
