// stepstone.Task, stepstone.evaluate and stepstone.Episode: the simulator from
// Python, for a stored genome or for a policy written in Python.

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "core/config.hpp"
#include "core/error.hpp"
#include "core/portable_math.hpp"
#include "core/rng.hpp"
#include "core/text.hpp"
#include "exp/evaluation.hpp"
#include "nn/genome.hpp"
#include "sim/arena_spec.hpp"
#include "sim/episode.hpp"
#include "sim/task.hpp"

namespace stepstone::python {

namespace {

struct PyTask {
    std::shared_ptr<const sim::Task> task;
};

py::dict result_dict(double reward, int balls, long steps, int nan_outputs,
                     const sim::Milestones& milestones) {
    py::dict out;
    out["reward"] = reward;
    out["balls"] = balls;
    out["steps"] = steps;
    out["nan_outputs"] = nan_outputs;
    out["milestones"] = milestones_dict(milestones);
    return out;
}

nn::DnnConfig dnn_of(const py::object& dnn) {
    if (dnn.is_none()) return {};
    const nlohmann::json json = nlohmann::json::parse(json_text(dnn));
    JsonReader reader(json, "dnn");
    return nn::DnnConfig::from_json(reader);
}

nn::Genome genome_of(const py::object& genome) {
    nlohmann::json json;
    try {
        json = nlohmann::json::parse(json_text(genome));
    } catch (const nlohmann::json::parse_error&) {
        throw DataError("genome is not JSON (pass a dict, or the JSON text a run stores)");
    }
    return nn::Genome::from_json(json);
}

py::dict evaluate(const PyTask& task, const py::object& genome, const py::object& dnn) {
    const nn::Genome parsed = genome_of(genome);
    const nn::DnnConfig config = dnn_of(dnn);
    std::vector<float> behaviour(task.task->behaviour_size());
    exp::Evaluation evaluation;
    {
        py::gil_scoped_release release;
        evaluation = exp::evaluate_genome(*task.task, parsed, config, behaviour);
    }
    py::dict out = result_dict(evaluation.reward, evaluation.balls, evaluation.steps, evaluation.nan_outputs,
                               evaluation.milestones);
    out["behaviour"] = matrix_copy(behaviour, sim::kChannels);
    return out;
}

py::array_t<float> inputs_array(const std::array<float, sim::kInputs>& inputs) {
    py::array_t<float> out(sim::kInputs);
    std::copy(inputs.begin(), inputs.end(), out.mutable_data());
    return out;
}

// An episode a Python controller drives one step at a time, in the order of
// sim::run_episode: starts in turn, each of steps_per_start steps, the whole
// episode ended by the stand-still rule.
class PyEpisode {
public:
    PyEpisode(const PyTask& task, bool record_behaviour)
        : task_(task.task), behaviour_(record_behaviour ? task.task->behaviour_size() : 0) {
        sim::Recording recording;
        recording.behaviour = behaviour_;
        episode_ = std::make_unique<sim::Episode>(*task_, recording);
        begin(0);
    }

    py::array_t<float> observation() const { return inputs_array(inputs_); }

    py::tuple step(const FloatArray& outputs) {
        if (done_) throw py::value_error("the episode is over; call finish() for its result");
        if (outputs.size() != sim::kOutputs) {
            throw py::value_error(concat("outputs must hold ", sim::kOutputs,
                                         " values (left wheel, right wheel, "
                                         "action), got ",
                                         outputs.size()));
        }
        std::array<float, sim::kOutputs> out{};
        std::copy(outputs.data(), outputs.data() + sim::kOutputs, out.begin());
        episode_->act(out.data());
        ++step_;
        if (episode_->stopped()) {
            done_ = true;
        } else if (step_ == task_->config().steps_per_start) {
            if (episode_->start() + 1 < task_->config().starts) {
                begin(episode_->start() + 1);
            } else {
                done_ = true;
            }
        }
        if (!done_) episode_->read_inputs(inputs_.data());
        return py::make_tuple(observation(), done_);
    }

