// stepstone db info | migrate

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/math_fingerprint.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "db/inspect.hpp"
#include "exp/parallel/writer_lock.hpp"
#include "runs/run_store.hpp"

namespace stepstone::app {

namespace {

struct DbInfoOptions {
    std::string file;
    bool json = false;
};

void run_db_info(const DbInfoOptions& options) {
    auto connection = db::open_database(options.file, db::OpenMode::read_only, /*allow_older=*/true);
    const auto info = db::database_info(connection);
    // a damaged file is said so, not listed as if it were whole
    const std::string integrity = db::integrity_check(connection);
    if (integrity != "ok") {
        throw DataError(concat(options.file, ": fails SQLite's integrity check (", one_line(integrity),
                               "); restore it from a copy, or rerun what wrote it"));
    }
    const auto tables = db::table_counts(connection);
    const std::string math = db::meta_value(connection, kMathFingerprintKey);  // run files since it was added
    if (options.json) {
        nlohmann::json out;
        out["file"] = options.file;
        out["application_id"] = info.application_id;
        out["schema_version"] = info.schema_version;
        out["program_schema_version"] = db::latest_schema_version();
        out["integrity"] = integrity;
        if (!math.empty()) out["math_fingerprint"] = math;
        out["tables"] = nlohmann::json::object();
        for (const auto& table : tables) out["tables"][table.name] = table.rows;
        std::cout << out.dump(2) << '\n';
        return;
    }
    char app_id[16];
    std::snprintf(app_id, sizeof app_id, "0x%08x", info.application_id);
    std::cout << "file            " << options.file << '\n'
              << "application_id  " << app_id << " (stepstone)\n"
              << "schema_version  " << info.schema_version
              << " (this program: " << db::latest_schema_version() << ")\n"
              << "integrity       ok\n";
    if (!math.empty()) {
        std::cout << "math            " << math << " (this machine: " << math_fingerprint() << ")\n";
    }
    std::cout << "tables          " << tables.size() << '\n';
    for (const auto& table : tables) {
        std::cout << "  " << table.name << std::string(table.name.size() < 24 ? 24 - table.name.size() : 1, ' ')
                  << table.rows << '\n';
    }
}

void run_db_migrate(const std::string& file) {
    int before = 0;
    {
        auto connection = db::open_database(file, db::OpenMode::read_only, /*allow_older=*/true);
        before = db::database_info(connection).schema_version;
        // a damaged file is not "up to date": migrating it would only hide the damage
        const std::string integrity = db::integrity_check(connection);
        if (integrity != "ok") {
            throw DataError(concat(file, ": fails SQLite's integrity check (", one_line(integrity),
                                   "); not migrated; restore it from a copy, or rerun what wrote it"));
        }
    }
    const WriterLock lock(file);  // not while evolve or a campaign writes it
    auto connection = db::open_database(file, db::OpenMode::read_write);
    const int after = db::database_info(connection).schema_version;
    std::cout << file << ": schema version " << before;
    if (after == before) {
        std::cout << ", up to date\n";
    } else {
        std::cout << " -> " << after << '\n';
    }
}

void run_db_digest(const std::string& file) {
    auto connection = db::open_database(file, db::OpenMode::read_only);
    if (!runs::holds_run(connection)) {
        throw DataError(file + ": holds no run (db digest hashes a run file; kb stats describes a knowledge base)");
    }
    std::cout << db::run_digest(connection) << '\n';
}

void add_db_command(CLI::App& app) {
    auto* db_cmd = app.add_subcommand("db", "Inspect and upgrade stepstone database files");
    db_cmd->require_subcommand(1);
    db_cmd->footer(example({"stepstone db info run.db --json", "stepstone db migrate old_run.db",
                            "stepstone db digest run.db"}));

    auto info_options = std::make_shared<DbInfoOptions>();
    auto* info = db_cmd->add_subcommand("info", "Print the application id, schema version and row counts of a database");
    info->add_option("file", info_options->file, "A stepstone database (opened read-only)")->required();
    info->add_flag("--json", info_options->json, "Print JSON instead of text");
    info->footer(example({"stepstone db info run.db", "stepstone db info run.db --json"}));
    info->callback([info_options] { run_db_info(*info_options); });

    auto file = std::make_shared<std::string>();
    auto* migrate = db_cmd->add_subcommand("migrate", "Upgrade a database to this program's schema version");
    migrate->add_option("file", *file, "A stepstone database (updated in place, one transaction per migration)")
        ->required();
    migrate->footer(example({"stepstone db migrate run.db"}));
    migrate->callback([file] { run_db_migrate(*file); });

    auto digest_file = std::make_shared<std::string>();
    auto* digest = db_cmd->add_subcommand(
        "digest", "Print a hex digest of a run's scientific content (no timings): equal digests, equal runs");
    digest->add_option("file", *digest_file, "A run database (opened read-only)")->required();
    digest->footer(example({"stepstone db digest run.db"}));
    digest->callback([digest_file] { run_db_digest(*digest_file); });
}

const CommandRegistrar db_registrar(90, add_db_command);

}  // namespace

}  // namespace stepstone::app
