// stepstone query: one analysis query of queries/ on a file, with headers
// stepstone export: tidy CSV of a run or a campaign, for pandas, R or a spreadsheet

#include <iostream>
#include <memory>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/user_query.hpp"
#include "runs/export.hpp"

namespace stepstone::app {

namespace {

struct QueryFlags {
    std::string file;
    std::string name;
    std::vector<std::string> params;
    bool csv = false;
    bool list = false;
};

void list_queries() {
    for (const auto& query : db::user_queries()) {
        std::string parameters;
        for (const auto& p : query.parameters) parameters += " --param " + p.substr(1) + "=...";
        std::cout << query.name << ": " << query.summary << "\n  stepstone query FILE.db " << query.name
                  << parameters << "\n";
    }
}

void run_query_command(const QueryFlags& flags) {
    if (flags.list) return list_queries();
    if (flags.file.empty() || flags.name.empty()) {
        throw ConfigError("query needs FILE.db and a query NAME (stepstone query --list shows them)");
    }
    std::vector<std::pair<std::string, std::string>> params;
    for (const auto& text : flags.params) {
        const auto equals = text.find('=');
        if (equals == std::string::npos || equals == 0) {
            throw ConfigError(concat("--param must be NAME=VALUE, got \"", text, '"'));
        }
        params.emplace_back(text.substr(0, equals), text.substr(equals + 1));
    }
    db::find_user_query(flags.name);  // a usage error before the file is opened
    auto connection = db::open_database(flags.file, db::OpenMode::read_only);
    db::run_user_query(connection, flags.name, params, std::cout,
                       flags.csv ? db::TableFormat::csv : db::TableFormat::list);
}

void add_query_command(CLI::App& app) {
    auto flags = std::make_shared<QueryFlags>();
    auto* cmd = app.add_subcommand("query", "Run an analysis query of queries/ on a database, with column headers");
    cmd->add_option("file", flags->file, "A run, KB or campaign database (opened read-only)");
    cmd->add_option("name", flags->name, "The query: a file name of queries/, with or without .sql");
    cmd->add_option("--param", flags->params, "A parameter of the query, NAME=VALUE (repeat for each)");
    cmd->add_flag("--csv", flags->csv, "CSV (RFC 4180) instead of the sqlite3 shell's '|' list");
    cmd->add_flag("--list", flags->list, "List the queries and their parameters");
    cmd->footer(example({"stepstone query --list",
                         "stepstone query run.db generation_times",
                         "stepstone query run.db salient_segments --param kb_name=run --param min_count=1 "
                         "--param limit=10 --csv"}));
    cmd->callback([flags] { run_query_command(*flags); });
}

struct TableExportFlags {
    std::string input;
    std::string what;
    std::string csv;
    bool force = false;
};

void add_export_command(CLI::App& app) {
    auto flags = std::make_shared<TableExportFlags>();
    auto* cmd = app.add_subcommand("export", "Write a run's or a campaign's generations, individuals or KB as tidy CSV");
    cmd->add_option("input", flags->input, "A run file, or a campaign directory (every run)")->required();
    cmd->add_option("--what", flags->what, "generations, individuals or kb")->required();
    cmd->add_option("--csv", flags->csv, "CSV file to write (written atomically)")->required();
    cmd->add_flag("--force", flags->force, "Replace an existing CSV file");
    cmd->footer(example({"stepstone export run.db --what generations --csv generations.csv",
                         "stepstone export camp --what individuals --csv individuals.csv",
                         "python3 -c \"import pandas; print(pandas.read_csv('generations.csv'))\""}));
    cmd->callback([flags] {
        const auto what = runs::parse_export_what(flags->what, "--what");
        check_output_target(flags->csv, flags->force);
        OutputFile out(flags->csv, flags->force);
        const std::size_t rows = runs::export_csv(flags->input, what, out.stream());
        out.commit();
        std::cout << flags->csv << ": " << rows << " rows\n";
    });
}

const CommandRegistrar query_registrar(57, add_query_command);
const CommandRegistrar export_registrar(58, add_export_command);

}  // namespace

}  // namespace stepstone::app
