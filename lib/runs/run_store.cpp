#include "runs/run_store.hpp"

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"

namespace stepstone::runs {

namespace {

void bind_progress(db::Statement& update, const RunRecord& run) {
    update.bind(":generations_done", run.generations_done)
        .bind(":evaluations", run.evaluations)
        .bind(":nan_outputs", run.nan_outputs)
        .bind(":status", to_string(run.status))
        .bind(":generations", run.generations)
        .bind(":run_id", run.id);
}

}  // namespace

std::int64_t insert_run(db::Connection& connection, const RunRecord& run,
                        const std::string& program_version) {
    auto insert = connection.prepare(db::sql("run/insert_run.sql"));
    insert.bind(":task", run.task)
        .bind(":treatment", run.treatment)
        .bind(":seed", run.seed)
        .bind(":config", run.config.dump())
        .bind(":generations", run.generations)
        .bind(":program_version", program_version)
        .run();
    return connection.last_insert_rowid();
}

RunRecord load_run(db::Connection& connection) {
    auto select = connection.prepare(db::sql("run/select_run.sql"));
    if (!select.step()) throw DatabaseError(concat(connection.name(), ": holds no run"));
    RunRecord run;
    run.id = select.column_int(select.column("id"));
    run.task = select.column_text(select.column("task"));
    run.treatment = select.column_text(select.column("treatment"));
    run.seed = select.column_int(select.column("seed"));
    try {
        run.config = nlohmann::json::parse(select.column_text(select.column("config")));
    } catch (const nlohmann::json::exception&) {
        throw DatabaseError(concat(connection.name(), ": run ", run.id, " has an unreadable config"));
    }
    run.status =
        parse_run_status(select.column_text(select.column("status")), connection.name() + ": run.status");
    run.generations = static_cast<int>(select.column_int(select.column("generations")));
    run.generations_done = static_cast<int>(select.column_int(select.column("generations_done")));
    run.evaluations = select.column_int(select.column("evaluations"));
    run.nan_outputs = select.column_int(select.column("nan_outputs"));
    if (select.step()) throw DatabaseError(concat(connection.name(), ": holds more than one run"));
    return run;
}

bool holds_run(db::Connection& connection) {
    return connection.query_int(db::sql("run/count_runs.sql")).value_or(0) > 0;
}

std::optional<double> best_reward(db::Connection& connection) {
    auto best = connection.prepare(db::sql("run/max_best_reward.sql"));  // max() is NULL without a generation
    if (best.step() && !best.is_null(0)) return best.column_double(0);
    return std::nullopt;
}

RunFileCost run_file_cost(db::Connection& connection) {
    RunFileCost cost;
    auto row = connection.prepare(db::sql("run/probe_generation_cost.sql"));
    row.step();
    cost.other_s = row.column_double(row.column("other_s"));
    cost.evaluations = row.column_double(row.column("evaluations"));
    auto bytes = connection.prepare(db::sql("run/probe_file_bytes.sql"));
    bytes.step();
    cost.individual_bytes = bytes.column_double(bytes.column("individual_bytes"));
    cost.generation_bytes = bytes.column_double(bytes.column("generation_bytes"));
    cost.kb_bytes = bytes.column_double(bytes.column("kb_bytes"));
    cost.total_bytes = bytes.column_double(bytes.column("total_bytes"));
    return cost;
}

void write_generation(db::Connection& connection, RunRecord& run, const GenerationWrite& write) {
    db::Transaction transaction(connection);

    const double started = now_seconds();
    const auto& s = write.stats;
    // every evaluated individual
    auto individual = connection.prepare(db::sql("run/insert_individual.sql"));
    const int p_run = individual.parameter(":run_id"), p_id = individual.parameter(":id"),
              p_gen = individual.parameter(":generation"), p_parent = individual.parameter(":parent_id"),
              p_reward = individual.parameter(":reward"), p_fitness = individual.parameter(":fitness"),
              p_diversity = individual.parameter(":diversity"), p_r_max = individual.parameter(":r_max"),
              p_balls = individual.parameter(":balls"), p_steps = individual.parameter(":steps"),
              p_presses = individual.parameter(":presses"), p_pickups = individual.parameter(":pickups"),
              p_carry = individual.parameter(":carry_steps"),
              p_releases = individual.parameter(":basket_releases");
    for (const auto& row : write.individuals) {
        individual.reset();
        individual.bind(p_run, run.id).bind(p_id, row.id).bind(p_gen, row.generation);
        individual.bind(p_parent, row.parent_id)
            .bind(p_reward, row.reward)
            .bind(p_fitness, row.fitness)
            .bind(p_diversity, row.diversity)
            .bind(p_r_max, row.r_max)
            .bind(p_balls, row.balls)
            .bind(p_steps, static_cast<std::int64_t>(row.steps))
            .bind(p_presses, row.milestones.presses)
            .bind(p_pickups, row.milestones.pickups)
            .bind(p_carry, static_cast<std::int64_t>(row.milestones.carry_steps))
            .bind(p_releases, row.milestones.basket_releases)
            .run();
    }

    // genomes kept for replay
    auto genome = connection.prepare(db::sql("run/insert_genome.sql"));
    for (const auto& row : write.genomes) {
        genome.reset();
        genome.bind(":run_id", run.id)
            .bind(":individual_id", row.individual_id)
            .bind(":genome", row.genome_json)
            .run();
    }

    // the knowledge base, when this generation observed into it
    if (write.kb) db::update_kb(connection, write.kb_id, *write.kb, write.kb_previous_size, s.generation);

    // the state to resume from, then the counters
    auto checkpoint = connection.prepare(db::sql("run/upsert_checkpoint.sql"));
    checkpoint.bind(":run_id", run.id)
        .bind(":generation", s.generation)
        .bind(":state", write.checkpoint.dump())
        .run();

    // statistics last, so they can hold the time the other writes took
    const double time_database = now_seconds() - started;
    auto generation = connection.prepare(db::sql("run/insert_generation.sql"));
    generation.bind(":run_id", run.id)
        .bind(":generation", s.generation)
        .bind(":best_reward", s.best_reward)
        .bind(":mean_reward", s.mean_reward)
        .bind(":median_reward", s.median_reward)
        .bind(":front_sizes", nlohmann::json(s.front_sizes).dump())
        .bind(":diversity_min", s.diversity_min)
        .bind(":diversity_max", s.diversity_max)
        .bind(":evaluations", s.evaluations)
        .bind(":wall_time", s.wall_time + time_database)
        .bind(":time_simulation", s.time_simulation)
        .bind(":time_kb", s.time_kb)
        .bind(":time_diversity", s.time_diversity)
        .bind(":time_selection", s.time_selection)
        .bind(":time_database", time_database)
        .run();

    RunRecord updated = run;
    updated.generations_done = s.generation;
    updated.evaluations += s.evaluations;
    updated.nan_outputs += write.nan_outputs;
    auto update = connection.prepare(db::sql("run/update_run_progress.sql"));
    bind_progress(update, updated);
    update.run();

    transaction.commit();
    run = updated;
}

void update_run(db::Connection& connection, const RunRecord& run) {
    auto update = connection.prepare(db::sql("run/update_run_progress.sql"));
    bind_progress(update, run);
    update.run();
}

std::optional<nlohmann::json> load_checkpoint(db::Connection& connection, std::int64_t run_id) {
    auto select = connection.prepare(db::sql("run/select_checkpoint.sql"));
    select.bind(":run_id", run_id);
    if (!select.step()) return std::nullopt;
    try {
        return nlohmann::json::parse(select.column_text(1));
    } catch (const nlohmann::json::exception&) {
        throw DatabaseError(concat(connection.name(), ": run ", run_id, " has an unreadable checkpoint"));
    }
}

StoredGenome load_genome(db::Connection& connection, std::int64_t run_id, std::int64_t individual_id) {
    auto select = connection.prepare(db::sql("run/select_genome.sql"));
    select.bind(":run_id", run_id).bind(":individual_id", individual_id);
    if (!select.step()) {
        throw DataError(concat(connection.name(), ": individual ", individual_id,
                               " has no stored genome (stored: first fronts and best of each generation; "
                               "a run with ",
                               option_name("retain"), " all keeps every genome)"));
    }
    StoredGenome stored;
    stored.individual_id = individual_id;
    try {
        stored.genome = nlohmann::json::parse(select.column_text(0));
    } catch (const nlohmann::json::exception&) {
        throw DatabaseError(
            concat(connection.name(), ": genome of individual ", individual_id, " is unreadable"));
    }
    stored.reward = select.column_double(1);
    stored.balls = static_cast<int>(select.column_int(2));
    stored.generation = static_cast<int>(select.column_int(3));
    return stored;
}

std::vector<std::int64_t> stored_individuals(db::Connection& connection, std::int64_t run_id) {
    auto select = connection.prepare(db::sql("run/select_genome_ids.sql"));
    select.bind(":run_id", run_id);
    std::vector<std::int64_t> ids;
    while (select.step()) ids.push_back(select.column_int(0));
    return ids;
}

StoredGenome load_best_genome(db::Connection& connection, std::int64_t run_id) {
    auto select = connection.prepare(db::sql("run/select_best_genome.sql"));
    select.bind(":run_id", run_id);
    if (!select.step()) throw DataError(concat(connection.name(), ": run ", run_id, " has no stored genome"));
    return load_genome(connection, run_id, select.column_int(0));
}

std::vector<StoredGenome> load_best_genomes(db::Connection& connection, std::int64_t run_id,
                                            std::int64_t count) {
    auto select = connection.prepare(db::sql("run/select_best_genomes.sql"));
    select.bind(":run_id", run_id).bind(":count", count);
    std::vector<StoredGenome> genomes;
    while (select.step()) {
        StoredGenome stored;
        stored.individual_id = select.column_int(0);
        try {
            stored.genome = nlohmann::json::parse(select.column_text(1));
        } catch (const nlohmann::json::exception&) {
            throw DatabaseError(
                concat(connection.name(), ": genome of individual ", stored.individual_id, " is unreadable"));
        }
        stored.reward = select.column_double(2);
        stored.balls = static_cast<int>(select.column_int(3));
        stored.generation = static_cast<int>(select.column_int(4));
        genomes.push_back(std::move(stored));
    }
    return genomes;
}

}  // namespace stepstone::runs
