// zbrdf.Brdf and zbrdf.load: anything `zbrdf eval` accepts (tools/brdf_input.h), evaluated,
// sampled and its density taken over arrays of directions.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "basis/error.h"
#include "basis/parallel.h"
#include "basis/vec3.h"
#include "brdf/brdf.h"
#include "python/bindings.h"
#include "tools/brdf_eval.h"
#include "tools/brdf_input.h"

namespace zbrdf::python {
namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// Rows per task of the parallel sample and pdf loops.
constexpr int64_t kPairsPerTask = 4096;

// Directions further than this from unit length are refused: 1e-6 admits vectors that went
// through float32 (relative rounding 6e-8 per component) and catches unnormalized ones.
constexpr double kUnitTolerance = 1e-6;

std::string ShapeText(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) {
    text += (d ? ", " : "") + std::to_string(a.shape(d));
  }
  return text + (a.ndim() == 1 ? ",)" : ")");
}

// Rows of three numbers: an (N, 3) array, or one row given as (3,). `single` remembers the
// latter, so that results drop the N axis as NumPy would.
struct Rows {
  std::vector<double> values;
  int64_t count = 0;
  bool single = false;
  const double* Row(int64_t k) const { return values.data() + 3 * (count == 1 ? 0 : k); }
};

Rows ToRows(const py::handle& value, const char* name, const char* what) {
  const Array a = Array::ensure(value);
  if (!a) {
    throw InputError(
        std::string(name) + " must be an array of shape (N, 3) or (3,) of " + what + "; got a " +
        py::str(py::type::of(value).attr("__name__")).cast<std::string>() + " that is not numeric");
  }
  if (!((a.ndim() == 2 && a.shape(1) == 3) || (a.ndim() == 1 && a.shape(0) == 3))) {
    throw InputError(std::string(name) + " must be an array of shape (N, 3) or (3,) of " + what +
                     "; got shape " + ShapeText(a));
  }
  Rows rows;
  rows.single = a.ndim() == 1;
  rows.count = rows.single ? 1 : a.shape(0);
  rows.values.assign(a.data(), a.data() + 3 * rows.count);
  return rows;
}

std::string RowText(const Rows& rows, const char* name, int64_t k) {
  char text[160];
  const double* r = rows.Row(k);
  std::snprintf(text, sizeof(text), "%s[%lld] = (%.17g, %.17g, %.17g)", name,
                static_cast<long long>(k), r[0], r[1], r[2]);
  return text;
}

// Unit vectors in the sample frame (docs/design.md section 2); a direction is not normalized
// silently, since an unnormalized one usually means a frame or unit mistake upstream.
Rows ToDirections(const py::handle& value, const char* name) {
  Rows rows = ToRows(value, name, "unit directions in the sample frame (normal +z)");
  for (int64_t k = 0; k < rows.count; ++k) {
    const double* r = rows.Row(k);
    const double length = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (!std::isfinite(length)) {
      throw InputError(RowText(rows, name, k) + " is not finite; directions must be unit vectors");
    }
    if (std::abs(length - 1.0) > kUnitTolerance) {
      throw InputError(RowText(rows, name, k) + " has length " + std::to_string(length) +
                       "; directions must be unit vectors (normalize them, or build them with "
                       "zbrdf.direction(theta, phi))");
    }
  }
  return rows;
}

// Uniform random numbers (u_lobe, u0, u1) in [0, 1) per row, as Brdf::Sample takes them.
Rows ToUniforms(const py::handle& value, const char* name) {
  Rows rows = ToRows(value, name, "uniform random numbers (u_lobe, u0, u1) in [0, 1)");
  for (int64_t k = 0; k < rows.count; ++k) {
    const double* r = rows.Row(k);
    for (int c = 0; c < 3; ++c) {
      if (!(r[c] >= 0.0 && r[c] < 1.0)) {
        throw InputError(RowText(rows, name, k) + ": uniform numbers must lie in [0, 1)");
      }
    }
  }
  return rows;
}

Vec3 AsVec3(const double* r) { return {r[0], r[1], r[2]}; }

// The number of rows of a call: every argument has either one row (used for all) or the same N.
int64_t BroadcastCount(const Rows& a, const char* a_name, const Rows& b, const char* b_name) {
  if (a.count == b.count || b.count == 1) return a.count;
  if (a.count == 1) return b.count;
  throw InputError(std::string(a_name) + " has " + std::to_string(a.count) + " rows and " + b_name +
                   " " + std::to_string(b.count) +
                   "; give the same number of rows, or one row for all");
}

// The shape of a result with `columns` values per row (0: one value per row).
std::vector<py::ssize_t> ResultShape(int64_t count, bool single, py::ssize_t columns) {
  std::vector<py::ssize_t> shape;
  if (!single) shape.push_back(count);
  if (columns > 0) shape.push_back(columns);
  return shape;
}

