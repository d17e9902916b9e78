#include "db/database.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "core/embedded.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"

namespace stepstone::db {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kSqliteMagic{"SQLite format 3\0", 16};

std::uint32_t read_be32(const unsigned char* p) {
    return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

std::string hex32(std::uint32_t value) {
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "0x%08x", value);
    return buffer;
}

// the checks that need no SQLite: the file exists, has the SQLite header and
// our application id, and is not shorter than its header says
void check_file_header(const fs::path& path, const std::string& name) {
    std::error_code ec;
    const auto status = fs::status(path, ec);
    if (ec || !fs::exists(status)) throw DatabaseError(concat(name, ": no such file"));
    if (fs::is_directory(status)) throw DatabaseError(concat(name, ": is a directory, not a database"));

    std::ifstream in(path, std::ios::binary);
    if (!in) throw DatabaseError(concat(name, ": cannot read"));
    std::array<unsigned char, 100> header{};
    in.read(reinterpret_cast<char*>(header.data()), header.size());
    const auto got = static_cast<std::size_t>(in.gcount());
    if (got == 0) throw DatabaseError(concat(name, ": empty file, not a stepstone database"));
    if (got < header.size() || std::string_view(reinterpret_cast<const char*>(header.data()), 16) != kSqliteMagic) {
        throw DatabaseError(concat(name, ": not an SQLite database"));
    }
    const std::uint32_t app_id = read_be32(&header[68]);
    if (app_id != kApplicationId) {
        throw DatabaseError(concat(name, ": not a stepstone database (application_id ", hex32(app_id),
                                   ", expected ", hex32(kApplicationId), ")"));
    }

    // the in-header page count is valid when the two change counters agree
    std::uint32_t page_size = (std::uint32_t{header[16]} << 8) | header[17];
    if (page_size == 1) page_size = 65536;
    const std::uint32_t pages = read_be32(&header[28]);
    const bool count_valid = read_be32(&header[24]) == read_be32(&header[92]);
    const auto size = fs::file_size(path, ec);
    fs::path wal = path;
    wal += "-wal";
    if (!ec && count_valid && pages > 0 && !fs::exists(wal)) {
        const std::uintmax_t expected = std::uintmax_t{pages} * page_size;
        if (size < expected) {
            throw DatabaseError(concat(name, ": truncated database (", size, " of ", expected, " bytes)"));
        }
    }
}

int parse_version(std::string_view file_name) {
    int version = 0;
    std::size_t digits = 0;
    while (digits < file_name.size() && file_name[digits] >= '0' && file_name[digits] <= '9') {
        version = version * 10 + (file_name[digits] - '0');
        ++digits;
    }
    if (digits != 4 || file_name.size() < 6 || file_name[4] != '_') {
        throw std::logic_error(concat("schema/", file_name, ": migrations are named NNNN_name.sql"));
    }
    return version;
}

// The first schema whose individual table names a policy's KB score r_max (0008_r_max.sql).
constexpr int kRMaxVersion = 8;

// A file older than a renaming migration, opened read-only, cannot be migrated; a
// temporary view (temp objects come before the file's own in name lookup, and a
// read-only connection may create them) shows the renamed column under its new name
// too, so every statement reads old and new files alike.
void show_old_names(Connection& connection, int schema_version) {
    if (schema_version >= kRMaxVersion || schema_version < 2) return;  // 2 made the individual table
    connection.exec("CREATE TEMP VIEW individual AS SELECT *, shaping AS r_max FROM main.individual");
}

}  // namespace

const std::vector<Migration>& migrations() {
    static const std::vector<Migration> all = [] {
        std::vector<Migration> list;
        for (const auto& file : schema_files()) {
            list.push_back({parse_version(file.path), std::string(file.path), file.text});
        }
        std::sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.version < b.version; });
        for (std::size_t i = 0; i < list.size(); ++i) {
            if (list[i].version != static_cast<int>(i) + 1) {
                throw std::logic_error(concat("schema/", list[i].name, ": expected migration ", i + 1));
            }
        }
        return list;
    }();
    return all;
}

int latest_schema_version() { return static_cast<int>(migrations().size()); }

std::string_view sql(std::string_view name) {
    for (const auto& file : sql_files()) {
        if (file.path == name) return file.text;
    }
    throw std::logic_error(concat("no embedded statement sql/", name));
}

DatabaseInfo database_info(Connection& connection) {
    DatabaseInfo info;
    info.application_id = static_cast<std::uint32_t>(connection.query_int("PRAGMA application_id").value_or(0));
    info.schema_version = static_cast<int>(connection.query_int("PRAGMA user_version").value_or(0));
    return info;
}

