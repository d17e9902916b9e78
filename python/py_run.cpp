// stepstone.Run: a run file read-only, its generations and individuals as
// numpy structured arrays (pandas DataFrames on request), its genomes replayed.

#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "runs/replay.hpp"
#include "runs/run_store.hpp"

namespace stepstone::python {

namespace {

struct IndividualRec {
    std::int64_t id;
    std::int32_t generation;
    std::int64_t parent_id;  // -1: a random individual of generation 0
    double reward;
    double fitness;
    double diversity;
    double r_max;  // NaN without a knowledge base
    std::int32_t balls;
    std::int64_t steps;
    std::int32_t presses;  // milestones; -1 in rows written before they were recorded
    std::int32_t pickups;
    std::int64_t carry_steps;
    std::int32_t basket_releases;
};

struct GenerationRec {
    std::int32_t generation;
    double best_reward;
    double mean_reward;
    double median_reward;
    double diversity_min;
    double diversity_max;
    std::int64_t evaluations;
    double wall_time;
    double time_simulation;
    double time_kb;
    double time_diversity;
    double time_selection;
    double time_database;
};

struct PyRun {
    std::string path;
    std::shared_ptr<db::Connection> connection;
    runs::RunRecord run;
};

PyRun open_run(const std::filesystem::path& path) {
    PyRun out;
    out.path = path.string();
    out.connection = std::make_shared<db::Connection>(db::open_database(path, db::OpenMode::read_only));
    out.run = runs::load_run(*out.connection);
    return out;
}

std::int64_t int_or(const db::Statement& row, int column, std::int64_t missing) {
    return row.is_null(column) ? missing : row.column_int(column);
}

template <class T>
T narrow(std::int64_t value) {
    return static_cast<T>(value);
}

// the rows of `sql` (?1: the run's id, further parameters bound by `bind`) as a structured array
template <class Rec, class Bind, class Row>
py::array_t<Rec> table(const PyRun& self, const char* sql, Bind&& bind, Row&& row) {
    std::vector<Rec> rows;
    {
        py::gil_scoped_release release;
        db::Statement query(*self.connection, sql);
        query.bind(1, self.run.id);
        bind(query);
        while (query.step()) rows.push_back(row(query));
    }
    py::array_t<Rec> out(static_cast<py::ssize_t>(rows.size()));
    std::copy(rows.begin(), rows.end(), out.mutable_data());
    return out;
}

py::array_t<IndividualRec> individuals(const PyRun& self, std::optional<int> generation) {
    return table<IndividualRec>(
        self,
        "SELECT id, generation, parent_id, reward, fitness, diversity, r_max, balls, steps, presses, "
        "pickups, "
        "carry_steps, basket_releases FROM individual WHERE run_id = ?1 AND (?2 IS NULL OR generation = ?2) "
        "ORDER BY id",
        [&](db::Statement& query) { query.bind(2, generation); },
        [](const db::Statement& q) {
            return IndividualRec{q.column_int(0),
                                 narrow<std::int32_t>(q.column_int(1)),
                                 int_or(q, 2, -1),
                                 q.column_double(3),
                                 q.column_double(4),
                                 q.column_double(5),
                                 q.is_null(6) ? std::numeric_limits<double>::quiet_NaN() : q.column_double(6),
                                 narrow<std::int32_t>(q.column_int(7)),
                                 q.column_int(8),
                                 narrow<std::int32_t>(int_or(q, 9, -1)),
                                 narrow<std::int32_t>(int_or(q, 10, -1)),
                                 int_or(q, 11, -1),
                                 narrow<std::int32_t>(int_or(q, 12, -1))};
        });
}

py::array_t<GenerationRec> generations(const PyRun& self) {
    return table<GenerationRec>(
        self,
        "SELECT generation, best_reward, mean_reward, median_reward, diversity_min, diversity_max, "
        "evaluations, "
        "wall_time, time_simulation, time_kb, time_diversity, time_selection, time_database FROM generation "
        "WHERE run_id = ?1 ORDER BY generation",
        [](db::Statement&) {},
        [](const db::Statement& q) {
            return GenerationRec{narrow<std::int32_t>(q.column_int(0)),
                                 q.column_double(1),
                                 q.column_double(2),
                                 q.column_double(3),
                                 q.column_double(4),
                                 q.column_double(5),
                                 q.column_int(6),
                                 q.column_double(7),
                                 q.column_double(8),
                                 q.column_double(9),
                                 q.column_double(10),
                                 q.column_double(11),
                                 q.column_double(12)};
        });
}

py::object frame(const py::array& table) {
    py::module_ pandas;
    try {
        pandas = py::module_::import("pandas");
    } catch (const py::error_already_set&) {
        throw py::import_error(
            "pandas is not installed (apt-get install python3-pandas); the numpy arrays of "
            "generations() and individuals() need nothing more");
    }
    return pandas.attr("DataFrame")(table);
}

std::string individual_text(const py::object& individual) {
    if (py::isinstance<py::str>(individual)) return individual.cast<std::string>();
    if (py::isinstance<py::int_>(individual)) return std::to_string(individual.cast<std::int64_t>());
    throw py::type_error("individual must be 'best' or an individual id (int)");
}

py::dict replay(const PyRun& self, const py::object& individual) {
    runs::Replay facts;
    std::vector<float> behaviour;
    const std::string which = individual_text(individual);
    {
        py::gil_scoped_release release;
        behaviour = runs::replay_behaviour(self.path, which, &facts);
    }
    py::dict out;
    out["individual_id"] = facts.individual_id;
    out["generation"] = facts.generation;
    out["stored_reward"] = facts.stored_reward;
    out["reward"] = facts.result.reward;
    out["balls"] = facts.result.balls;
    out["steps"] = facts.result.steps_run;
    out["milestones"] = milestones_dict(facts.result.milestones);
    out["behaviour"] = matrix_copy(behaviour, sim::kChannels);
    return out;
}

py::object genome(const PyRun& self, const py::object& individual) {
    const std::string which = individual_text(individual);
    runs::StoredGenome stored;
    if (which == "best") {
        stored = runs::load_best_genome(*self.connection, self.run.id);
    } else {
        stored = runs::load_genome(*self.connection, self.run.id, individual.cast<std::int64_t>());
    }
    return json_loads(stored.genome.dump());
}

}  // namespace

void bind_run(py::module_& m) {
    PYBIND11_NUMPY_DTYPE(IndividualRec, id, generation, parent_id, reward, fitness, diversity, r_max, balls,
                         steps, presses, pickups, carry_steps, basket_releases);
    PYBIND11_NUMPY_DTYPE(GenerationRec, generation, best_reward, mean_reward, median_reward, diversity_min,
                         diversity_max, evaluations, wall_time, time_simulation, time_kb, time_diversity,
                         time_selection, time_database);

    py::class_<PyRun>(m, "Run", R"(A run file written by `stepstone evolve`, opened read-only.

>>> run = stepstone.Run("target.db")
>>> run.generations()["best_reward"]          # one row per committed generation
>>> ind = run.individuals(generation=10)       # one row per evaluated individual
>>> run.replay("best")["behaviour"].shape      # (steps, 15)
>>> stepstone.KnowledgeBase.open("source.db")  # the KB a source run grew (named 'run'))")
        .def(py::init(&open_run), py::arg("path"),
             "Opens a run file read-only. Raises DatabaseError naming the file when it is missing, foreign, "
             "or holds no run.")
        .def_property_readonly(
            "path", [](const PyRun& r) { return r.path; }, "the run file, as given")
        .def_property_readonly(
            "id", [](const PyRun& r) { return r.run.id; }, "the run's id in its file")
        .def_property_readonly(
            "task", [](const PyRun& r) { return r.run.task; }, "'source' or 'target'")
        .def_property_readonly(
            "treatment", [](const PyRun& r) { return r.run.treatment; },
            "none, sum, mo, sum-rand or mo-rand; for a seeded run its seeded twin: seed, seed-sum, seed-mo, "
            "seed-sum-rand or seed-mo-rand")
        .def_property_readonly(
            "seed", [](const PyRun& r) { return r.run.seed; }, "the run seed")
        .def_property_readonly(
            "status", [](const PyRun& r) { return std::string(runs::to_string(r.run.status)); },
            "'running' or 'finished'")
        .def_property_readonly(
            "generations_asked", [](const PyRun& r) { return r.run.generations; },
            "epochs asked for after generation 0")
        .def_property_readonly(
            "generations_done", [](const PyRun& r) { return r.run.generations_done; },
            "the last committed generation (-1: none yet)")
        .def_property_readonly(
            "evaluations", [](const PyRun& r) { return r.run.evaluations; }, "evaluations run so far")
        .def_property_readonly(
            "config", [](const PyRun& r) { return json_loads(r.run.config.dump()); },
            "the effective config as stored (a dict): task, dnn, ea, kb, transfer, seed")
        .def_property_readonly(
            "seeded_from",
            [](const PyRun& r) -> py::object {
                const auto& config = r.run.config;
                if (!config.contains("transfer") || !config["transfer"].contains("seed")) return py::none();
                return json_loads(config["transfer"]["seed"].dump());
            },
            "the seeding of generation 0 (config['transfer']['seed']: from, with, count and the source's "
            "digest), None for a random generation 0")
        .def("generations", &generations,
             "One row per committed generation: generation, best/mean/median_reward, diversity_min/max, "
             "evaluations, wall_time and the time_* split (seconds).")
        .def(
            "individuals", &individuals, py::arg("generation") = py::none(),
            "One row per evaluated individual (of one generation if given): id, generation, parent_id (-1: "
            "none), reward, fitness, diversity, r_max (NaN without a KB), balls, steps, and the milestones "
            "presses, pickups, carry_steps, basket_releases (-1 where not recorded).")
        .def(
            "generations_frame", [](const PyRun& r) { return frame(generations(r)); },
            "generations() as a pandas DataFrame (ImportError without pandas).")
        .def(
            "individuals_frame",
            [](const PyRun& r, std::optional<int> generation) { return frame(individuals(r, generation)); },
            py::arg("generation") = py::none(),
            "individuals() as a pandas DataFrame (ImportError without pandas).")
        .def("genome", &genome, py::arg("individual") = "best",
             "The stored genome of an individual ('best' or an id) as a dict; DataError if it was not kept.")
        .def("replay", &replay, py::arg("individual") = "best",
             "Re-simulates a stored genome with the run's task and network: a dict of individual_id, "
             "generation, "
             "stored_reward, reward, balls, steps, milestones and behaviour (the first start's steps x 15 "
             "matrix, float32).")
        .def("__repr__", [](const PyRun& r) {
            return concat("<stepstone.Run ", r.path, ": ", r.run.task, ", ", r.run.treatment, ", seed ",
                          r.run.seed, ", ", r.run.generations_done + 1, " of ", r.run.generations,
                          " generations>");
        });
}

}  // namespace stepstone::python
