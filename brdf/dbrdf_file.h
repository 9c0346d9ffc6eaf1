// The D-BRDF file: a fitted distribution-based BRDF (dbrdf.h) for renderers, as OpenEXR.
//
// One scanline part, phi_samples pixels wide and theta_samples high, one FLOAT channel "p":
// pixel (x = k, y = j) is p(h) in 1/sr at theta_h = j (pi/2) / (theta_samples - 1) and phi_h =
// k 2 pi / phi_samples (linear interpolation in between, periodic in phi). Header attributes:
//   zbrdf.format  "zbrdf-dbrdf-v1"          zbrdf.model  the formula, as text
//   zbrdf.c       V3d, RGB scale c           zbrdf.F0     double, Schlick's F0
//   zbrdf.kd      V3d, RGB diffuse albedo    zbrdf.info   JSON text (fit report, provenance)
// Evaluate f_r = c p(h) F(w_i.h) / (w_i.n + w_o.n - (w_i.n)(w_o.n)) + kd / pi. docs/sh-and-dbrdf-
// files.md is the reader's guide.
//
// p is stored in 32-bit float, so a file's p integrates to 1 only to ~1e-7; ReadDBrdfFile
// renormalizes it (integral p(h) cos(theta_h) dw_h = 1, dbrdf.h) and folds the factor into c, so
// f_r round-trips to float precision.
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "brdf/dbrdf.h"

namespace zbrdf {

// Throws InputError naming the file if it cannot be written.
void WriteDBrdfFile(const std::string& path, const DBrdf& model, const nlohmann::json& info);

// Throws InputError naming the file and what is wrong (not an EXR, not a D-BRDF file, a missing
// attribute, a negative or non-finite p, p all zero).
std::unique_ptr<DBrdf> ReadDBrdfFile(const std::string& path);

// The zbrdf.info attribute of a D-BRDF file (an empty object if absent).
nlohmann::json ReadDBrdfFileInfo(const std::string& path);

}  // namespace zbrdf
