// The SH BRDF file: zonal data converted to spherical harmonics (zbrdf convert), for renderers.
//
// The stored function is f^(w_i, w_r) = f_r(w_i, w_r) cos(theta_i), expanded in a target basis
// T_a (basis/target_basis.h: sh, sh-even, sh-odd or hsh, order L) in both directions:
//   f^(w_i, w_r) = sum_a sum_b y_ab T_a(w_i) T_b(w_r)                           (tensor form)
//               = sum_a y_a(w_r) T_a(w_i),  y_a(w_r) = sum_b y_ab T_b(w_r)      (per-exitant form)
// The per-exitant form is what the thesis's renderer used (Ghosh 2007, section 3.4.1, eq. 3.17):
// y_a tabulated over a grid of exitant directions, 90 x 90 cells over the upper hemisphere by
// default, cell (i, j) centred at theta_r = (i + 1/2) (pi/2) / rows, phi_r = (j + 1/2) 2 pi / cols.
//
// OpenEXR, two scanline parts:
//   "exitant"  cols x rows pixels; per target function a one layer <name>.R/.G/.B (FLOAT), name
//              "Y<l>_<m>" (sh, sh-even, sh-odd) or "H<l>_<m>" (hsh), e.g. Y2_-1.G.
//   "tensor"   n x n pixels (n = number of target functions); channels y.R/.G/.B; pixel
//              (x = b, y = a) is y_ab (row a: the function of w_i, column b: of w_r).
// Header attributes (both parts): zbrdf.format "zbrdf-sh-v1"; zbrdf.target ("sh", ...);
// zbrdf.order (int); zbrdf.theta_min_rad, zbrdf.theta_max_rad (double: the measured zone; outside
// it the function is extrapolated); zbrdf.quantity "f_r*cos(theta_i)"; zbrdf.normalization (the
// SH convention, as text); zbrdf.info (JSON: conversion diagnostics, provenance).
// docs/sh-and-dbrdf-files.md is the reader's guide.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "basis/target_basis.h"
#include "basis/vec3.h"

namespace zbrdf {

struct ShBrdfData {
  double theta_min_rad = 0, theta_max_rad = 0;  // the zone the data were measured on
  TargetKind target = TargetKind::kSh;
  int order = 0;
  // y_ab per channel: size() x size(), rows a (w_i), columns b (w_r).
  std::array<Eigen::MatrixXd, 3> coefficients;
  // Per-exitant tables: exitant[ch][(i * exitant_phi + j) * size() + a] = y_a(w_r of cell (i, j)).
  int exitant_theta = 90, exitant_phi = 90;
  std::array<std::vector<float>, 3> exitant;
  nlohmann::json info = nlohmann::json::object();

  int size() const;  // number of target functions
  // Centre of exitant cell (i, j) (see above).
  Vec3 ExitantDirection(int i, int j) const;
  // Fills `exitant` from `coefficients` (on the current exitant_theta x exitant_phi grid).
  void FillExitantTables();
  // Empty if consistent, else what is wrong.
  std::string Problems() const;
};

// The layer name of target function a ("Y2_-1", "H3_0").
std::string ShLayerName(TargetKind target, int l, int m);

// Throws InputError naming the file if it cannot be written or the data are inconsistent.
void WriteShFile(const std::string& path, const ShBrdfData& data);
// Throws InputError naming the file and what is wrong.
ShBrdfData ReadShFile(const std::string& path);

}  // namespace zbrdf
