// Flags shared by the commands that render material balls (preview, compare, report).
#pragma once

#include <memory>
#include <string>

#include "tools/cli/command.h"
#include "pictures/environment.h"
#include "pictures/material_ball.h"

namespace zbrdf::cli {

// --light, --environment (alias --envmap), --envmap-rotate, --spp, --size, --camera, --sampling, --exposure, --seed,
// with the given defaults for --spp and --size.
void AddPreviewFlags(CommandLine& cl, int default_spp, int default_size);

struct PreviewSetup {
  BallOptions ball;
  std::unique_ptr<Environment> environment;  // null in directional-light mode
  std::string lighting;                      // "dir:45,30", "sky", "studio", "environment FILE"
  double exposure_ev = 0;
};
// Reads the flags; loads the environment map (or builds the sky). Throws InputError for bad
// values, naming the flag.
PreviewSetup ReadPreviewFlags(const CommandLine& cl);

// "sky", "studio" or an .exr / .hdr file (warning on stderr about negative pixels set to 0).
Environment LoadEnvironment(const std::string& name);

// "dir:THETA,PHI" (degrees: theta from the view axis, phi from +x toward +y) -> world direction
// toward the light.
Vec3 ParseLightDirection(const std::string& text);

}  // namespace zbrdf::cli
