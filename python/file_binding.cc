// zbrdf's own files as dicts of NumPy arrays, read by the readers the tools use: zonal.exr
// (acquisition/zonal.h), SH files (brdf/sh_file.h) and D-BRDF files (brdf/dbrdf_file.h).
// docs/session-folder.md, docs/sh-and-dbrdf-files.md and docs/formats.md define the contents.
#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <pybind11/numpy.h>

#include "acquisition/zonal.h"
#include "basis/spherical_harmonics.h"
#include "basis/target_basis.h"
#include "brdf/dbrdf_file.h"
#include "brdf/sh_file.h"
#include "python/bindings.h"

namespace zbrdf::python {
namespace {

// (3, rows, cols) from one matrix per channel: out[c, a, b] = m[c](a, b).
py::array_t<double> ChannelMatrices(const std::array<Eigen::MatrixXd, 3>& m) {
  const py::ssize_t rows = m[0].rows(), cols = m[0].cols();
  py::array_t<double> out({py::ssize_t{3}, rows, cols});
  auto view = out.mutable_unchecked<3>();
  for (int c = 0; c < 3; ++c) {
    for (py::ssize_t a = 0; a < rows; ++a) {
      for (py::ssize_t b = 0; b < cols; ++b) view(c, a, b) = m[c](a, b);
    }
  }
  return out;
}

// (n, 2) array of (l, m) per function.
py::array_t<int> DegreeOrders(const std::vector<std::array<int, 2>>& lm) {
  py::array_t<int> out({static_cast<py::ssize_t>(lm.size()), py::ssize_t{2}});
  auto view = out.mutable_unchecked<2>();
  for (size_t k = 0; k < lm.size(); ++k) {
    view(k, 0) = lm[k][0];
    view(k, 1) = lm[k][1];
  }
  return out;
}

py::dict ReadZonal(const py::handle& path_value) {
  const std::string path = PathArgument(path_value, "path");
  ZonalData data;
  {
    py::gil_scoped_release release;
    data = ReadZonalExr(path);
  }
  const ExitantGrid& grid = data.grid;
  const py::ssize_t functions = static_cast<py::ssize_t>(data.functions.size());
  const py::ssize_t n_theta = grid.n_theta, n_phi = grid.n_phi;
  // Per function k: z_k on the exitant grid, (k, channel, theta row, phi column).
  py::array_t<float> value({functions, py::ssize_t{3}, n_theta, n_phi});
  py::array_t<float> variance({functions, py::ssize_t{3}, n_theta, n_phi});
  py::array_t<float> weight({functions, py::ssize_t{3}, n_theta, n_phi});
  py::array_t<bool> filled({functions, n_theta, n_phi});
  auto v = value.mutable_unchecked<4>();
  auto s = variance.mutable_unchecked<4>();
  auto w = weight.mutable_unchecked<4>();
  auto f = filled.mutable_unchecked<3>();
  for (py::ssize_t k = 0; k < functions; ++k) {
    const GridImage& image = data.functions[k];
    for (py::ssize_t cell = 0; cell < n_theta * n_phi; ++cell) {
      const py::ssize_t i = cell / n_phi, j = cell % n_phi;
      for (int c = 0; c < 3; ++c) {
        v(k, c, i, j) = image.value[c].empty() ? 0.f : image.value[c][cell];
        s(k, c, i, j) = image.variance[c].empty() ? 0.f : image.variance[c][cell];
        w(k, c, i, j) = image.weight[c].empty() ? 0.f : image.weight[c][cell];
      }
      f(k, i, j) = !image.filled.empty() && image.filled[cell] != 0;
    }
  }
  std::vector<std::array<int, 2>> lm;
  for (int k = 0; k < (data.order + 1) * (data.order + 1); ++k) {
    int l = 0, m = 0;
    ShDegreeOrder(k, &l, &m);
    lm.push_back({l, m});
  }
  py::dict grid_dict;
  grid_dict["theta_min_rad"] = grid.theta_min_rad;
  grid_dict["theta_max_rad"] = grid.theta_max_rad;
  grid_dict["theta_step_rad"] = grid.theta_step_rad;
  grid_dict["phi_step_rad"] = grid.phi_step_rad;
  grid_dict["n_theta"] = grid.n_theta;
  grid_dict["n_phi"] = grid.n_phi;
  py::dict out;
  out["theta_min_rad"] = data.theta_min_rad;
  out["theta_max_rad"] = data.theta_max_rad;
  out["order"] = data.order;
  out["lm"] = DegreeOrders(lm);
  out["tensor"] = ChannelMatrices(data.tensor);
  out["tensor_variance"] = ChannelMatrices(data.tensor_variance);
  out["grid"] = grid_dict;
  out["value"] = value;
  out["variance"] = variance;
  out["weight"] = weight;
  out["filled"] = filled;
  out["attributes"] = ToPython(data.attributes);
  return out;
}

py::dict ReadSh(const py::handle& path_value) {
  const std::string path = PathArgument(path_value, "path");
  ShBrdfData data;
  {
    py::gil_scoped_release release;
    data = ReadShFile(path);
  }
  const TargetBasis basis(data.target, data.order);
  std::vector<std::array<int, 2>> lm;
  for (int k = 0; k < basis.size(); ++k) lm.push_back({basis.degree(k), basis.azimuthal_order(k)});
  const py::ssize_t n = data.size(), rows = data.exitant_theta, cols = data.exitant_phi;
  // exitant[c][(i * cols + j) * n + a] -> (channel, theta row i, phi column j, function a).
  py::array_t<float> exitant({py::ssize_t{3}, rows, cols, n});
  for (int c = 0; c < 3; ++c) {
    if (data.exitant[c].size() != static_cast<size_t>(rows * cols * n)) continue;
    std::copy(data.exitant[c].begin(), data.exitant[c].end(),
              exitant.mutable_data() + c * rows * cols * n);
  }
  py::dict out;
  out["theta_min_rad"] = data.theta_min_rad;
  out["theta_max_rad"] = data.theta_max_rad;
  out["target"] = TargetName(data.target);
  out["order"] = data.order;
  out["lm"] = DegreeOrders(lm);
  out["coefficients"] = ChannelMatrices(data.coefficients);
  out["exitant"] = exitant;
  out["info"] = ToPython(data.info);
  return out;
}

py::dict ReadDBrdf(const py::handle& path_value) {
  const std::string path = PathArgument(path_value, "path");
  std::unique_ptr<DBrdf> model;
  nlohmann::json info;
  {
    py::gil_scoped_release release;
    model = ReadDBrdfFile(path);
    info = ReadDBrdfFileInfo(path);
  }
  const HalfVectorTable& table = model->table();
  py::array_t<double> p({py::ssize_t{table.theta_samples}, py::ssize_t{table.phi_samples}});
  py::array_t<double> theta_h(table.theta_samples), phi_h(table.phi_samples);
  for (int j = 0; j < table.theta_samples; ++j) {
    theta_h.mutable_data()[j] = j * table.ThetaStep();
    for (int k = 0; k < table.phi_samples; ++k)
      p.mutable_data()[j * table.phi_samples + k] = table.At(j, k);
  }
  for (int k = 0; k < table.phi_samples; ++k) phi_h.mutable_data()[k] = k * table.PhiStep();
  const auto rgb = [](const Rgb& v) {
    py::array_t<double> a(3);
    for (int c = 0; c < 3; ++c) a.mutable_data()[c] = v[c];
    return a;
  };
  py::dict out;
  out["c"] = rgb(model->c());
  out["f0"] = model->f0();
  out["kd"] = rgb(model->kd());
  out["p"] = p;
  out["theta_h_rad"] = theta_h;
  out["phi_h_rad"] = phi_h;
  out["spec"] = model->Spec();
  out["info"] = ToPython(info);
  return out;
}

}  // namespace

void BindFiles(py::module_& m) {
  m.def("read_zonal", &ReadZonal, py::arg("path"),
        "A zonal.exr (docs/session-folder.md) as a dict: theta_min_rad, theta_max_rad, order, "
        "lm (K, 2) the (l, m) of each zonal function in ShIndex order, tensor and "
        "tensor_variance (3, K, K) float64 (channel, k of w_i, j of w_r), grid (the exitant "
        "grid's zone, steps and counts), value, variance and weight (K, 3, n_theta, n_phi) "
        "float32 (z_k on the exitant grid), filled (K, n_theta, n_phi) bool, attributes.");
  m.def("read_sh", &ReadSh, py::arg("path"),
        "An SH file (docs/sh-and-dbrdf-files.md) as a dict: theta_min_rad, theta_max_rad, "
        "target, order, lm (n, 2), coefficients (3, n, n) float64 y_ab (channel, a of w_i, b of "
        "w_r) of f_r cos(theta_i), exitant (3, rows, cols, n) float32 per-exitant tables y_a(w_r), "
        "info.");
  m.def("read_dbrdf", &ReadDBrdf, py::arg("path"),
        "A D-BRDF file (docs/sh-and-dbrdf-files.md) as a dict: c (3,), f0, kd (3,), p "
        "(theta_samples, phi_samples) the normalized p(h) in 1/sr at nodes theta_h_rad, "
        "phi_h_rad, spec (a material spec of the same model), info (the fit report).");
}

}  // namespace zbrdf::python
