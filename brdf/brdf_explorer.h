// Disney BRDF Explorer ".brdf" files: an analytic BRDF as a GLSL function with its parameters
// (the "analytic" file type of github.com/wdas/brdf; docs/formats.md):
//
//   analytic
//   # comments
//   ::begin parameters
//   float NAME MIN MAX DEFAULT      color NAME R G B      bool NAME DEFAULT
//   ::end parameters
//   ::begin shader
//   vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y ) { ... }   // f_r, no cosine
//   ::end shader
//
// L points toward the light, V toward the viewer, N is the normal and X, Y the tangents of the
// sample frame, so the shader evaluates exactly our f_r(w_i = L, w_o = V) in the local frame
// (X, Y, N). Written for lambert, blinn-phong, ward, as (Ashikhmin-Shirley), ggx, dbrdf (p(h)
// embedded as a const float array indexed like HalfVectorTable::Eval) and the measured networks
// (the 6-21-21-3 MLP's weights as const arrays). MERL tables need no conversion: BRDF Explorer
// opens .binary files directly (zbrdf export --format merl).
//
// A "# zbrdf-model: NAME" comment names the shader template, so that ReadBrdfExplorerFile can
// rebuild the model from the parameter defaults and the arrays (numbers are written with 9
// significant digits, float precision, which is what the GPU evaluates).
#pragma once

#include <memory>
#include <string>

#include "brdf/brdf.h"

namespace zbrdf {

// The file's text. Throws InputError for a model the format cannot express, naming the
// formats that can hold it.
std::string BrdfExplorerSource(const Brdf& brdf);
void WriteBrdfExplorerFile(const std::string& path, const Brdf& brdf);

// Rebuilds the model of a file written by WriteBrdfExplorerFile. Throws InputError naming the
// file and what is missing or malformed; files from other sources (no zbrdf-model line) are
// rejected with a message saying so.
std::unique_ptr<Brdf> ReadBrdfExplorerFile(const std::string& path);

}  // namespace zbrdf
