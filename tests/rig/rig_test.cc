#include "rig/rig.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "basis/error.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

std::string ErrorOf(const std::string& yaml) {
  try {
    ParseRig(yaml, "test.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string ThesisText() {
  return WriteRigYaml(LoadRig(testing::SourceRig("thesis.yaml")));
}

TEST(RigTest, ShippedRigsLoadWithTheirStatedGeometry) {
  const Rig thesis = LoadRig(testing::SourceRig("thesis.yaml"));
  EXPECT_EQ(thesis.name, "thesis");
  // Camera 27 cm above the parabola vertex, vertex 13.5 cm above the sample (docs/design.md 1).
  EXPECT_DOUBLE_EQ(thesis.parabola.vertex_height_mm, 135);
  EXPECT_DOUBLE_EQ(thesis.camera.position_mm.z - thesis.parabola.vertex_height_mm, 270);
  EXPECT_EQ(thesis.camera.width, 1360);
  EXPECT_EQ(thesis.camera.height, 1024);
  EXPECT_EQ(thesis.sensor.bit_depth, 12);
  EXPECT_DOUBLE_EQ(thesis.timing.frame_rate_hz, 15);
  EXPECT_EQ(thesis.projector.lens.width, 800);
  EXPECT_EQ(thesis.projector.lens.height, 600);
  const Rig full = LoadRig(testing::SourceRig("full-dome.yaml"));
  EXPECT_EQ(full.dome.lower_edge_height_mm, 0);
  EXPECT_GT(thesis.dome.lower_edge_height_mm, 0);
}

// `--rig thesis` anywhere, an installed zbrdf included: a bare name is the bundled rig file.
TEST(RigTest, ABareNameLoadsTheBundledRigAndAMistypedOneGetsTheClosest) {
  const Rig by_name = LoadRig("thesis");
  EXPECT_EQ(WriteRigYaml(by_name), ThesisText());
  EXPECT_EQ(std::filesystem::path(by_name.source_path).filename(), "thesis.yaml");
  std::string message;
  try {
    LoadRig("thesys");
  } catch (const InputError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("rig 'thesys' is neither a file nor a bundled rig; did you mean "
                         "'thesis'? Give the path of a rig YAML or the name of a bundled rig "
                         "(full-dome, thesis, in "),
            std::string::npos)
      << message;
  EXPECT_THROW(LoadRig("no/such/rig.yaml"), InputError);
}

TEST(RigTest, CanonicalYamlRoundTrips) {
  const Rig rig = LoadRig(testing::SourceRig("thesis.yaml"));
  const std::string text = WriteRigYaml(rig);
  EXPECT_EQ(WriteRigYaml(ParseRig(text, "round trip")), text);
  EXPECT_EQ(RigHash(ParseRig(text, "round trip")), RigHash(rig));
  Rig moved = rig;
  moved.misalignment.camera_offset_mm.x = 0.1;
  EXPECT_NE(RigHash(moved), RigHash(rig));
}

TEST(RigTest, ErrorsNameTheFieldAndTheValue) {
  std::string text = ThesisText();
  const auto replace = [](std::string s, const std::string& from, const std::string& to) {
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  const std::string bad_pitch = ErrorOf(replace(text, "pixel_pitch_um: 6.45", "pixel_pitch_um: -3.45"));
  EXPECT_NE(bad_pitch.find("rig file test.yaml: camera.pixel_pitch_um must be > 0 (got -3.45)"),
            std::string::npos)
      << bad_pitch;
  const std::string typo = ErrorOf(replace(text, "focal_length_mm: 4.5", "focal_lenght_mm: 4.5"));
  EXPECT_NE(typo.find("parabola.focal_lenght_mm is not a known field"), std::string::npos) << typo;
  EXPECT_NE(typo.find("parabola.focal_length_mm is missing"), std::string::npos) << typo;
  const std::string word = ErrorOf(replace(text, "f_number: 8", "f_number: eight"));
  EXPECT_NE(word.find("camera.f_number must be a number (got 'eight')"), std::string::npos) << word;
  const std::string layout = ErrorOf(replace(text, "layout: bayer-rggb", "layout: bayer-xyz"));
  EXPECT_NE(layout.find("sensor.layout"), std::string::npos) << layout;
  const std::string below = ErrorOf(replace(text, "rim_radius_mm: 18.5", "rim_radius_mm: 60"));
  EXPECT_NE(below.find("reaches below the sample plane"), std::string::npos) << below;
  EXPECT_NE(ErrorOf("not: [valid").find("not valid YAML"), std::string::npos);
  EXPECT_NE(ErrorOf("- a list").find("must be a YAML map"), std::string::npos);
  // Several problems are reported together.
  const std::string two =
      ErrorOf(replace(replace(text, "f_number: 8", "f_number: 0"), "bit_depth: 12", "bit_depth: 3"));
  EXPECT_NE(two.find("camera.f_number"), std::string::npos) << two;
  EXPECT_NE(two.find("sensor.bit_depth"), std::string::npos) << two;
  EXPECT_THROW(LoadRig("/no/such/rig.yaml"), InputError);
}

// Found by fuzz/rig_fuzz and fuzz/rig_overlay_fuzz: a list or map used as a key ("? [a, b]",
// "{[1, 2]: 3}") made yaml-cpp's conversion to a field name throw YAML::BadConversion, which
// escaped the readers instead of an InputError.
TEST(RigTest, KeysThatAreNotNamesAreInputErrors) {
  std::string text = ThesisText();
  const std::string top = ErrorOf(text + "? [a, b]\n: 1\n");
  EXPECT_NE(top.find("the top level has a key that is a list or map"), std::string::npos) << top;
  const size_t parabola = text.find("parabola:\n");
  ASSERT_NE(parabola, std::string::npos);
  const std::string nested =
      ErrorOf(text.insert(parabola + 10, "  {x: 1}: 2\n"));
  EXPECT_NE(nested.find("parabola has a key that is a list or map"), std::string::npos) << nested;

  const Rig thesis = LoadRig(testing::SourceRig("thesis.yaml"));
  EXPECT_THROW(ApplyRigOverlayText(thesis, "{[1, 2]: 3}", "faults.yaml"), InputError);
  EXPECT_THROW(ApplyRigOverlayText(thesis, "camera:\n  [x]: 1\n", "faults.yaml"), InputError);
}

// Found by fuzz/rig_overlay_fuzz: camera.resolution [688888888888888880, 512] was converted to
// int before its range was checked (undefined behaviour; UBSan's float-cast-overflow). Integer
// fields had the same conversion after a failed range check.
TEST(RigTest, NumbersBeyondIntAreInputErrorsNotConversions) {
  const std::string text = ThesisText();
  const auto replace = [](std::string s, const std::string& from, const std::string& to) {
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  const std::string resolution =
      ErrorOf(replace(text, "resolution: [1360, 1024]", "resolution: [688888888888888880, 1024]"));
  EXPECT_NE(resolution.find("camera.resolution must be two integers in [8, 20000]"),
            std::string::npos)
      << resolution;
  const std::string steps = ErrorOf(replace(text, "design_steps: 20000", "design_steps: 1e30"));
  EXPECT_NE(steps.find("dome.design_steps must be an integer"), std::string::npos) << steps;

  const Rig thesis = LoadRig(testing::SourceRig("thesis.yaml"));
  EXPECT_THROW(ApplyRigOverlayText(thesis, "camera: {resolution: [688888888888888880, 512]}",
                                   "faults.yaml"),
               InputError);
}

TEST(RigTest, FastPresetKeepsTheOpticsAndTheFieldOfView) {
  const Rig rig = LoadRig(testing::SourceRig("thesis.yaml"));
  const Rig fast = ApplyPreset(rig, Preset::kFast);
  EXPECT_EQ(fast.camera.width, rig.camera.width / 4);
  EXPECT_DOUBLE_EQ(fast.camera.width * fast.camera.pixel_pitch_um,
                   rig.camera.width * rig.camera.pixel_pitch_um);
  EXPECT_EQ(fast.projector.lens.height, rig.projector.lens.height / 4);
  EXPECT_EQ(fast.simulation.samples_per_pixel, 2 * rig.simulation.samples_per_pixel);
  EXPECT_EQ(WriteRigYaml(ApplyPreset(rig, Preset::kFull)), WriteRigYaml(rig));
  EXPECT_THROW(ParsePreset("medium"), InputError);
}

TEST(RigTest, ProjectorResponseAndFlatField) {
  ProjectorParams p;
  p.lens.width = 100;
  p.lens.height = 50;
  p.gamma = 2.2;
  EXPECT_NEAR(p.Response(0.5), std::pow(0.5, 2.2), 1e-15);
  p.response_table = {0, 0.25, 1};  // piecewise linear through (0.5, 0.25)
  EXPECT_NEAR(p.Response(0.75), 0.625, 1e-15);
  p.flat_field_falloff = 0.3;
  EXPECT_NEAR(p.FlatField(50, 25), 1.0, 1e-15);
  EXPECT_NEAR(p.FlatField(0, 0), 0.7, 1e-15);  // the corner loses the falloff
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
