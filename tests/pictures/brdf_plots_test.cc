// Polar slices and band energy.
#include "pictures/brdf_plots.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "acquisition/zonal.h"
#include "basis/spherical_harmonics.h"
#include "brdf/material_spec.h"
#include "tests/acquisition/session_fixture.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(Plots, BandEnergySumsTheSquaredCoefficientsByDegree) {
  const ZonalData data = testing::MakeZonalData();
  const BandEnergy e = ZonalBandEnergy(data);
  ASSERT_EQ(e.by_l_in.size(), 3u);
  for (int c = 0; c < 3; ++c) {
    double total_in = 0, total_out = 0;
    for (int l = 0; l <= 2; ++l) {
      double expected = 0;
      for (int m = -l; m <= l; ++m) {
        for (int j = 0; j < 9; ++j)
          expected += std::pow((c + 1.0) / (1 + ShIndex(l, m) + 2.0 * j), 2);
      }
      EXPECT_NEAR(e.by_l_in[l][c], expected, 1e-12 * expected);
      total_in += e.by_l_in[l][c];
      total_out += e.by_l_out[l][c];
    }
    // Both groupings partition the same coefficients (Parseval: the total is the squared norm).
    EXPECT_NEAR(total_in, data.tensor[c].squaredNorm(), 1e-12 * total_in);
    EXPECT_NEAR(total_out, total_in, 1e-12 * total_in);
  }
  const cv::Mat chart = DrawBandEnergy({e}, "test");
  EXPECT_GT(chart.rows, 200);
  EXPECT_EQ(chart.type(), CV_8UC3);
}

TEST(Plots, SlicesLieInThePlaneOfIncidence) {
  // Blinn-Phong peaks where h = n, i.e. exactly at the mirror direction theta_o = -theta_i.
  const auto brdf = MakeBrdf("blinn-phong:kd=0.1,ks=0.5,n=300");
  const auto slices = IncidencePlaneSlices(*brdf, {30}, 181);
  ASSERT_EQ(slices.size(), 1u);
  size_t peak = 0;
  for (size_t k = 0; k < slices[0].f.size(); ++k) {
    if (slices[0].f[k].g > slices[0].f[peak].g) peak = k;
  }
  EXPECT_NEAR(slices[0].theta_o_deg[peak], -30.0, 0.5);  // the samples are 1 deg apart
  // Sample 90 of 181 is the normal direction.
  EXPECT_EQ(slices[0].theta_o_deg[90], 0.0);
  EXPECT_EQ(slices[0].f[90].g, brdf->Eval(SphericalDirection(M_PI / 6, 0), {0, 0, 1}).g);
  const cv::Mat image = DrawIncidenceSlices(slices, "blinn-phong", true);
  EXPECT_EQ(image.type(), CV_8UC3);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
