#include "support/db_files.hpp"

#include <sqlite3.h>

#include <stdexcept>
#include <string>

#include "db/database.hpp"
#include "db/digest.hpp"
#include "db/inspect.hpp"
#include "support/temp_dir.hpp"

namespace stepstone::test {

// raw SQLite, bypassing every stepstone check
void raw_exec(const std::filesystem::path& path, const std::string& sql) {
    sqlite3* db = nullptr;
    if (sqlite3_open(path.c_str(), &db) != SQLITE_OK) throw std::runtime_error("open failed");
    char* error = nullptr;
    const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error);
    const std::string message = error ? error : "";
    sqlite3_free(error);
    sqlite3_close(db);
    if (rc != SQLITE_OK) throw std::runtime_error("raw exec failed: " + message);
}

void make_stepstone_db(const std::filesystem::path& path) {
    auto connection = db::open_database(path, db::OpenMode::create);
    for (int i = 0; i < 200; ++i) {
        db::set_meta_value(connection, "key" + std::to_string(i), std::string(300, char('a' + i % 26)));
    }
}

void make_foreign_sqlite(const std::filesystem::path& path) {
    raw_exec(path, "CREATE TABLE other (x INTEGER); INSERT INTO other VALUES (1), (2);");
}

void make_newer_stepstone(const std::filesystem::path& path) {
    make_stepstone_db(path);
    raw_exec(path, "PRAGMA user_version = " + std::to_string(db::latest_schema_version() + 1));
}

void make_old_stepstone(const std::filesystem::path& path) {
    raw_exec(path, "PRAGMA application_id = " + std::to_string(db::kApplicationId) + "; PRAGMA user_version = 0;");
}

void make_schema4_run(const std::filesystem::path& path) {
    raw_exec(
        path,
        "ALTER TABLE individual DROP COLUMN presses; ALTER TABLE individual DROP COLUMN pickups;"
        "ALTER TABLE individual DROP COLUMN carry_steps; ALTER TABLE individual DROP COLUMN basket_releases;"
        "ALTER TABLE kb DROP COLUMN counting; ALTER TABLE individual RENAME COLUMN r_max TO shaping;"
        "PRAGMA user_version = 4;");
}

void make_truncated_stepstone(const std::filesystem::path& path) {
    make_stepstone_db(path);
    const std::string bytes = read_file(path);
    write_file(path, bytes.substr(0, bytes.size() / 2));
}

int generations_done(const std::filesystem::path& path, int missing) {
    if (!std::filesystem::exists(path)) return missing;
    try {
        auto connection = db::open_database(path, db::OpenMode::read_only);
        return static_cast<int>(connection.query_int("SELECT generations_done FROM run").value_or(missing));
    } catch (const std::exception&) {
        return missing;  // not created yet
    }
}

std::string file_digest(const std::filesystem::path& path) {
    auto connection = db::open_database(path, db::OpenMode::read_only);
    return db::run_digest(connection);
}

std::string integrity_check(const std::filesystem::path& path) {
    if (!std::filesystem::exists(path)) return "absent";
    db::Connection connection(path, db::OpenMode::read_write);
    auto check = connection.prepare("PRAGMA integrity_check");
    check.step();
    return check.column_text(0);
}

}  // namespace stepstone::test
