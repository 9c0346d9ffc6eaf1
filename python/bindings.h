// The Python module `zbrdf` (docs/python.md): the libraries and the orchestration of tools/ as
// Python functions over NumPy arrays, built with pybind11. It is a top layer like tools/
// (docs/design.md section 5): it binds what the CLI runs and reimplements none of it.
//
// Each file binds one part; module.cc puts them together:
//   brdf_binding.cc      zbrdf.Brdf (eval, sample, pdf), zbrdf.load, zbrdf.direction, angles
//   file_binding.cc      read_zonal, read_sh, read_dbrdf: zbrdf's files as dicts of arrays
//   pipeline_binding.cc  zbrdf.fit, zbrdf.export, zbrdf.FitContext
//   module.cc            errors, __version__, the data folder of an installed module
//
// Errors: zbrdf's exceptions reach Python with their message unchanged (basis/error.h), as
// zbrdf.Error (a RuntimeError) and its subclasses zbrdf.InputError (also a ValueError: wrong
// input, including wrong arrays), zbrdf.NumericalError and zbrdf.DeviceError.
#pragma once

#include <string>

#include <nlohmann/json.hpp>
#include <pybind11/pybind11.h>

namespace zbrdf::python {

namespace py = pybind11;

void BindBrdf(py::module_& m);
void BindFiles(py::module_& m);
void BindPipeline(py::module_& m);

// A JSON value as the Python object json.loads makes of it (NaN, which JSON cannot hold, was
// already written as null by nlohmann).
py::object ToPython(const nlohmann::json& value);

// A path argument (str or os.PathLike) as text; raises TypeError (naming `what`) for anything else.
std::string PathArgument(const py::handle& value, const char* what);

}  // namespace zbrdf::python
