// Resolution of INPUT: specs, every kind of file, sessions and their preference order.
#include "tools/brdf_input.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "acquisition/session_brdf.h"
#include "basis/error.h"
#include "brdf/brdf_explorer.h"
#include "brdf/dbrdf.h"
#include "brdf/material_spec.h"
#include "brdf/merl_table.h"
#include "brdf/nbrdf.h"
#include "brdf/rgl_bsdf.h"
#include "brdf/sh_brdf.h"
#include "tests/acquisition/session_fixture.h"
#include "tools/brdf_export.h"
#include "tools_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::TempDir;

std::string MessageOf(const std::string& input) {
  try {
    ResolveBrdfInput(input);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(BrdfInput, SpecsResolveToTheirModel) {
  const BrdfInput in = ResolveBrdfInput("ggx:alpha=0.2,F0=0.5");
  EXPECT_EQ(in.kind, "spec");
  EXPECT_EQ(in.brdf->Spec(), MakeBrdf("ggx:alpha=0.2,F0=0.5")->Spec());
  EXPECT_EQ(in.name, "ggx");
  EXPECT_EQ(ResolveBrdfInput("merl:blue-acrylic").name, "blue-acrylic");
}

TEST(BrdfInput, FilesResolveByKind) {
  TempDir dir("input_files");
  const BrdfInput ggx = ResolveBrdfInput("ggx:alpha=0.3,F0=0.8");
  ExportOptions options;
  options.scenes = {};
  options.format = ExportFormat::kMerl;
  options.out = dir.File("t.binary");
  ExportBrdf(ggx, options);
  options.format = ExportFormat::kRgl;
  options.rgl_variant = ExportOptions::RglVariant::kRgb;
  options.out = dir.File("t.bsdf");
  ExportBrdf(ggx, options);
  options.format = ExportFormat::kBrdfExplorer;
  options.out = dir.File("t.brdf");
  ExportBrdf(ggx, options);
  WriteDBrdfFile(dir.File("d.exr"), testing::MakeDBrdf(), {{"test", 1}});
  WriteShFile(dir.File("s.exr"), testing::MakeShData());
  testing::WriteJson(dir.File("fit-ward.json"),
                     {{"model", "ward"}, {"spec", "ward:rho_d=0.1,rho_s=0.1,alpha=0.2"}});

  EXPECT_EQ(ResolveBrdfInput(dir.File("t.binary")).kind, "merl-file");
  EXPECT_NE(dynamic_cast<const MerlBrdf*>(ResolveBrdfInput(dir.File("t.binary")).brdf.get()),
            nullptr);
  EXPECT_NE(dynamic_cast<const RglBrdf*>(ResolveBrdfInput(dir.File("t.bsdf")).brdf.get()), nullptr);
  // A file-backed BRDF's Spec() resolves back to the file.
  const BrdfInput rgl = ResolveBrdfInput(dir.File("t.bsdf"));
  EXPECT_EQ(ResolveBrdfInput(rgl.brdf->Spec()).source, dir.File("t.bsdf"));
  EXPECT_EQ(ResolveBrdfInput(dir.File("t.brdf")).brdf->Spec(), ggx.brdf->Spec());
  EXPECT_NE(dynamic_cast<const DBrdf*>(ResolveBrdfInput(dir.File("d.exr")).brdf.get()), nullptr);
  EXPECT_NE(dynamic_cast<const ShBrdf*>(ResolveBrdfInput(dir.File("s.exr")).brdf.get()), nullptr);
  EXPECT_EQ(ResolveBrdfInput(dir.File("fit-ward.json")).brdf->Spec(),
            MakeBrdf("ward:rho_d=0.1,rho_s=0.1,alpha=0.2")->Spec());
  const std::string network =
      std::string(ZBRDF_SOURCE_DIR) + "/data/materials/merl/red-fabric.json";
  EXPECT_NE(dynamic_cast<const NbrdfBrdf*>(ResolveBrdfInput(network).brdf.get()), nullptr);
  // A zonal file is data, not a BRDF: the message says how to get one.
  WriteZonalExr(dir.File("zonal.exr"), testing::MakeZonalData());
  EXPECT_NE(MessageOf(dir.File("zonal.exr")).find("zbrdf convert"), std::string::npos);
}

TEST(BrdfInput, SessionsPreferDBrdfThenAnalyticFitThenSh) {
  TempDir dir("input_session");
  testing::WriteSessionJson(dir.path(), "merl:blue-acrylic");
  // No fit yet: the message names the files, the commands and the true material.
  const std::string message = MessageOf(dir.path());
  EXPECT_NE(message.find("fit-dbrdf.exr"), std::string::npos) << message;
  EXPECT_NE(message.find("zbrdf fit"), std::string::npos) << message;
  EXPECT_NE(message.find("merl:blue-acrylic"), std::string::npos) << message;

  // zbrdf convert names its output sh-<target>.exr.
  WriteShFile(dir.File("sh-sh.exr"), testing::MakeShData());
  EXPECT_NE(dynamic_cast<const ShBrdf*>(ResolveBrdfInput(dir.path()).brdf.get()), nullptr);
  // Analytic fits: the first by name that holds a model; a fit that failed is skipped, and the
  // D-BRDF fit's report (fit-dbrdf.json) is not a model.
  testing::WriteJson(dir.File("fit-as.json"),
                     {{"fitted", false}, {"spec", "as:rs=0.1,nu=10,nv=10"}});
  testing::WriteJson(dir.File("fit-dbrdf.json"), {{"model", "dbrdf"}, {"fitted", true}});
  testing::WriteJson(dir.File("fit-ggx.json"), {{"spec", "ggx:alpha=0.25,F0=0.1"}});
  testing::WriteJson(dir.File("fit-ward.json"), {{"spec", "ward:rho_d=0.1,rho_s=0.1,alpha=0.2"}});
  BrdfInput in = ResolveBrdfInput(dir.path());
  EXPECT_EQ(in.brdf->Spec(), MakeBrdf("ggx:alpha=0.25,F0=0.1")->Spec());
  EXPECT_EQ(in.kind, "session");
  EXPECT_EQ(in.session_dir, dir.path());
  WriteDBrdfFile(dir.File("fit-dbrdf.exr"), testing::MakeDBrdf(), {});
  in = ResolveBrdfInput(dir.path());
  EXPECT_NE(dynamic_cast<const DBrdf*>(in.brdf.get()), nullptr);
  const std::vector<std::string> files = SessionBrdfFiles(dir.path());
  ASSERT_EQ(files.size(), 5u);
  EXPECT_EQ(files[0], dir.File("fit-dbrdf.exr"));
  EXPECT_EQ(files[1], dir.File("fit-as.json"));
  EXPECT_EQ(files[4], dir.File("sh-sh.exr"));
}

TEST(BrdfInput, UnknownInputsSayWhatWasTried) {
  EXPECT_NE(MessageOf("no/such/file.binary").find("not an existing file or folder"),
            std::string::npos);
  EXPECT_NE(MessageOf("blue-acrylic").find("not an existing file or folder"), std::string::npos);
  // A spec with a bad parameter keeps the spec parser's message.
  EXPECT_NE(MessageOf("ggx:alpha=-1").find("alpha"), std::string::npos);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
