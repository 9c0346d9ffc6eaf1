// Synthetic session folders for the tests of what reads one (acquisition/, pictures/, tools/):
// session.json, report.json, zonal.exr with known coefficients, and the files a fit or
// conversion leaves (fit-dbrdf.exr, fit-<model>.json, sh.exr), written through the same writers
// the pipeline uses.
#pragma once

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "acquisition/zonal.h"
#include "basis/spherical_harmonics.h"
#include "brdf/dbrdf.h"
#include "brdf/dbrdf_file.h"
#include "brdf/sh_file.h"

namespace zbrdf::testing {

inline void WriteJson(const std::string& path, const nlohmann::json& j) {
  std::ofstream(path) << j.dump(2) << "\n";
}

// session.json of a simulated session of `material` (empty: a measured one).
inline void WriteSessionJson(const std::string& dir, const std::string& material) {
  nlohmann::json j = {{"rig", {{"name", "test-rig"}}}, {"seed", 1}, {"calibration", "nominal"}};
  if (!material.empty()) {
    j["material"] = material;
    j["kind"] = "simulated";
  }
  WriteJson(dir + "/session.json", j);
}

// Zonal data of order 2 on the zone [9, 57] deg whose tensor coefficient (k, j) in channel c is
// (c + 1) / (1 + k + 2 j): every band has energy, and the sums are known.
inline ZonalData MakeZonalData() {
  ZonalData data;
  data.order = 2;
  data.theta_min_rad = 9 * M_PI / 180;
  data.theta_max_rad = 57 * M_PI / 180;
  data.grid = MakeExitantGrid(data.zone(), 6.0, 10.0);
  const int n = ShCount(data.order), cells = data.grid.cells();
  data.functions.resize(n);
  for (GridImage& image : data.functions) {
    for (int c = 0; c < 3; ++c) {
      image.value[c].assign(cells, 0.1f);
      image.variance[c].assign(cells, 0.0f);
      image.weight[c].assign(cells, 1.0f);
    }
    image.filled.assign(cells, 0);
  }
  for (int c = 0; c < 3; ++c) {
    data.tensor[c].resize(n, n);
    data.tensor_variance[c].setZero(n, n);
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < n; ++j) data.tensor[c](k, j) = (c + 1.0) / (1.0 + k + 2.0 * j);
    }
  }
  data.attributes = {{"test", true}};
  return data;
}

// SH data of order 1: f^ = y00 Y00(w_i) Y00(w_r) (a constant f_r cos(theta_i) = y00 / (4 pi)).
inline ShBrdfData MakeShData(double y00 = 0.5) {
  ShBrdfData data;
  data.order = 1;
  data.target = TargetKind::kSh;
  data.theta_min_rad = 9 * M_PI / 180;
  data.theta_max_rad = 57 * M_PI / 180;
  data.exitant_theta = 9;
  data.exitant_phi = 12;
  for (int c = 0; c < 3; ++c) {
    data.coefficients[c].setZero(4, 4);
    data.coefficients[c](0, 0) = y00 * (c + 1);
  }
  data.FillExitantTables();
  return data;
}

inline DBrdf MakeDBrdf() {
  DBrdfParams params;
  std::vector<double> p(19);
  for (int j = 0; j < 19; ++j) p[j] = std::exp(-j / 3.0);
  params.p_h = HalfVectorTable::Isotropic(p);
  params.p_h.Normalize();
  params.c = Rgb(0.3, 0.25, 0.2);
  params.f0 = 0.5;
  params.kd = Rgb(0.05);
  return DBrdf(params);
}

}  // namespace zbrdf::testing
