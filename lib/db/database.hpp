#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "db/connection.hpp"

namespace stepstone::db {

/// PRAGMA application_id of every stepstone database: "STPS" in ASCII.
inline constexpr std::uint32_t kApplicationId = 0x53545053;

/// The schema version this program writes: the number of the last migration
/// in schema/.
int latest_schema_version();

/// The oldest schema version a read-only open accepts without `allow_older`:
/// every later migration only adds nullable columns that read as NULL
/// (0005: the individuals' milestones), so readers that check for them
/// (has_milestones) read these files as they are, or a second stored form that
/// readers tell apart by its length (0006: packed KB segments, segment_codec.hpp).
inline constexpr int kOldestReadableVersion = 4;

/// One numbered migration of schema/.
struct Migration {
    int version;
    std::string name;       ///< file name, e.g. "0001_init.sql"
    std::string_view sql;
};

/// The migrations embedded in the binary, in order. Numbers run 1, 2, ... with
/// no gap (checked here; a gap is a build error caught by the tests).
const std::vector<Migration>& migrations();

/// The text of a statement of sql/, e.g. sql("db/meta_get.sql"). Throws
/// std::logic_error for an unknown name (a bug, not a user error).
std::string_view sql(std::string_view name);

/// What a stepstone database file says about itself.
struct DatabaseInfo {
    std::uint32_t application_id = 0;
    int schema_version = 0;
};

/// Opens a stepstone database after checking, before anything is written,
/// that the file is SQLite, carries kApplicationId and has a schema version
/// this program knows. OpenMode::create makes a new file (refused if `path`
/// exists) and applies every migration; read_write migrates an older file;
/// read_only refuses a file older than kOldestReadableVersion (run
/// `stepstone db migrate`) unless `allow_older` (for inspection). Throws
/// DatabaseError with a one-line message naming the file; the file is then
/// left byte for byte as it was.
/// `label` names the file in messages (default: `path`).
Connection open_database(const std::filesystem::path& path, OpenMode mode, bool allow_older = false,
                         const std::string& label = {});

/// Applies the migrations newer than the file's version, each in its own
/// transaction. Returns the number applied.
int migrate(Connection& connection);

/// Switches a file to WAL mode before a long series of writes (evolve): readers
/// then never block the writer. read_write opens leave the journal mode as the
/// file has it, so a command that refuses its input after opening it has not
/// changed a byte.
void start_writing(Connection& connection);

/// Leaves WAL mode for a finished file (no writer expected any more): readers
/// opening it read-only then need no -wal / -shm files beside it. Does
/// nothing if another connection holds the file (the switch needs it alone).
void finish_writing(Connection& connection);

/// A file whose writer has ended, left in WAL mode with -wal / -shm beside it
/// (its writer closed while a reader held it, so SQLite could not fold the
/// journal back): opened read-write alone, folded back and switched out of
/// WAL mode, as its writer would have. Does nothing when no -wal or -shm is
/// beside `path`, and leaves things as they are if the file is busy or
/// unreadable (a reader still holds it): every committed write is in the
/// file or its -wal either way.
void settle_journal(const std::filesystem::path& path);

/// Application id and schema version of an open connection.
DatabaseInfo database_info(Connection& connection);

/// A new database written under a temporary name in the target's folder and
/// renamed over `path` by commit(): a crash or an exception leaves no partial
/// output. An existing `path` is refused unless `force`; when it is replaced,
/// its journal files go too, so they are never applied to the new file. A
/// symbolic link is followed: the file it names is replaced, the link stays.
class OutputDatabase {
public:
    OutputDatabase(const std::filesystem::path& path, bool force);
    ~OutputDatabase();
    OutputDatabase(const OutputDatabase&) = delete;
    OutputDatabase& operator=(const OutputDatabase&) = delete;

    Connection& connection() { return connection_; }
    /// Closes the connection and moves the file into place.
    void commit();

private:
    std::filesystem::path path_;
    std::filesystem::path temp_;
    Connection connection_;
    bool committed_ = false;
};

/// Removes a database file and the journal files beside it (-wal, -shm,
/// -journal); missing files are not an error.
void remove_database_files(const std::filesystem::path& path);

/// Refuses (ConfigError) an existing output path unless `force`, a directory,
/// a path whose folder does not exist (core/output_file.hpp), standard output
/// ("-") and a FIFO or device; returns the path to write, symbolic links
/// followed (the link is kept and names the new file).
std::filesystem::path check_output_path(const std::filesystem::path& path, bool force);

}  // namespace stepstone::db
