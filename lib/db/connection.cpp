#include "db/connection.hpp"

#include <sqlite3.h>

#include <utility>

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/segment_codec.hpp"

namespace stepstone::db {

// ---------------------------------------------------------------- Connection

Connection::Connection(const std::filesystem::path& path, OpenMode mode, std::string label)
    : path_(path), label_(label.empty() ? path.string() : std::move(label)), mode_(mode) {
    int flags = SQLITE_OPEN_NOMUTEX;
    switch (mode) {
        case OpenMode::read_only: flags |= SQLITE_OPEN_READONLY; break;
        case OpenMode::read_write: flags |= SQLITE_OPEN_READWRITE; break;
        case OpenMode::create: flags |= SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE; break;
    }
    const int rc = sqlite3_open_v2(path.c_str(), &db_, flags, nullptr);
    if (rc != SQLITE_OK) {
        std::string message = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
        sqlite3_close_v2(db_);
        db_ = nullptr;
        throw DatabaseError(concat(name(), ": cannot open: ", message));
    }
    sqlite3_extended_result_codes(db_, 1);
    sqlite3_busy_timeout(db_, 10000);
    register_segment_functions(db_);
    exec("PRAGMA foreign_keys = ON");
}

Connection::~Connection() {
    if (db_) sqlite3_close_v2(db_);
}

Connection::Connection(Connection&& other) noexcept
    : db_(std::exchange(other.db_, nullptr)),
      path_(std::move(other.path_)),
      label_(std::move(other.label_)),
      mode_(other.mode_) {}

Connection& Connection::operator=(Connection&& other) noexcept {
    if (this != &other) {
        if (db_) sqlite3_close_v2(db_);
        db_ = std::exchange(other.db_, nullptr);
        path_ = std::move(other.path_);
        label_ = std::move(other.label_);
        mode_ = other.mode_;
    }
    return *this;
}

void Connection::close() {
    if (!db_) return;
    if (sqlite3_close(db_) != SQLITE_OK) fail("cannot close");
    db_ = nullptr;
}

namespace {

// a read-only reader cannot recover the WAL that a killed writer left behind
std::string hint_for(sqlite3* db) {
    if (!db) return "";
    const int code = sqlite3_extended_errcode(db);
    if (code == SQLITE_READONLY_RECOVERY || code == SQLITE_READONLY_CANTINIT || code == SQLITE_READONLY_ROLLBACK) {
        return " (the file was left mid-write by a killed program: resume the run that wrote it, "
               "or open it once for writing, e.g. by migrating it)";
    }
    return "";
}

}  // namespace

namespace {

// SQLite quotes the text near a syntax error, which in a damaged schema can be a
// whole statement: an error line keeps the first 160 characters of it
std::string clipped(std::string text) {
    constexpr std::size_t kLongest = 160;
    if (text.size() > kLongest) text = text.substr(0, kLongest) + "... (cut)";
    return text;
}

}  // namespace

void Connection::fail(std::string_view context) const {
    throw DatabaseError(
        concat(name(), ": ", context, ": ", clipped(db_ ? sqlite3_errmsg(db_) : "closed"), hint_for(db_)));
}

void Connection::exec(std::string_view sql) {
    char* error = nullptr;
    const std::string text(sql);
    if (sqlite3_exec(db_, text.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
        std::string message = error ? error : sqlite3_errmsg(db_);
        sqlite3_free(error);
        throw DatabaseError(concat(name(), ": ", clipped(one_line(message)), hint_for(db_)));
    }
}

Statement Connection::prepare(std::string_view sql) { return Statement(*this, sql); }

std::vector<Statement> Connection::prepare_all(std::string_view sql) {
    std::vector<Statement> statements;
    while (!sql.empty()) {
        Statement statement(*this, sql, &sql);
        // comments and whitespace after the last statement prepare to nothing
        if (!statement.empty()) statements.push_back(std::move(statement));
    }
    return statements;
}

std::optional<std::int64_t> Connection::query_int(std::string_view sql) {
    Statement statement(*this, sql);
    if (!statement.step() || statement.is_null(0)) return std::nullopt;
    return statement.column_int(0);
}

std::int64_t Connection::last_insert_rowid() const { return sqlite3_last_insert_rowid(db_); }

// ----------------------------------------------------------------- Statement

Statement::Statement(Connection& connection, std::string_view sql) : Statement(connection, sql, nullptr) {}

Statement::Statement(Connection& connection, std::string_view sql, std::string_view* rest)
    : connection_(&connection) {
    const char* tail = nullptr;
    if (sqlite3_prepare_v3(connection.handle(), sql.data(), static_cast<int>(sql.size()),
                           SQLITE_PREPARE_PERSISTENT, &stmt_, &tail) != SQLITE_OK) {
        connection.fail("cannot prepare statement");
    }
    if (rest) *rest = sql.substr(static_cast<std::size_t>(tail - sql.data()));
    if (!stmt_ && !rest) {
        throw DatabaseError(concat(connection.name(), ": empty statement"));
    }
    bound_.assign(static_cast<std::size_t>(parameter_count()), false);
}

Statement::~Statement() {
    if (stmt_) sqlite3_finalize(stmt_);
}

Statement::Statement(Statement&& other) noexcept
    : connection_(other.connection_),
      stmt_(std::exchange(other.stmt_, nullptr)),
      bound_(std::move(other.bound_)),
      executing_(other.executing_) {}

void Statement::check(int rc, std::string_view context) const {
    if (rc != SQLITE_OK) connection_->fail(context);
}

void Statement::mark_bound(int index) {
    // SQLite refused an index out of range already (check)
    bound_[static_cast<std::size_t>(index - 1)] = true;
}

void Statement::check_bound() const {
    for (std::size_t i = 0; i < bound_.size(); ++i) {
        if (!bound_[i]) {
            const int index = static_cast<int>(i + 1);
            const std::string name = parameter_name(index);
            throw DatabaseError(concat(connection_->name(), ": statement parameter ",
                                       name.empty() ? concat('?', index) : name, " is not bound"));
        }
    }
}

Statement& Statement::bind(int index, std::int64_t value) {
    check(sqlite3_bind_int64(stmt_, index, value), "bind");
    mark_bound(index);
    return *this;
}

Statement& Statement::bind(int index, double value) {
    check(sqlite3_bind_double(stmt_, index, value), "bind");
    mark_bound(index);
    return *this;
}

Statement& Statement::bind(int index, std::string_view value) {
    check(sqlite3_bind_text64(stmt_, index, value.data(), value.size(), SQLITE_TRANSIENT, SQLITE_UTF8), "bind");
    mark_bound(index);
    return *this;
}

Statement& Statement::bind_blob(int index, std::span<const std::byte> value) {
    // a zero-length blob is still a blob, not NULL
    check(sqlite3_bind_blob64(stmt_, index, value.empty() ? "" : static_cast<const void*>(value.data()),
                              value.size(), SQLITE_TRANSIENT),
          "bind");
    mark_bound(index);
    return *this;
}

Statement& Statement::bind_null(int index) {
    check(sqlite3_bind_null(stmt_, index), "bind");
    mark_bound(index);
    return *this;
}

int Statement::parameter(std::string_view name) const {
    const std::string text(name);
    const int index = sqlite3_bind_parameter_index(stmt_, text.c_str());
    if (index == 0) {
        throw DatabaseError(concat(connection_->name(), ": statement has no parameter ", name));
    }
    return index;
}

int Statement::parameter_count() const { return sqlite3_bind_parameter_count(stmt_); }

std::string Statement::parameter_name(int index) const {
    const char* name = sqlite3_bind_parameter_name(stmt_, index);
    return name ? name : "";
}

bool Statement::step() {
    if (!executing_) {
        check_bound();
        executing_ = true;
    }
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    connection_->fail("query failed");
}

void Statement::run() {
    while (step()) {
    }
}

void Statement::reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
    bound_.assign(bound_.size(), false);
    executing_ = false;
}

int Statement::column_count() const { return sqlite3_column_count(stmt_); }

std::string Statement::column_name(int index) const { return sqlite3_column_name(stmt_, index); }

int Statement::column(std::string_view name) const {
    for (int i = 0; i < column_count(); ++i) {
        if (name == sqlite3_column_name(stmt_, i)) return i;
    }
    throw DatabaseError(concat(connection_->name(), ": statement has no column ", name));
}

Statement::Type Statement::column_type(int index) const {
    switch (sqlite3_column_type(stmt_, index)) {
        case SQLITE_INTEGER: return Type::integer;
        case SQLITE_FLOAT: return Type::real;
        case SQLITE_TEXT: return Type::text;
        case SQLITE_BLOB: return Type::blob;
        default: return Type::null;
    }
}

bool Statement::is_null(int index) const { return sqlite3_column_type(stmt_, index) == SQLITE_NULL; }

std::int64_t Statement::column_int(int index) const { return sqlite3_column_int64(stmt_, index); }

double Statement::column_double(int index) const { return sqlite3_column_double(stmt_, index); }

std::string Statement::column_text(int index) const {
    const auto* text = sqlite3_column_text(stmt_, index);
    const int size = sqlite3_column_bytes(stmt_, index);
    return text ? std::string(reinterpret_cast<const char*>(text), static_cast<std::size_t>(size)) : std::string();
}

std::span<const std::byte> Statement::column_blob(int index) const {
    const void* data = sqlite3_column_blob(stmt_, index);
    const int size = sqlite3_column_bytes(stmt_, index);
    return {static_cast<const std::byte*>(data), static_cast<std::size_t>(size)};
}

// --------------------------------------------------------------- Transaction

Transaction::Transaction(Connection& connection) : connection_(connection) {
    connection_.exec("BEGIN IMMEDIATE");
}

Transaction::~Transaction() {
    if (!done_) {
        // never throws: a failed rollback leaves SQLite to roll back on close
        sqlite3_exec(connection_.handle(), "ROLLBACK", nullptr, nullptr, nullptr);
    }
}

void Transaction::commit() {
    connection_.exec("COMMIT");
    done_ = true;
}

}  // namespace stepstone::db
