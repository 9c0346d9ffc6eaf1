// The module `zbrdf`: its errors, its version and where an installed copy finds zbrdf's data.
#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "basis/error.h"
#include "python/bindings.h"

namespace zbrdf::python {
namespace {

// An installed module lies in PREFIX/ZBRDF_PYTHON_INSTALL_DIR and its data in PREFIX/share/zbrdf
// (basis/data_path.h). DataRoot() looks beside the running executable, which for a module is
// the Python interpreter, so the module points ZBRDF_DATA_DIR at its own prefix's data when that
// exists and the variable is unset. In the build tree there is no such folder, and DataRoot()
// falls back to the source tree as it does for the zbrdf binary.
void UseDataBesideTheModule() {
  const char* env = std::getenv("ZBRDF_DATA_DIR");
  if (env != nullptr && *env != '\0') return;
  Dl_info info;
  if (dladdr(reinterpret_cast<void*>(&UseDataBesideTheModule), &info) == 0 ||
      info.dli_fname == nullptr) {
    return;
  }
  std::error_code error;
  const std::filesystem::path module = std::filesystem::canonical(info.dli_fname, error);
  if (error) return;
  const std::filesystem::path root =
      (module.parent_path() / ZBRDF_PYTHON_TO_PREFIX / "share" / "zbrdf").lexically_normal();
  if (std::filesystem::is_directory(root / "data", error)) {
    // Through os.environ, which also calls setenv: Python code and subprocesses see it too.
    py::module_::import("os").attr("environ")["ZBRDF_DATA_DIR"] = root.string();
  }
}

}  // namespace

py::object ToPython(const nlohmann::json& value) {
  return py::module_::import("json").attr("loads")(
      value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

std::string PathArgument(const py::handle& value, const char* what) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::hasattr(value, "__fspath__")) {
    const py::object path = py::module_::import("os").attr("fspath")(value);
    if (py::isinstance<py::str>(path)) return path.cast<std::string>();
  }
  throw py::type_error(std::string(what) + " must be a str or os.PathLike, got " +
                       py::str(py::type::of(value).attr("__name__")).cast<std::string>());
}

}  // namespace zbrdf::python

PYBIND11_MODULE(zbrdf, m) {
  namespace py = pybind11;
  using namespace zbrdf::python;
  m.doc() =
      "zbrdf: BRDF models, measured materials, fits and exports of the zbrdf project, over NumPy "
      "arrays (docs/python.md). Directions are unit vectors in the sample frame: normal +z, "
      "azimuth from +x; w_i toward the light, w_o toward the viewer; f_r in 1/sr, linear RGB, "
      "without any cosine.";
  m.attr("__version__") = ZBRDF_VERSION;

  // The Python classes, then one translator that tries the most specific C++ class first.
  static py::exception<zbrdf::Error> error(m, "Error", PyExc_RuntimeError);
  // InputError is both: `except ValueError` and `except zbrdf.Error` catch it.
  static py::exception<zbrdf::InputError> input_error(
      m, "InputError", py::make_tuple(error, py::handle(PyExc_ValueError)));
  static py::exception<zbrdf::NumericalError> numerical_error(m, "NumericalError", error.ptr());
  static py::exception<zbrdf::DeviceError> device_error(m, "DeviceError", error.ptr());
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const zbrdf::InputError& e) {
      input_error(e.what());
    } catch (const zbrdf::NumericalError& e) {
      numerical_error(e.what());
    } catch (const zbrdf::DeviceError& e) {
      device_error(e.what());
    } catch (const zbrdf::Error& e) {
      error(e.what());
    }
  });

  UseDataBesideTheModule();
  BindBrdf(m);
  BindFiles(m);
  BindPipeline(m);
}
