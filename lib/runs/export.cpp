#include "runs/export.hpp"

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/inspect.hpp"
#include "db/table_output.hpp"
#include "runs/campaign_store.hpp"

namespace stepstone::runs {

namespace fs = std::filesystem;

namespace {

constexpr db::TableFormat kCsv = db::TableFormat::csv;

// files older than schema 0005 hold no milestones: their columns export empty
std::string_view statement_for(ExportWhat what, bool milestones) {
    switch (what) {
        case ExportWhat::generations:
            return db::sql("export/generations.sql");
        case ExportWhat::individuals:
            return db::sql(milestones ? "export/individuals.sql"
                                      : "export/individuals_before_milestones.sql");
        case ExportWhat::kb:
            return db::sql("export/kb_segments.sql");
    }
    return {};
}

// the rows of one file, after `prefix`; the header once, before the first file's rows
std::size_t write_file_rows(const fs::path& file, ExportWhat what,
                            const std::vector<std::string>& prefix_names,
                            const std::vector<std::string>& prefix, bool& header_done, std::ostream& out) {
    auto connection = db::open_database(file, db::OpenMode::read_only);
    auto statement = connection.prepare(statement_for(what, db::has_milestones(connection)));
    if (!header_done) {
        db::write_header(out, statement, kCsv, prefix_names);
        header_done = true;
    }
    std::size_t rows = 0;
    while (statement.step()) {
        db::write_row(out, statement, kCsv, prefix);
        ++rows;
    }
    return rows;
}

// task, treatment and seed of a run file (its one run row)
std::vector<std::string> run_columns(const fs::path& file) {
    auto connection = db::open_database(file, db::OpenMode::read_only);
    auto run = connection.prepare(db::sql("export/run_columns.sql"));
    if (!run.step()) throw DataError(concat(file.string(), ": holds no run (is it a knowledge-base file?)"));
    return {run.column_text(0), run.column_text(1), std::to_string(run.column_int(2))};
}

}  // namespace

ExportWhat parse_export_what(const std::string& text, const std::string& what) {
    if (text == "generations") return ExportWhat::generations;
    if (text == "individuals") return ExportWhat::individuals;
    if (text == "kb") return ExportWhat::kb;
    throw ConfigError(concat(what, " must be generations, individuals or kb, got \"", text, '"'));
}

std::size_t export_csv(const fs::path& input, ExportWhat what, std::ostream& out) {
    bool header_done = false;
    std::size_t rows = 0;
    if (!fs::is_directory(input)) {
        if (what == ExportWhat::kb) return write_file_rows(input, what, {}, {}, header_done, out);
        return write_file_rows(input, what, {"task", "treatment", "seed"}, run_columns(input), header_done,
                               out);
    }
    if (what == ExportWhat::kb) {
        const fs::path campaign = input / "campaign.db";
        load_campaign(input);  // a clear error when this is no campaign
        auto connection = db::open_database(campaign, db::OpenMode::read_only);
        auto files = connection.prepare(db::sql("export/campaign_kb_files.sql"));
        std::vector<std::string> names;
        while (files.step()) names.push_back(files.column_text(0));
        for (const auto& name : names) {
            rows += write_file_rows(input / name, what, {"file"}, {name}, header_done, out);
        }
    } else {
        const auto index = load_campaign(input);
        for (std::size_t k = 0; k < index.runs.size(); ++k) {
            const auto& run = index.runs[k].run;
            const fs::path file = input / run.file;
            if (index.runs[k].status == RunStatus::pending && !fs::exists(file)) continue;
            rows += write_file_rows(file, what, {"task", "treatment", "seed"},
                                    {std::string(to_string(run.step)), std::string(to_string(run.treatment)),
                                     std::to_string(run.seed)},
                                    header_done, out);
        }
    }
    if (!header_done) {
        throw DataError(concat(input.string(), ": the campaign has no ",
                               what == ExportWhat::kb ? "knowledge base" : "run file", " yet"));
    }
    return rows;
}

}  // namespace stepstone::runs
