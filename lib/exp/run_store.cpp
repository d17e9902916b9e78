#include "exp/run_store.hpp"

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"

namespace stepstone::exp {

namespace {

void bind_progress(db::Statement& update, const RunRecord& run) {
    update.bind(update.parameter(":generations_done"), run.generations_done)
        .bind(update.parameter(":evaluations"), run.evaluations)
        .bind(update.parameter(":nan_outputs"), run.nan_outputs)
        .bind(update.parameter(":status"), run.status)
        .bind(update.parameter(":generations"), run.generations)
        .bind(update.parameter(":run_id"), run.id);
}

}  // namespace

std::int64_t insert_run(db::Connection& connection, const RunRecord& run, const std::string& program_version) {
    auto insert = connection.prepare(db::sql("run/insert_run.sql"));
    insert.bind(insert.parameter(":task"), run.task)
        .bind(insert.parameter(":treatment"), run.treatment)
        .bind(insert.parameter(":seed"), run.seed)
        .bind(insert.parameter(":config"), run.config.dump())
        .bind(insert.parameter(":generations"), run.generations)
        .bind(insert.parameter(":program_version"), program_version)
        .run();
    return connection.last_insert_rowid();
}

RunRecord load_run(db::Connection& connection) {
    auto select = connection.prepare(db::sql("run/select_run.sql"));
    if (!select.step()) throw DatabaseError(concat(connection.name(), ": holds no run"));
    RunRecord run;
    run.id = select.column_int(0);
    run.task = select.column_text(1);
    run.treatment = select.column_text(2);
    run.seed = select.column_int(3);
    try {
        run.config = nlohmann::json::parse(select.column_text(4));
    } catch (const nlohmann::json::exception&) {
        throw DatabaseError(concat(connection.name(), ": run ", run.id, " has an unreadable config"));
    }
    run.status = select.column_text(5);
    run.generations = static_cast<int>(select.column_int(6));
    run.generations_done = static_cast<int>(select.column_int(7));
    run.evaluations = select.column_int(8);
    run.nan_outputs = select.column_int(9);
    if (select.step()) throw DatabaseError(concat(connection.name(), ": holds more than one run"));
    return run;
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
              p_diversity = individual.parameter(":diversity"), p_shaping = individual.parameter(":shaping"),
              p_balls = individual.parameter(":balls"), p_steps = individual.parameter(":steps");
    for (const auto& row : write.individuals) {
        individual.reset();
        individual.bind(p_run, run.id).bind(p_id, row.id).bind(p_gen, row.generation);
        individual.bind(p_parent, row.parent_id)
            .bind(p_reward, row.reward)
            .bind(p_fitness, row.fitness)
            .bind(p_diversity, row.diversity)
            .bind(p_shaping, row.shaping)
            .bind(p_balls, row.balls)
            .bind(p_steps, static_cast<std::int64_t>(row.steps))
            .run();
    }

    // genomes kept for replay
    auto genome = connection.prepare(db::sql("run/insert_genome.sql"));
    for (const auto& row : write.genomes) {
        genome.reset();
        genome.bind(1, run.id).bind(2, row.individual_id).bind(3, row.genome_json).run();
    }

    // the knowledge base, when this generation observed into it
    if (write.kb) db::update_kb(connection, write.kb_id, *write.kb, write.kb_previous_size, s.generation);

    // the state to resume from, then the counters
    auto checkpoint = connection.prepare(db::sql("run/upsert_checkpoint.sql"));
    checkpoint.bind(1, run.id).bind(2, s.generation).bind(3, write.checkpoint.dump()).run();

    // statistics last, so they can hold the time the other writes took
    const double time_database = now_seconds() - started;
    auto generation = connection.prepare(db::sql("run/insert_generation.sql"));
    generation.bind(generation.parameter(":run_id"), run.id)
        .bind(generation.parameter(":generation"), s.generation)
        .bind(generation.parameter(":best_reward"), s.best_reward)
        .bind(generation.parameter(":mean_reward"), s.mean_reward)
        .bind(generation.parameter(":median_reward"), s.median_reward)
        .bind(generation.parameter(":front_sizes"), nlohmann::json(s.front_sizes).dump())
        .bind(generation.parameter(":diversity_min"), s.diversity_min)
        .bind(generation.parameter(":diversity_max"), s.diversity_max)
        .bind(generation.parameter(":evaluations"), s.evaluations)
        .bind(generation.parameter(":wall_time"), s.wall_time + time_database)
        .bind(generation.parameter(":time_simulation"), s.time_simulation)
        .bind(generation.parameter(":time_kb"), s.time_kb)
        .bind(generation.parameter(":time_diversity"), s.time_diversity)
        .bind(generation.parameter(":time_selection"), s.time_selection)
        .bind(generation.parameter(":time_database"), time_database)
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
    select.bind(1, run_id);
    if (!select.step()) return std::nullopt;
    try {
        return nlohmann::json::parse(select.column_text(1));
    } catch (const nlohmann::json::exception&) {
        throw DatabaseError(concat(connection.name(), ": run ", run_id, " has an unreadable checkpoint"));
    }
}

StoredGenome load_genome(db::Connection& connection, std::int64_t run_id, std::int64_t individual_id) {
    auto select = connection.prepare(db::sql("run/select_genome.sql"));
    select.bind(1, run_id).bind(2, individual_id);
    if (!select.step()) {
        throw DataError(concat(connection.name(), ": individual ", individual_id,
                               " has no stored genome (stored: first fronts and best of each generation; "
                               "use --retain all to keep every genome)"));
    }
    StoredGenome stored;
    stored.individual_id = individual_id;
    try {
        stored.genome = nlohmann::json::parse(select.column_text(0));
    } catch (const nlohmann::json::exception&) {
        throw DatabaseError(concat(connection.name(), ": genome of individual ", individual_id, " is unreadable"));
    }
    stored.reward = select.column_double(1);
    stored.balls = static_cast<int>(select.column_int(2));
    stored.generation = static_cast<int>(select.column_int(3));
    return stored;
}

StoredGenome load_best_genome(db::Connection& connection, std::int64_t run_id) {
    auto select = connection.prepare(db::sql("run/select_best_genome.sql"));
    select.bind(1, run_id);
    if (!select.step()) throw DataError(concat(connection.name(), ": run ", run_id, " has no stored genome"));
    return load_genome(connection, run_id, select.column_int(0));
}

}  // namespace stepstone::exp