int migrate(Connection& connection) {
    int applied = 0;
    const int current = database_info(connection).schema_version;
    for (const auto& migration : migrations()) {
        if (migration.version <= current) continue;
        Transaction transaction(connection);
        connection.exec(migration.sql);
        connection.exec(concat("PRAGMA user_version = ", migration.version));
        transaction.commit();
        ++applied;
    }
    return applied;
}

Connection open_database(const fs::path& path, OpenMode mode, bool allow_older, const std::string& label) {
    const std::string name = label.empty() ? path.string() : label;
    if (mode == OpenMode::create) {
        if (fs::exists(path)) throw DatabaseError(concat(name, ": already exists"));
        Connection connection(path, OpenMode::create, name);
        // the stamp goes into the main file's header before WAL is on
        connection.exec(concat("PRAGMA application_id = ", static_cast<std::int64_t>(kApplicationId)));
        connection.exec("PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL");
        migrate(connection);
        return connection;
    }

    check_file_header(path, name);
    Connection connection(path, mode, name);
    const DatabaseInfo info = database_info(connection);
    const int latest = latest_schema_version();
    if (info.schema_version > latest) {
        throw DatabaseError(concat(name, ": schema version ", info.schema_version,
                                   " is newer than this program (", latest, ")"));
    }
    if (mode == OpenMode::read_only) {
        if (info.schema_version < kOldestReadableVersion && !allow_older) {
            throw DatabaseError(concat(name, ": schema version ", info.schema_version, " is older than this program (",
                                       latest, "); run: stepstone db migrate ", path.string()));
        }
        show_old_names(connection, info.schema_version);
        return connection;
    }
    // the journal mode is left as the file has it until the caller starts writing
    connection.exec("PRAGMA synchronous = NORMAL");
    migrate(connection);
    return connection;
}

void start_writing(Connection& connection) {
    connection.exec("PRAGMA journal_mode = WAL");
}

void finish_writing(Connection& connection) {
    try {
        connection.exec("PRAGMA journal_mode = DELETE");
    } catch (const DatabaseError&) {
        // a reader holds the file: it stays in WAL mode, which is still correct
    }
}

fs::path check_output_path(const fs::path& path, bool force) {
    const OutputTarget target = resolve_output_target(path, force);
    if (target.kind == OutputKind::standard_output)
        throw ConfigError("a database cannot be written to standard output ('-'); name a file");
    if (target.kind == OutputKind::stream) {
        throw ConfigError(
            concat(path.string(), ": is a FIFO or a device, not a file a database can be written to"));
    }
    return target.path;
}

namespace {

// the journal files SQLite may keep beside a database
constexpr const char* kJournalSuffixes[] = {"-wal", "-shm", "-journal"};

void remove_journals(const fs::path& path) {
    std::error_code ec;
    for (const char* suffix : kJournalSuffixes) fs::remove(fs::path(path.string() + suffix), ec);
}

}  // namespace

void settle_journal(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(fs::path(path.string() + "-wal"), ec) &&
        !fs::exists(fs::path(path.string() + "-shm"), ec))
        return;
    try {
        auto connection = open_database(path, OpenMode::read_write);
        finish_writing(connection);
    } catch (const Error&) {
        // busy or unreadable: the journal stays, which is still correct
    }
}

void remove_database_files(const fs::path& path) {
    std::error_code ec;
    fs::remove(path, ec);
    remove_journals(path);
}

namespace {

fs::path temp_name_for(const fs::path& path) {
    fs::path temp = path.parent_path() / concat('.', path.filename().string(), ".tmp-", ::getpid());
    // a stale temp file from a crashed process with the same pid is ours to replace
    remove_database_files(temp);
    return temp;
}

}  // namespace

OutputDatabase::OutputDatabase(const fs::path& path, bool force)
    : path_(check_output_path(path, force)),
      temp_(temp_name_for(path_)),
      connection_(open_database(temp_, OpenMode::create, false, path.string())) {}

OutputDatabase::~OutputDatabase() {
    if (committed_) return;
    try {
        connection_.close();
    } catch (...) {
    }
    remove_database_files(temp_);
}

void OutputDatabase::commit() {
    // a finished output is not written again: no WAL, so readers leave no files beside it
    finish_writing(connection_);
    connection_.close();
    // journals of a replaced file (--force) must not be applied to the new one
    remove_journals(path_);
    std::error_code ec;
    fs::rename(temp_, path_, ec);
    if (ec) throw DatabaseError(concat(path_.string(), ": cannot move the output into place: ", ec.message()));
    committed_ = true;
}

}  // namespace stepstone::db