    py::dict finish() {
        if (finished_) throw py::value_error("finish() was already called on this episode");
        finished_ = true;
        done_ = true;
        const sim::EpisodeResult result = episode_->finish();
        py::dict out =
            result_dict(result.reward, result.balls, result.steps_run, result.nan_outputs, result.milestones);
        out["stopped_early"] = result.stopped_early;
        if (!behaviour_.empty()) out["behaviour"] = matrix_copy(behaviour_, sim::kChannels);
        return out;
    }

    const sim::Episode& episode() const { return *episode_; }
    int step_in_start() const { return step_; }
    bool done() const { return done_; }

private:
    void begin(int start) {
        episode_->begin_start(start);
        step_ = 0;
        episode_->read_inputs(inputs_.data());
    }

    std::shared_ptr<const sim::Task> task_;
    std::vector<float> behaviour_;  // sized once: the episode records into it
    std::unique_ptr<sim::Episode> episode_;
    std::array<float, sim::kInputs> inputs_{};
    int step_ = 0;
    bool done_ = false;
    bool finished_ = false;
};

}  // namespace

void bind_sim(py::module_& m) {
    py::class_<PyTask>(m, "Task", R"(One of the paper's two tasks in the walled arena (docs/simulator.md).

'source': collect balls; a switch opens the door to the second room.
'target': the door is open; each switch press lights one ball, re-armed after 100 steps.
The defaults are the paper's: 3 starts of 4000 steps, the stand-still rule at 100 steps.
The keys are those of a run config's "task" object, so
Task(**run.config["task"], math=run.config.get("math", "libm")) rebuilds a run's task, its arena
and its math included (a stored config names "math" only when portable).)")
        .def(py::init([](const std::string& kind, int steps_per_start, int starts, int still_limit,
                         int grid_period, const py::object& arena, const std::string& math) {
                 sim::TaskConfig config;
                 const auto chosen = parse_math(math);
                 if (!chosen) throw ConfigError(concat("math must be portable or libm, got '", math, "'"));
                 config.math = *chosen;
                 if (py::isinstance<py::str>(arena) || py::hasattr(arena, "__fspath__")) {
                     config.arena = std::make_shared<const sim::ArenaSpec>(
                         sim::ArenaSpec::load(arena.cast<std::filesystem::path>()));
                 } else if (!arena.is_none()) {
                     config.arena = std::make_shared<const sim::ArenaSpec>(
                         sim::ArenaSpec::from_json(nlohmann::json::parse(json_text(arena)), "arena"));
                 }
                 config.kind = sim::parse_task_kind(kind, "kind");
                 config.steps_per_start = steps_per_start;
                 config.starts = starts;
                 config.still_limit = still_limit;
                 config.grid_period = grid_period;
                 return PyTask{sim::make_task(config)};
             }),
             py::arg("kind") = "source", py::arg("steps_per_start") = 4000, py::arg("starts") = 3,
             py::arg("still_limit") = 100, py::arg("grid_period") = 50, py::arg("arena") = py::none(),
             py::arg("math") = "portable",
             "Builds a task; raises ConfigError naming the first value out of range. `arena` is an arena "
             "file's path or an arena as a dict (docs/simulator.md); default: the paper's. `math`: "
             "'portable' (stepstone's sine and cosine, the same on every machine) or 'libm' (glibc's, "
             "what runs made before 0.2.0 used; a stored config without \"math\" is libm).")
        .def_property_readonly(
            "arena", [](const PyTask& t) { return json_loads(t.task->arena_spec().to_json().dump()); },
            "the arena, as a dict in the format of an arena file")
        .def_property_readonly(
            "kind", [](const PyTask& t) { return std::string(sim::to_string(t.task->kind())); },
            "'source' or 'target'")
        .def_property_readonly(
            "steps_per_start", [](const PyTask& t) { return t.task->config().steps_per_start; },
            "steps of each start")
        .def_property_readonly(
            "starts", [](const PyTask& t) { return t.task->config().starts; },
            "starts of an evaluation, 1 to 3 (the arena's start poses in order)")
        .def_property_readonly(
            "still_limit", [](const PyTask& t) { return t.task->config().still_limit; },
            "the evaluation ends when the cumulative still steps exceed this")
        .def_property_readonly(
            "grid_period", [](const PyTask& t) { return t.task->config().grid_period; },
            "steps between two samples of the diversity trajectory")
        .def_property_readonly(
            "reward_divisor", [](const PyTask& t) { return t.task->reward_divisor(); },
            "reward = balls / reward_divisor (8 balls per start)")
        .def("__repr__", [](const PyTask& t) {
            const auto& c = t.task->config();
            return concat("<stepstone.Task ", sim::to_string(c.kind), ": ", c.starts, " starts of ",
                          c.steps_per_start, " steps>");
        });

    m.def(
        "paper_arena", [] { return json_loads(sim::paper_arena().to_json().dump()); },
        "The paper's arena (the default of every task) as a dict in the format of an arena file.");

    m.def("evaluate", &evaluate, py::arg("task"), py::arg("genome"), py::arg("dnn") = py::none(),
          R"(One evaluation of a genome (a dict, or the JSON text a run stores) on `task` with the network
settings `dnn` (a dict of a run config's "dnn" keys; default: the paper's). Returns a dict of reward,
balls, steps, nan_outputs, milestones (presses, pickups, carry_steps, basket_releases) and behaviour,
the first start's (steps x 15) float32 matrix: 12 inputs then 3 outputs per step. Deterministic.)");

    m.def(
        "random_genome",
        [](std::uint64_t seed, const py::object& dnn) {
            Rng rng(seed, 0, 0, Purpose::initial_genome);
            return json_loads(nn::Genome::random_perceptron(dnn_of(dnn), rng).to_json().dump());
        },
        py::arg("seed"), py::arg("dnn") = py::none(),
        "The initial genome of a run with this seed's first individual: every input connected to every "
        "output, genes uniform on [0, 1], as a dict.");

    py::class_<PyEpisode>(m, "Episode", R"(An evaluation a Python controller drives one step at a time.

>>> episode = stepstone.Episode(task)
>>> observation, done = episode.observation, False
>>> while not done:
...     observation, done = episode.step(policy(observation))   # 3 outputs in [0, 1]
>>> episode.finish()["reward"]

Steps run as in `stepstone evolve`: each start in turn for steps_per_start steps, the
stand-still rule ending the whole episode. Outputs are clamped to [0, 1] (NaN counts as 0).
`start` tells a recurrent controller when to reset its state.)")
        .def(py::init<const PyTask&, bool>(), py::arg("task"), py::arg("record_behaviour") = true,
             py::keep_alive<1, 2>(), "Begins the first start of `task`.")
        .def_property_readonly("observation", &PyEpisode::observation,
                               "the 12 inputs of the current step (float32): 3 lasers, 2 ball, 2 basket, 2 "
                               "switch sensors, 2 bumpers, carrying")
        .def("step", &PyEpisode::step, py::arg("outputs"),
             "Applies (left wheel, right wheel, action) and moves on; returns (observation, done).")
        .def("finish", &PyEpisode::finish,
             "The result: reward, balls, steps, nan_outputs, milestones, stopped_early and, when recorded, "
             "the first start's behaviour matrix.")
        .def_property_readonly("done", &PyEpisode::done,
                               "True once the last step ran or the robot stood still too long")
        .def_property_readonly(
            "start", [](const PyEpisode& e) { return e.episode().start(); },
            "the current start (0 to starts - 1)")
        .def_property_readonly("step_in_start", &PyEpisode::step_in_start, "steps run in the current start")
        .def_property_readonly(
            "pose",
            [](const PyEpisode& e) {
                const auto& pose = e.episode().pose();
                return py::make_tuple(pose.x, pose.y, pose.heading);
            },
            "(x, y, heading) in pixels and radians")
        .def_property_readonly(
            "balls", [](const PyEpisode& e) { return e.episode().balls(); },
            "balls scored so far, all starts")
        .def_property_readonly(
            "carrying", [](const PyEpisode& e) { return e.episode().carrying(); },
            "whether the robot carries a ball")
        .def_property_readonly(
            "door_open", [](const PyEpisode& e) { return e.episode().door_open(); },
            "whether the door is open (the target task: always)");
}

}  // namespace stepstone::python
