// `import stepstone`: knowledge bases, run files and the simulator from Python
// (docs/library.md: Python). Errors of the library arrive as stepstone.Error
// subclasses carrying its one-line message.

#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "core/version.hpp"
#include "sim/episode.hpp"

namespace stepstone::python {

std::span<const float> behaviour_values(const FloatArray& behaviour, std::size_t channels, const char* what) {
    if (behaviour.ndim() != 2) {
        throw py::value_error(
            concat(what, " must be a (steps x channels) matrix, got ", behaviour.ndim(), " dimension(s)"));
    }
    if (static_cast<std::size_t>(behaviour.shape(1)) != channels) {
        throw py::value_error(concat(what, " has ", behaviour.shape(1), " columns, the knowledge base has ",
                                     channels, " channels"));
    }
    return {behaviour.data(), static_cast<std::size_t>(behaviour.size())};
}

py::array_t<float> matrix_copy(std::span<const float> values, std::size_t columns) {
    const auto rows = static_cast<py::ssize_t>(columns == 0 ? 0 : values.size() / columns);
    py::array_t<float> out({rows, static_cast<py::ssize_t>(columns)});
    std::copy(values.begin(), values.end(), out.mutable_data());
    return out;
}

py::dict milestones_dict(const sim::Milestones& m) {
    py::dict out;
    out["presses"] = m.presses;
    out["pickups"] = m.pickups;
    out["carry_steps"] = m.carry_steps;
    out["basket_releases"] = m.basket_releases;
    return out;
}

py::object json_loads(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

std::string json_text(const py::handle& object) {
    if (py::isinstance<py::str>(object)) return object.cast<std::string>();
    return py::module_::import("json").attr("dumps")(object).cast<std::string>();
}

}  // namespace stepstone::python

PYBIND11_MODULE(stepstone, m) {
    namespace py = pybind11;
    using namespace stepstone::python;
    m.doc() = R"(stepstone: knowledge bases of behaviour segments for reward shaping in evolutionary robotics.

KnowledgeBase   segments of behaviour with the cumulated reward of the policies that showed them
Run             a run file written by `stepstone evolve`, read-only
Task, Episode   the simulator: evaluate a genome, or drive an episode from Python
evaluate        one evaluation of a genome on a task

Files are the SQLite files the `stepstone` command reads and writes.)";
    m.attr("__version__") = std::string(stepstone::program_version());
    m.attr("__commit__") = std::string(stepstone::build_commit());

    // the library's errors, with its one-line messages
    static py::exception<stepstone::Error> error(m, "Error");
    static py::exception<stepstone::ConfigError> config_error(m, "ConfigError", error.ptr());
    static py::exception<stepstone::DataError> data_error(m, "DataError", error.ptr());
    static py::exception<stepstone::DatabaseError> database_error(m, "DatabaseError", error.ptr());
    error.doc() =
        "Base of every error of the stepstone library: str(e) is one line naming the bad value or file.";
    config_error.doc() = "A parameter or config value is unusable.";
    data_error.doc() = "Data is unusable: NaN, wrong dimensions, inconsistent sizes.";
    database_error.doc() = "A file is missing, foreign, corrupt or of an unknown schema version.";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const stepstone::ConfigError& e) {
            config_error(e.what());
        } catch (const stepstone::DataError& e) {
            data_error(e.what());
        } catch (const stepstone::DatabaseError& e) {
            database_error(e.what());
        } catch (const stepstone::Error& e) {
            error(e.what());
        }
    });

    bind_kb(m);
    bind_run(m);
    bind_sim(m);
}
