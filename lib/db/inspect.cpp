#include "db/inspect.hpp"

#include "db/database.hpp"

namespace stepstone::db {

bool has_column(Connection& connection, std::string_view table, std::string_view column) {
    auto columns = connection.prepare(sql("db/table_columns.sql"));
    columns.bind(":table", std::string(table));
    while (columns.step()) {
        if (columns.column_text(0) == column) return true;
    }
    return false;
}

bool has_milestones(Connection& connection) { return has_column(connection, "individual", "presses"); }

std::string integrity_check(Connection& connection) {
    auto check = connection.prepare(sql("db/integrity_check.sql"));
    return check.step() ? check.column_text(0) : std::string("ok");
}

std::vector<TableCount> table_counts(Connection& connection) {
    std::vector<TableCount> tables;
    auto list = connection.prepare(sql("db/list_tables.sql"));
    while (list.step()) tables.push_back({list.column_text(0), 0});
    for (auto& table : tables) {
        // the name comes from sqlite_schema; quoting keeps odd names safe
        std::string quoted = "\"";
        for (char c : table.name) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
        quoted += '"';
        table.rows = connection.query_int("SELECT count(*) FROM " + quoted).value_or(0);
    }
    return tables;
}

std::string meta_value(Connection& connection, std::string_view key) {
    auto get = connection.prepare(sql("db/meta_get.sql"));
    get.bind(":key", key);
    return get.step() ? get.column_text(0) : std::string();
}

void set_meta_value(Connection& connection, std::string_view key, std::string_view value) {
    auto set = connection.prepare(sql("db/meta_set.sql"));
    set.bind(":key", key).bind(":value", value).run();
}

}  // namespace stepstone::db
