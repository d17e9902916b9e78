#include "runs/csv_reader.hpp"

#include <csv.h>

#include <fstream>
#include <iterator>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::runs {

namespace {

struct Collector {
    std::vector<CsvRecord> records;
    std::vector<std::string> fields;
    std::size_t line = 1;
};

void on_field(void* text, std::size_t size, void* data) {
    static_cast<Collector*>(data)->fields.emplace_back(static_cast<const char*>(text), size);
}

void on_record(int, void* data) {
    auto* c = static_cast<Collector*>(data);
    c->records.push_back({c->line, std::move(c->fields)});
    c->fields.clear();
}

// the line of a carriage return that does not end a line, outside quotes (0: none)
std::size_t stray_carriage_return(const std::string& text) {
    bool quoted = false;
    std::size_t line = 1;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '"') quoted = !quoted;
        if (c == '\n') ++line;
        if (c == '\r' && !quoted && (i + 1 == text.size() || text[i + 1] != '\n')) return line;
    }
    return 0;
}

}  // namespace

std::vector<CsvRecord> read_csv_records(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw DataError(concat(file.string(), ": cannot be read"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // a UTF-8 byte-order mark
    if (const std::size_t line = stray_carriage_return(text)) {
        throw DataError(concat(file.string(), " line ", line,
                               ": a carriage return inside the line (only CRLF or LF may end a line)"));
    }

    csv_parser parser;
    if (csv_init(&parser, CSV_STRICT | CSV_STRICT_FINI) != 0)
        throw DataError("the CSV parser could not start");
    Collector collector;
    // one physical line at a time, so that each record knows the line it ends on
    std::size_t from = 0;
    bool failed = false;
    while (from < text.size() && !failed) {
        const std::size_t lf = text.find('\n', from);
        const std::size_t to = lf == std::string::npos ? text.size() : lf + 1;
        failed =
            csv_parse(&parser, text.data() + from, to - from, on_field, on_record, &collector) != to - from;
        if (!failed && lf != std::string::npos) ++collector.line;
        from = to;
    }
    if (!failed) failed = csv_fini(&parser, on_field, on_record, &collector) != 0;
    const int error = csv_error(&parser);
    csv_free(&parser);
    if (failed) {
        throw DataError(concat(
            file.string(), " line ", collector.line, ": ",
            error == CSV_EPARSE ? "a quote is not closed or is followed by text" : csv_strerror(error)));
    }
    return collector.records;
}

}  // namespace stepstone::runs
