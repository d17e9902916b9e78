#pragma once

// The parts of the Python module (module.cpp assembles them). Each bind_*
// adds its classes and functions to `m`; docstrings follow the C++ docs.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl/filesystem.h>

#include <cstddef>
#include <span>
#include <string>

namespace stepstone::sim {
struct Milestones;
}

namespace stepstone::python {

namespace py = pybind11;

void bind_kb(py::module_& m);
void bind_run(py::module_& m);
void bind_sim(py::module_& m);

/// A C-contiguous float32 array (any other dtype or layout is converted once).
using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

/// The values of a (steps x channels) behaviour matrix, checked: two
/// dimensions and `channels` columns, else ValueError naming `what`.
std::span<const float> behaviour_values(const FloatArray& behaviour, std::size_t channels, const char* what);

/// A fresh (rows x columns) float32 array holding a copy of `values`.
py::array_t<float> matrix_copy(std::span<const float> values, std::size_t columns);

/// {presses, pickups, carry_steps, basket_releases} of an evaluation.
py::dict milestones_dict(const sim::Milestones& milestones);

/// json.loads(text): a Python object from a JSON document.
py::object json_loads(const std::string& text);
/// json.dumps(object): a JSON document from a Python dict, list or str (a str is returned as is).
std::string json_text(const py::handle& object);

}  // namespace stepstone::python
