// The material spec: one line of text that names a BRDF, used by every tool, rig file and test.
//
//   lambert:0.18                 lambert:0.5,0.4,0.3            lambert:albedo=0.18
//   blinn-phong:kd=0.1,ks=0.5,n=100
//   ward:rho_d=0.1,rho_s=0.05,alpha_x=0.1,alpha_y=0.3           (alpha= sets both)
//   as:rd=0.3,rs=0.05,nu=100,nv=10                              (Ashikhmin-Shirley)
//   ggx:alpha=0.2,F0=0.04,kd=0.1,0.2,0.5                         (or alpha_x=..,alpha_y=..)
//   dbrdf:c=1,F0=0.04,kd=0,theta_samples=3,phi_samples=1,p=2,1,0.5
//   mirror:R=0.95                mirror:0.9
//   retro:kd=0.1,kr=0.6,n=20     retro-reflective lobe about w_o (brdf/retro.h)
//   merl:blue-acrylic            a bundled measured material (network), see MaterialSpecHelp()
//   file:PATH.binary             a MERL table;   file:PATH.json: a network file
//   target:white  target:graycard  target:mirror   the calibration targets (constants below)
//
// MODEL:PARAMETERS, parameters separated by commas. A token with '=' starts a parameter; a token
// without one extends the previous parameter's value list, so "kd=0.1,0.2,0.5" is one RGB value.
// Colours take one value (gray) or three (RGB). Keys and model names are case-insensitive.
// Parameters with defaults may be left out: blinn-phong kd = 0; ward rho_d = 0; as rd = 0;
// ggx F0 = 0.04, kd = 0; dbrdf c = 1, F0 = 0.04, kd = 0, phi_samples = 1. A dbrdf's p is
// rescaled to integral p(h) cos(theta_h) dw_h = 1 (unless within 1e-12 of it), so its units are
// free and its scale belongs in c.
//
// Every model's Spec() returns a canonical spec (all parameters, shortest exact numbers) that
// MakeBrdf turns back into the same model.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "brdf/brdf.h"

namespace zbrdf {

// The calibration targets: a diffuse white target, an 18% gray card (the reflectance standard
// of the gray-card calibration) and a front-surface aluminium mirror.
inline constexpr double kWhiteTargetAlbedo = 0.95;
inline constexpr double kGrayCardAlbedo = 0.18;
inline constexpr double kTargetMirrorReflectance = 0.92;

// Builds the BRDF a spec names. Throws InputError naming the spec and the bad part, and listing
// what is valid: an unknown model or key, a missing parameter, a value that is not a number or
// is out of range (negative albedo, alpha <= 0, NaN: never clamped), an unknown or unreadable
// material or file.
std::unique_ptr<Brdf> MakeBrdf(const std::string& spec);

// The model names MakeBrdf accepts ("lambert", "blinn-phong", ...), in help order.
std::vector<std::string> MaterialModelNames();
// A short name of a spec for titles and file names: "merl:blue-acrylic" -> "blue-acrylic",
// "file:dir/gold.binary" -> "gold", "ggx:alpha=0.2" -> "ggx" (the model, lower case).
std::string MaterialShortName(const std::string& spec);

// Help text for --help: the syntax of every model with its parameters and defaults, and the
// names of the bundled measured materials.
std::string MaterialSpecHelp();

}  // namespace zbrdf