// f_r for every row: tools/brdf_eval.h's EvaluateDirections, what `zbrdf eval` computes (the
// same EvalBatch blocks), 0 where either direction is below the horizon.
py::array_t<double> Eval(const BrdfInput& input, const py::handle& w_i_value,
                         const py::handle& w_o_value) {
  const Rows w_i = ToDirections(w_i_value, "w_i");
  const Rows w_o = ToDirections(w_o_value, "w_o");
  const int64_t n = BroadcastCount(w_i, "w_i", w_o, "w_o");
  py::array_t<double> f(ResultShape(n, w_i.single && w_o.single, 3));
  double* out = f.mutable_data();
  const Brdf& brdf = *input.brdf;
  {
    py::gil_scoped_release release;
    std::vector<Vec3> a(n), b(n);
    for (int64_t k = 0; k < n; ++k) {
      a[k] = AsVec3(w_i.Row(k));
      b[k] = AsVec3(w_o.Row(k));
    }
    std::vector<Rgb> rgb(n);
    EvaluateDirections(brdf, a, b, rgb);
    for (int64_t k = 0; k < n; ++k) {
      out[3 * k + 0] = rgb[k].r;
      out[3 * k + 1] = rgb[k].g;
      out[3 * k + 2] = rgb[k].b;
    }
  }
  return f;
}

py::tuple Sample(const BrdfInput& input, const py::handle& w_o_value, const py::handle& u_value) {
  const Rows w_o = ToDirections(w_o_value, "w_o");
  const Rows u = ToUniforms(u_value, "u");
  const int64_t n = BroadcastCount(w_o, "w_o", u, "u");
  const bool single = w_o.single && u.single;
  py::array_t<double> w_i(ResultShape(n, single, 3)), pdf(ResultShape(n, single, 0));
  double* w_out = w_i.mutable_data();
  double* pdf_out = pdf.mutable_data();
  const Brdf& brdf = *input.brdf;
  {
    py::gil_scoped_release release;
    ParallelFor(n, kPairsPerTask, [&](int64_t begin, int64_t end) {
      for (int64_t k = begin; k < end; ++k) {
        const double* r = u.Row(k);
        const BrdfSample s = brdf.Sample(AsVec3(w_o.Row(k)), r[0], r[1], r[2]);
        w_out[3 * k + 0] = s.w_i.x;
        w_out[3 * k + 1] = s.w_i.y;
        w_out[3 * k + 2] = s.w_i.z;
        pdf_out[k] = s.pdf;
      }
    });
  }
  return py::make_tuple(w_i, pdf);
}

py::array_t<double> Pdf(const BrdfInput& input, const py::handle& w_o_value,
                        const py::handle& w_i_value) {
  const Rows w_o = ToDirections(w_o_value, "w_o");
  const Rows w_i = ToDirections(w_i_value, "w_i");
  const int64_t n = BroadcastCount(w_o, "w_o", w_i, "w_i");
  py::array_t<double> pdf(ResultShape(n, w_o.single && w_i.single, 0));
  double* out = pdf.mutable_data();
  const Brdf& brdf = *input.brdf;
  {
    py::gil_scoped_release release;
    ParallelFor(n, kPairsPerTask, [&](int64_t begin, int64_t end) {
      for (int64_t k = begin; k < end; ++k) {
        out[k] = brdf.Pdf(AsVec3(w_o.Row(k)), AsVec3(w_i.Row(k)));
      }
    });
  }
  return pdf;
}

// One array of angles (any shape, or a number) as doubles, with its shape.
struct AngleArray {
  std::vector<double> values;
  std::vector<py::ssize_t> shape;
};

AngleArray ToAngles(const py::handle& value, const char* name) {
  const Array a = Array::ensure(value);
  if (!a) {
    throw InputError(std::string(name) + " must be a number or an array of numbers (radians)");
  }
  AngleArray angles;
  angles.values.assign(a.data(), a.data() + a.size());
  angles.shape.assign(a.shape(), a.shape() + a.ndim());
  return angles;
}

// Unit vectors from polar angle and azimuth (basis/vec3.h SphericalDirection, the function
// `zbrdf eval` turns its input angles with): shape theta.shape + (3,).
py::array_t<double> Direction(const py::handle& theta_value, const py::handle& phi_value) {
  const AngleArray theta = ToAngles(theta_value, "theta");
  const AngleArray phi = ToAngles(phi_value, "phi");
  const size_t n_theta = theta.values.size(), n_phi = phi.values.size();
  if (n_theta != n_phi && n_theta != 1 && n_phi != 1) {
    throw InputError("theta has " + std::to_string(n_theta) + " values and phi " +
                     std::to_string(n_phi) + "; give the same number, or one value for all");
  }
  const bool by_phi = n_theta == 1 && n_phi != 1;
  const size_t n = by_phi ? n_phi : n_theta;
  std::vector<py::ssize_t> shape = by_phi ? phi.shape : theta.shape;
  shape.push_back(3);
  py::array_t<double> w(shape);
  double* out = w.mutable_data();
  for (size_t k = 0; k < n; ++k) {
    const Vec3 d =
        SphericalDirection(theta.values[n_theta == 1 ? 0 : k], phi.values[n_phi == 1 ? 0 : k]);
    out[3 * k + 0] = d.x;
    out[3 * k + 1] = d.y;
    out[3 * k + 2] = d.z;
  }
  return w;
}

