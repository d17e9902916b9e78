#include "db/user_query.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <set>

#include "core/embedded.hpp"
#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::db {

namespace {

bool is_word(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// the :names of a query's text, in order of first appearance (comments skipped)
std::vector<std::string> parameters_of(std::string_view sql) {
    std::vector<std::string> names;
    std::size_t k = 0;
    while (k < sql.size()) {
        if (sql.substr(k, 2) == "--") {
            k = sql.find('\n', k);
            if (k == std::string_view::npos) break;
        } else if (sql[k] == '\'') {
            k = sql.find('\'', k + 1);
            if (k == std::string_view::npos) break;
            ++k;
        } else if (sql[k] == ':' && k + 1 < sql.size() && (is_word(sql[k + 1]) && !std::isdigit(static_cast<unsigned char>(sql[k + 1])))) {
            std::size_t end = k + 1;
            while (end < sql.size() && is_word(sql[end])) ++end;
            std::string name(sql.substr(k, end - k));
            if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
            k = end;
        } else {
            ++k;
        }
    }
    return names;
}

// where the first sentence of `text` ends: the first ". " that does not close an
// abbreviation ("Fig. 5", "e.g. ", "cf. "); npos if none does
std::size_t sentence_end(const std::string& text) {
    static constexpr std::string_view kAbbreviations[] = {"Fig", "Figs", "e.g", "i.e",
                                                          "cf",  "vs",   "Eq",  "Sec"};
    for (std::size_t stop = text.find(". "); stop != std::string::npos; stop = text.find(". ", stop + 1)) {
        const std::size_t space = text.rfind(' ', stop);
        const std::size_t from = space == std::string::npos ? 0 : space + 1;
        std::string_view word(text.data() + from, stop - from);
        if (!word.empty() && word.front() == '(') word.remove_prefix(1);
        if (std::find(std::begin(kAbbreviations), std::end(kAbbreviations), word) == std::end(kAbbreviations))
            return stop;
    }
    return std::string::npos;
}

// the first sentence of the leading "-- " comment, its lines joined (up to the
// first ". " that ends a sentence or a line ending in "." or ":"; the whole
// comment if none does)
std::string summary_of(std::string_view sql) {
    std::string text;
    while (sql.substr(0, 3) == "-- ") {
        const auto end = std::min(sql.find('\n'), sql.size());
        const std::string_view line = sql.substr(3, end - 3);
        text += (text.empty() ? "" : " ") + std::string(line);
        if (const auto stop = sentence_end(text); stop != std::string::npos) return text.substr(0, stop + 1);
        if (line.ends_with(".") || line.ends_with(":")) break;
        sql = sql.substr(std::min(end + 1, sql.size()));
    }
    return text;
}

std::string joined(const std::vector<std::string>& items) {
    std::string text;
    for (const auto& item : items) text += (text.empty() ? "" : ", ") + item;
    return text.empty() ? "none" : text;
}

// binds `value` typed as the user most likely meant
void bind_typed(Statement& statement, int index, const std::string& value) {
    if (value.size() >= 2 && value.front() == '\'' && value.back() == '\'') {
        statement.bind(index, std::string_view(value).substr(1, value.size() - 2));
        return;
    }
    std::int64_t integer = 0;
    const char* end = value.data() + value.size();
    auto parsed = std::from_chars(value.data(), end, integer);
    if (!value.empty() && parsed.ec == std::errc() && parsed.ptr == end) {
        statement.bind(index, integer);
        return;
    }
    double real = 0;
    auto parsed_real = std::from_chars(value.data(), end, real);
    if (!value.empty() && parsed_real.ec == std::errc() && parsed_real.ptr == end && std::isfinite(real)) {
        statement.bind(index, real);
        return;
    }
    statement.bind(index, std::string_view(value));
}

}  // namespace

std::vector<UserQuery> user_queries() {
    std::vector<UserQuery> list;
    for (const auto& file : query_files()) {
        std::string name(file.path);
        if (name.size() > 4 && name.ends_with(".sql")) name.resize(name.size() - 4);
        list.push_back({name, summary_of(file.text), parameters_of(file.text), file.text});
    }
    std::sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
    return list;
}

UserQuery find_user_query(const std::string& name) {
    std::string wanted = name;
    if (wanted.ends_with(".sql")) wanted.resize(wanted.size() - 4);
    if (const auto slash = wanted.find_last_of('/'); slash != std::string::npos) wanted = wanted.substr(slash + 1);
    std::vector<std::string> names;
    for (auto& query : user_queries()) {
        if (query.name == wanted) return query;
        names.push_back(query.name);
    }
    throw ConfigError(concat("no query called \"", name, "\" (queries: ", joined(names), ")"));
}

void run_user_query(Connection& connection, const std::string& name,
                    const std::vector<std::pair<std::string, std::string>>& params, std::ostream& out,
                    TableFormat format) {
    const UserQuery query = find_user_query(name);
    std::vector<std::pair<std::string, std::string>> given;
    std::set<std::string> seen;
    for (const auto& [key, value] : params) {
        const std::string colon = key.starts_with(":") ? key : ":" + key;
        if (std::find(query.parameters.begin(), query.parameters.end(), colon) == query.parameters.end()) {
            throw ConfigError(concat(option_name("param"), " ", key, ": query ", query.name,
                                     " has no parameter ", colon,
                                     " (its parameters: ", joined(query.parameters), ")"));
        }
        if (!seen.insert(colon).second)
            throw ConfigError(concat(option_name("param"), " ", key, " is given twice"));
        given.emplace_back(colon, value);
    }
    for (const auto& parameter : query.parameters) {
        if (!seen.count(parameter)) {
            throw ConfigError(concat("query ", query.name, " needs ", option_name("param"), " ",
                                     parameter.substr(1),
                                     "=VALUE (its parameters: ", joined(query.parameters), ")"));
        }
    }
    // a KB name that is not in the file would give an empty table: say so instead
    for (const auto& [key, value] : given) {
        if (key != ":kb_name") continue;
        std::vector<std::string> kbs;
        auto names = connection.prepare("SELECT name FROM kb ORDER BY id");
        while (names.step()) kbs.push_back(names.column_text(0));
        const std::string wanted = value.size() >= 2 && value.front() == '\'' && value.back() == '\''
                                       ? value.substr(1, value.size() - 2)
                                       : value;
        if (std::find(kbs.begin(), kbs.end(), wanted) == kbs.end()) {
            throw DataError(concat(connection.name(), ": no knowledge base named \"", wanted,
                                   "\" (its KBs: ", joined(kbs), ")"));
        }
    }
    for (auto& statement : connection.prepare_all(query.sql)) {
        for (int k = 1; k <= statement.parameter_count(); ++k) {
            const std::string parameter = statement.parameter_name(k);
            for (const auto& [key, value] : given) {
                if (key == parameter) bind_typed(statement, k, value);
            }
        }
        bool first = true;
        while (statement.step()) {
            if (first) write_header(out, statement, format);
            first = false;
            write_row(out, statement, format);
        }
        if (first && statement.column_count() > 0) write_header(out, statement, format);
    }
}

}  // namespace stepstone::db
