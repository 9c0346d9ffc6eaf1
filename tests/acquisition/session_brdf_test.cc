#include "acquisition/session_brdf.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "basis/error.h"
#include "brdf/dbrdf.h"
#include "brdf/material_spec.h"
#include "brdf/sh_brdf.h"
#include "tests/acquisition/session_fixture.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::TempDir;

std::string MessageOf(const std::string& dir) {
  try {
    ReadSessionBrdf(dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SessionBrdf, ShConversionsComeInNameOrderAfterShExr) {
  TempDir dir("session_brdf_sh");
  WriteShFile(dir.File("sh-sh.exr"), testing::MakeShData(0.5));
  WriteShFile(dir.File("sh-hsh.exr"), testing::MakeShData(0.25));
  WriteShFile(dir.File("sh.exr"), testing::MakeShData(0.125));
  testing::WriteFile(dir.File("sh-notes.txt"), "not an SH file");
  const std::vector<std::string> expected = {dir.File("sh.exr"), dir.File("sh-hsh.exr"),
                                             dir.File("sh-sh.exr")};
  EXPECT_EQ(SessionShFiles(dir.path()), expected);
  EXPECT_EQ(SessionBrdfFiles(dir.path()), expected);
  const BrdfFile file = ReadSessionBrdf(dir.path());
  EXPECT_EQ(file.path, dir.File("sh.exr"));
  EXPECT_EQ(file.kind, "sh-file");
  EXPECT_NE(dynamic_cast<const ShBrdf*>(file.brdf.get()), nullptr);
}

TEST(SessionBrdf, AFitWithoutAModelIsSkippedAndNamedWhenNothingElseIsThere) {
  TempDir dir("session_brdf_fits");
  testing::WriteJson(dir.File("fit-ggx.json"), {{"fitted", false}, {"spec", "ggx:alpha=0.2"}});
  const std::string message = MessageOf(dir.path());
  EXPECT_NE(message.find("no fitted model"), std::string::npos) << message;
  EXPECT_NE(message.find("fit-ggx.json"), std::string::npos) << message;
  // The D-BRDF fit wins over analytic fits, whatever their names.
  testing::WriteJson(dir.File("fit-as.json"), {{"spec", "as:rs=0.1,nu=10,nv=10"}});
  EXPECT_EQ(ReadSessionBrdf(dir.path()).brdf->Spec(), MakeBrdf("as:rs=0.1,nu=10,nv=10")->Spec());
  WriteDBrdfFile(dir.File("fit-dbrdf.exr"), testing::MakeDBrdf(), {});
  const BrdfFile file = ReadSessionBrdf(dir.path());
  EXPECT_EQ(file.kind, "dbrdf-file");
  EXPECT_NE(dynamic_cast<const DBrdf*>(file.brdf.get()), nullptr);
}

TEST(SessionBrdf, AnEmptySessionNamesTheCommandsAndItsTrueMaterial) {
  TempDir dir("session_brdf_empty");
  testing::WriteSessionJson(dir.path(), "ggx:alpha=0.3");
  const std::string message = MessageOf(dir.path());
  EXPECT_NE(message.find("zbrdf convert"), std::string::npos) << message;
  EXPECT_NE(message.find("ggx:alpha=0.3"), std::string::npos) << message;
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
