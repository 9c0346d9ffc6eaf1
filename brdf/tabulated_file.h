// The tabulated BRDF file: a whole-hemisphere isotropic BRDF on a HalfDiffGrid
// (brdf/tabulated_brdf.h), as OpenEXR, for renderers and for zbrdf's own tools. `zbrdf fit
// --model prior` writes one (fit-prior.exr); export, eval, preview and compare read it.
//
// One scanline part, ZIP-compressed, phi_d_nodes pixels wide and theta_h_nodes * theta_d_nodes
// high: pixel (x = ip, y = ih * theta_d_nodes + id) is the node (theta_h = (pi/2) (ih / (nh -
// 1))^2, theta_d = (pi/2) id / (nd - 1), phi_d = (pi/2) ip / (np - 1)). FLOAT channels R, G, B
// hold f_r in 1/sr; sigma.R, sigma.G, sigma.B (optional) its one-standard-deviation
// uncertainty. Attributes: zbrdf.format "zbrdf-tabulated-v1", zbrdf.grid ("nh nd np"),
// zbrdf.model (the coordinates and the interpolation, as text), zbrdf.info (JSON: fit report,
// provenance). docs/formats.md is the reader's guide.
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "brdf/tabulated_brdf.h"

namespace zbrdf {

// Throws InputError naming the file if it cannot be written.
void WriteTabulatedFile(const std::string& path, const TabulatedBrdf& brdf,
                        const nlohmann::json& info);

// Throws InputError naming the file and what is wrong (not OpenEXR, not a tabulated file, a
// missing attribute or channel, sizes that disagree with the grid, negative or non-finite
// values). spec: what the BRDF's Spec() returns (default "file:" + path).
std::unique_ptr<TabulatedBrdf> ReadTabulatedFile(const std::string& path,
                                                 const std::string& spec = "");

// The zbrdf.info attribute (an empty object if absent). Throws like ReadTabulatedFile.
nlohmann::json ReadTabulatedFileInfo(const std::string& path);

}  // namespace zbrdf
