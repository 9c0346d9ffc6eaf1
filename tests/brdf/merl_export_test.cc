// MERL export (brdf/merl_export.h), read back by the independent implementation of MERL's
// reference lookup in tests/brdf/merl_reader.h. The export command's handling of invalid values
// and delta materials is tested in tests/tools/brdf_export_test.cc.
#include "brdf/merl_export.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "brdf/material_spec.h"
#include "tests/brdf/merl_reader.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::BinCentre;
using testing::Lookup;
using testing::MerlFile;
using testing::ReadRaw;
using testing::TempDir;

void ExpectMatchesAtBinCentres(const std::string& spec, int stride) {
  TempDir dir("merl_" + std::to_string(std::hash<std::string>()(spec)));
  const std::shared_ptr<const Brdf> brdf = MakeBrdf(spec);
  ValueCheck check;
  const MerlTable table = SampleMerlTable(*brdf, &check);
  check.Finish("merl export of " + spec);
  WriteMerlBinary(dir.File("table.binary"), table);
  const MerlFile file = ReadRaw(dir.File("table.binary"));
  ASSERT_EQ(file.dims[0], 90);
  ASSERT_EQ(file.dims[1], 90);
  ASSERT_EQ(file.dims[2], 180);
  ASSERT_EQ(file.values.size(), 3u * 90 * 90 * 180);
  int checked = 0, nonzero = 0;
  double worst = 0;
  for (int i = 0; i < 90; ++i) {
    for (int j = 0; j < 90; ++j) {
      for (int k = (i + j) % stride; k < 180; k += stride) {
        Vec3 in, out;
        BinCentre(i, j, k, &in, &out);
        int bin = -1;
        const Rgb stored = Lookup(file, in, out, &bin);
        // The independent lookup must find the bin whose centre this is.
        ASSERT_EQ(bin, k + j * 180 + i * 180 * 90) << i << " " << j << " " << k;
        const Rgb expected = (in.z > 0 && out.z > 0) ? brdf->Eval(in, out) : Rgb();
        for (int c = 0; c < 3; ++c) {
          // Stored as f / scale in float64 and multiplied back: a few ulps.
          const double error = std::abs(stored[c] - expected[c]);
          worst = std::max(worst, expected[c] > 0 ? error / expected[c] : error);
          ASSERT_LE(error, 1e-6 * std::abs(expected[c]))
              << spec << " bin " << i << " " << j << " " << k;
        }
        ++checked;
        nonzero += expected.Max() > 0;
      }
    }
  }
  EXPECT_GT(nonzero, checked / 3) << "the test must look at bins above the horizon";
  ::testing::Test::RecordProperty("worst_relative_error", std::to_string(worst));
}

TEST(MerlExport, GgxMatchesAtEveryBinCentre) {
  ExpectMatchesAtBinCentres("ggx:alpha=0.25,F0=0.9,0.6,0.3,kd=0.05,0.1,0.2", 1);
}

TEST(MerlExport, BlinnPhongMatchesAtBinCentres) {
  ExpectMatchesAtBinCentres("blinn-phong:kd=0.2,0.3,0.4,ks=0.5,n=80", 7);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
