#include "tools/cli/preview_flags.h"

#include <cmath>
#include <cstdio>

#include "basis/error.h"

namespace zbrdf::cli {

void AddPreviewFlags(CommandLine& cl, int default_spp, int default_size) {
  cl.Option("light", "dir:THETA,PHI",
            "a directional light instead of an environment: THETA from the view axis, PHI from "
            "the image's right toward its top, degrees")
      .Option("environment", "E",
              "the light: an equirectangular HDR map (.exr or .hdr), or the built-in sky or "
              "studio (default: sky; docs/preview.md)")
      .Option("envmap", "E", "the same as --environment (its earlier name)")
      .Option("envmap-rotate", "DEG", "turn the environment about the vertical axis", "0")
      .Option("spp", "N", "samples per pixel", std::to_string(default_spp))
      .Option("size", "N", "image width and height in pixels", std::to_string(default_size))
      .Option("camera", "C", "ortho or pinhole", "ortho")
      .Option("sampling", "S",
              "mis (BRDF + environment), brdf, cosine or light: the strategies of the thesis's "
              "figure 3.11",
              "mis")
      .Option("exposure", "EV", "exposure of the PNG in stops", "0")
      .Option("seed", "N", "seed of the pixel samples", "1");
}

Vec3 ParseLightDirection(const std::string& text) {
  if (text.rfind("dir:", 0) != 0) {
    throw InputError("--light must be dir:THETA,PHI in degrees, e.g. dir:45,30 (got '" + text +
                     "')");
  }
  double theta = 0, phi = 0;
  char extra = 0;
  if (std::sscanf(text.c_str() + 4, "%lf,%lf%c", &theta, &phi, &extra) != 2 ||
      !std::isfinite(theta) || !std::isfinite(phi) || theta < 0 || theta > 180) {
    throw InputError("--light must be dir:THETA,PHI with THETA in [0, 180] degrees (got '" + text +
                     "')");
  }
  const double t = theta * M_PI / 180, p = phi * M_PI / 180;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

Environment LoadEnvironment(const std::string& name) {
  if (name == "sky") return Environment::Sky();
  if (name == "studio") return Environment::Studio();
  int negatives = 0;
  Environment env = Environment::FromFile(name, 0.0, &negatives);
  if (negatives > 0) {
    std::fprintf(stderr, "zbrdf: warning: environment %s: %d pixels had negative values, set to 0\n",
                 name.c_str(), negatives);
  }
  return env;
}

PreviewSetup ReadPreviewFlags(const CommandLine& cl) {
  PreviewSetup setup;
  setup.ball.spp = cl.GetInt("spp", 1, 1 << 20);
  setup.ball.size = cl.GetInt("size", 8, 8192);
  setup.ball.seed = static_cast<uint64_t>(cl.GetInt("seed", 0, 1 << 30));
  setup.exposure_ev = cl.GetDouble("exposure", -20, 20);
  const std::string camera = cl.Get("camera");
  if (camera == "ortho") {
    setup.ball.camera = BallOptions::Camera::kOrthographic;
  } else if (camera == "pinhole") {
    setup.ball.camera = BallOptions::Camera::kPinhole;
  } else {
    throw InputError("--camera must be ortho or pinhole (got '" + camera + "')");
  }
  const std::string sampling = cl.Get("sampling");
  if (sampling == "mis") {
    setup.ball.sampling = BallOptions::Sampling::kMis;
  } else if (sampling == "brdf") {
    setup.ball.sampling = BallOptions::Sampling::kBrdf;
  } else if (sampling == "cosine") {
    setup.ball.sampling = BallOptions::Sampling::kCosine;
  } else if (sampling == "light") {
    setup.ball.sampling = BallOptions::Sampling::kLight;
  } else {
    throw InputError("--sampling must be mis, brdf, cosine or light (got '" + sampling + "')");
  }
  if (cl.Has("environment") && cl.Has("envmap")) {
    throw InputError("--environment and --envmap are the same flag; give one");
  }
  const std::string environment = cl.Has("environment") ? cl.Get("environment")
                                  : cl.Has("envmap")    ? cl.Get("envmap")
                                                        : "";
  if (cl.Has("light")) {
    if (!environment.empty()) {
      throw InputError(
          "--light and --environment exclude each other: a preview has one kind of light");
    }
    setup.ball.light_direction = ParseLightDirection(cl.Get("light"));
    setup.lighting = cl.Get("light");
    return setup;
  }
  const double rotation = cl.GetDouble("envmap-rotate", -360, 360) * M_PI / 180;
  setup.environment = std::make_unique<Environment>(
      LoadEnvironment(environment.empty() ? "sky" : environment).Rotated(rotation));
  setup.lighting = environment.empty() || environment == "sky" ? "sky"
                   : environment == "studio"                   ? "studio"
                                                               : "environment " + environment;
  return setup;
}

}  // namespace zbrdf::cli
