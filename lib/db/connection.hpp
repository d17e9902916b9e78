#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

struct sqlite3;
struct sqlite3_stmt;

namespace stepstone::db {

/// How a database file is opened.
enum class OpenMode {
    read_only,   ///< inputs: never written
    read_write,  ///< an existing file that will be updated
    create,      ///< a new file (it must not exist yet)
};

class Statement;

/// An open SQLite connection (RAII). Foreign keys are on and a busy timeout is
/// set (WAL is chosen per file: db/database.hpp). Every failure throws DatabaseError
/// whose message starts with the file name. Not thread-safe: one per thread.
class Connection {
public:
    /// Opens `path` with the raw SQLite checks only (see db/database.hpp for
    /// the stepstone checks). ":memory:" opens a private in-memory database.
    /// `label` names the file in error messages (default: `path` as given);
    /// a temporary output passes the user's path.
    Connection(const std::filesystem::path& path, OpenMode mode, std::string label = {});
    ~Connection();
    Connection(Connection&& other) noexcept;
    Connection& operator=(Connection&& other) noexcept;
    Connection(const Connection&) = delete;
    Connection& operator=(const Connection&) = delete;

    /// Runs one or more statements that return no rows.
    void exec(std::string_view sql);
    /// Prepares one statement.
    Statement prepare(std::string_view sql);
    /// Prepares every statement of a text holding several, in order.
    std::vector<Statement> prepare_all(std::string_view sql);
    /// The single value of a one-row, one-column query (nullopt if no row or NULL).
    std::optional<std::int64_t> query_int(std::string_view sql);

    std::int64_t last_insert_rowid() const;
    bool read_only() const { return mode_ == OpenMode::read_only; }
    const std::filesystem::path& path() const { return path_; }
    /// The file as named in error messages: the path as the user gave it.
    const std::string& name() const { return label_; }
    sqlite3* handle() const { return db_; }

    /// Closes now (the destructor does it otherwise); throws on failure.
    void close();

    /// Throws DatabaseError "<file>: <context>: <sqlite message>".
    [[noreturn]] void fail(std::string_view context) const;

private:
    sqlite3* db_ = nullptr;
    std::filesystem::path path_;
    std::string label_;
    OpenMode mode_ = OpenMode::read_only;
};

/// A prepared statement (RAII). Parameters are bound by name (":run_id", as
/// the sql/ files write them) or by index from 1; columns are read by index
/// from 0, found by name with column(). Stepping a statement with a parameter
/// left unbound throws DatabaseError naming it: a NULL is bound explicitly
/// (bind_null, or bind of an empty optional).
class Statement {
public:
    Statement(Connection& connection, std::string_view sql);
    /// Prepares the first statement of `sql`; `*rest` receives what follows it.
    Statement(Connection& connection, std::string_view sql, std::string_view* rest);
    ~Statement();
    Statement(Statement&& other) noexcept;
    Statement& operator=(Statement&&) = delete;
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;

    Statement& bind(int index, std::int64_t value);
    Statement& bind(int index, int value) { return bind(index, static_cast<std::int64_t>(value)); }
    Statement& bind(int index, double value);
    Statement& bind(int index, std::string_view value);
    Statement& bind(int index, const char* value) { return bind(index, std::string_view(value)); }
    Statement& bind_blob(int index, std::span<const std::byte> value);
    Statement& bind_null(int index);
    /// Binds the value, or NULL when `value` is empty.
    template <class T>
    Statement& bind(int index, const std::optional<T>& value) {
        return value ? bind(index, *value) : bind_null(index);
    }
    /// Binds the parameter called `name` (":name"); throws DatabaseError if
    /// the statement has no such parameter.
    template <class T>
    Statement& bind(std::string_view name, const T& value) {
        return bind(parameter(name), value);
    }
    Statement& bind_blob(std::string_view name, std::span<const std::byte> value) {
        return bind_blob(parameter(name), value);
    }
    Statement& bind_null(std::string_view name) { return bind_null(parameter(name)); }
    /// Index of a named parameter (":name"); throws if the statement has none.
    int parameter(std::string_view name) const;
    int parameter_count() const;
    /// The name of parameter `index` (from 1) as written, e.g. ":kb_name"; empty for "?".
    std::string parameter_name(int index) const;
    /// True for a text that held only comments or white space.
    bool empty() const { return stmt_ == nullptr; }

    /// Advances; true while a row is available.
    bool step();
    /// Steps to completion, for statements that return no rows.
    void run();
    /// Resets for another execution and clears the bindings.
    void reset();

    int column_count() const;
    std::string column_name(int index) const;
    /// Index of the result column called `name`; throws DatabaseError if the
    /// statement has none.
    int column(std::string_view name) const;
    /// The storage class of a column of the current row.
    enum class Type { integer, real, text, blob, null };
    Type column_type(int index) const;
    bool is_null(int index) const;
    std::int64_t column_int(int index) const;
    double column_double(int index) const;
    std::string column_text(int index) const;
    std::span<const std::byte> column_blob(int index) const;

private:
    void check(int rc, std::string_view context) const;
    // records that parameter `index` is bound
    void mark_bound(int index);
    // throws for the first parameter not bound before an execution starts
    void check_bound() const;

    Connection* connection_;
    sqlite3_stmt* stmt_ = nullptr;
    std::vector<bool> bound_;  // per parameter, since the last reset
    bool executing_ = false;   // stepped since the last reset
};

/// A transaction that rolls back unless commit() is called. BEGIN IMMEDIATE,
/// so a writer waits for others at the start rather than failing midway.
class Transaction {
public:
    explicit Transaction(Connection& connection);
    ~Transaction();
    Transaction(const Transaction&) = delete;
    Transaction& operator=(const Transaction&) = delete;

    void commit();

private:
    Connection& connection_;
    bool done_ = false;
};

}  // namespace stepstone::db