// (theta, phi) of directions (basis/vec3.h SphericalTheta, SphericalPhi: phi in [0, 2 pi)).
py::tuple DirectionAngles(const py::handle& w_value) {
  const Rows w = ToRows(w_value, "w", "directions");
  const std::vector<py::ssize_t> shape = ResultShape(w.count, w.single, 0);
  py::array_t<double> theta(shape), phi(shape);
  for (int64_t k = 0; k < w.count; ++k) {
    const Vec3 d = AsVec3(w.Row(k));
    theta.mutable_data()[k] = SphericalTheta(d);
    phi.mutable_data()[k] = SphericalPhi(d);
  }
  return py::make_tuple(theta, phi);
}

BrdfInput Load(const py::handle& spec_or_path) {
  const std::string input = PathArgument(spec_or_path, "spec_or_path");
  py::gil_scoped_release release;  // a MERL table or an RGL file takes a while to read
  return ResolveBrdfInput(input);
}

}  // namespace

void BindBrdf(py::module_& m) {
  py::class_<BrdfInput>(m, "Brdf",
                        "A BRDF: a material spec, a file or a session's fit, as zbrdf.load makes "
                        "it (what `zbrdf eval` accepts). Directions are unit vectors in the "
                        "sample frame (normal +z, azimuth from +x), w_i toward the light, w_o "
                        "toward the viewer, as float64 arrays of shape (N, 3) or (3,) for one; "
                        "one row is used for all rows of the other argument.")
      .def(py::init(&Load), py::arg("spec_or_path"), "The same as zbrdf.load(spec_or_path).")
      .def("eval", &Eval, py::arg("w_i"), py::arg("w_o"),
           "f_r(w_i, w_o) in 1/sr, linear RGB, no cosine: shape (N, 3). 0 where either "
           "direction is below the horizon. Computed as `zbrdf eval` does (Brdf::EvalBatch on "
           "all cores, without the GIL).")
      .def("sample", &Sample, py::arg("w_o"), py::arg("u"),
           "Importance-samples w_i given w_o from uniforms u = (u_lobe, u0, u1) in [0, 1), "
           "shape (N, 3). Returns (w_i (N, 3), pdf (N,)): pdf is the solid-angle density over "
           "the whole sphere of w_i; 0 means no sample was produced (w_o below the horizon); "
           "for a delta material (is_delta) it is 1, the probability of the one direction.")
      .def("pdf", &Pdf, py::arg("w_o"), py::arg("w_i"),
           "Solid-angle density (N,) with which sample() proposes w_i given w_o (0 for every "
           "pair of a delta material).")
      .def_property_readonly(
          "spec", [](const BrdfInput& in) { return in.brdf->Spec(); },
          "A material spec that recreates the model (brdf/material_spec.h).")
      .def_readonly("kind", &BrdfInput::kind,
                    "What was loaded: spec, session, dbrdf-file, tabulated-file, sh-file, "
                    "fit-json, merl-file, network-file, rgl-file, brdf-explorer-file; fit for a "
                    "model zbrdf.fit returned.")
      .def_readonly("source", &BrdfInput::source, "The file read, or the spec.")
      .def_readonly("session_dir", &BrdfInput::session_dir, "The session folder, if one.")
      .def_readonly("name", &BrdfInput::name, "A short name for titles and file names.")
      .def_readonly("description", &BrdfInput::description, "What was loaded from where.")
      .def_property_readonly("is_isotropic",
                             [](const BrdfInput& in) { return in.brdf->IsIsotropic(); })
      .def_property_readonly("is_reciprocal",
                             [](const BrdfInput& in) { return in.brdf->IsReciprocal(); })
      .def_property_readonly("is_energy_conserving",
                             [](const BrdfInput& in) { return in.brdf->IsEnergyConserving(); })
      .def_property_readonly("is_delta", [](const BrdfInput& in) { return in.brdf->IsDelta(); })
      .def("__repr__", [](const BrdfInput& in) {
        return "<zbrdf.Brdf " + in.kind + " '" + in.name + "': " + in.description + ">";
      });
  m.def("load", &Load, py::arg("spec_or_path"),
        "A BRDF from anything `zbrdf eval` accepts (tools/brdf_input.h): a material spec "
        "(merl:blue-acrylic, ggx:alpha=0.2, ...), a file (MERL .binary, RGL .bsdf, SH, D-BRDF "
        "or tabulated .exr, network or fit .json, BRDF Explorer .brdf) or a session folder. "
        "Raises zbrdf.InputError (a ValueError) saying what was tried.");
  m.def("direction", &Direction, py::arg("theta"), py::arg("phi"),
        "Unit vectors from polar angle theta (from the normal +z) and azimuth phi (from +x), "
        "radians, numbers or arrays of one shape: shape theta.shape + (3,). The function "
        "`zbrdf eval` turns its angles into directions with.");
  m.def("angles", &DirectionAngles, py::arg("w"),
        "(theta, phi) in radians of directions w of shape (N, 3); phi in [0, 2 pi).");
}

}  // namespace zbrdf::python
