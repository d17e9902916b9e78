#include "db/table_output.hpp"

#include "core/text.hpp"

namespace stepstone::db {

std::string format_field(const std::string& text, TableFormat format) {
    if (format == TableFormat::list || text.find_first_of(",\"\r\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) {
        if (c == '"') quoted += '"';
        quoted += c;
    }
    return quoted + '"';
}

namespace {

char separator(TableFormat format) { return format == TableFormat::csv ? ',' : '|'; }

std::string field(const Statement& statement, int index, TableFormat format) {
    switch (statement.column_type(index)) {
        case Statement::Type::null: return "";
        case Statement::Type::integer: return std::to_string(statement.column_int(index));
        case Statement::Type::real:
            // CSV: the shortest text that reads back exactly; list: as the sqlite3 shell prints it
            return format == TableFormat::csv ? shortest(statement.column_double(index))
                                              : statement.column_text(index);
        case Statement::Type::text: return statement.column_text(index);
        case Statement::Type::blob: return concat("<blob of ", statement.column_blob(index).size(), " bytes>");
    }
    return "";
}

void write_fields(std::ostream& out, const std::vector<std::string>& fields, TableFormat format) {
    for (std::size_t k = 0; k < fields.size(); ++k) {
        if (k > 0) out << separator(format);
        out << format_field(fields[k], format);
    }
    out << '\n';
}

}  // namespace

void write_header(std::ostream& out, const Statement& statement, TableFormat format,
                  const std::vector<std::string>& prefix) {
    std::vector<std::string> fields = prefix;
    for (int k = 0; k < statement.column_count(); ++k) fields.push_back(statement.column_name(k));
    write_fields(out, fields, format);
}

void write_row(std::ostream& out, const Statement& statement, TableFormat format,
               const std::vector<std::string>& prefix) {
    std::vector<std::string> fields = prefix;
    for (int k = 0; k < statement.column_count(); ++k) fields.push_back(field(statement, k, format));
    write_fields(out, fields, format);
}

}  // namespace stepstone::db
