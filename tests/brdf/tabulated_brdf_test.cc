#include "brdf/tabulated_brdf.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "basis/error.h"
#include "basis/zone.h"
#include "brdf/ggx.h"
#include "brdf/lambertian.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;

// Right-handed rotations about y and z, written out.
Vec3 RotateY(const Vec3& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x + s * v.z, v.y, -s * v.x + c * v.z};
}
Vec3 RotateZ(const Vec3& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}

// The pair with half-vector angles (theta_h, phi_h) and difference angles (theta_d, phi_d),
// inverting Rusinkiewicz's change of variables (brdf/merl_table.h): d is w_i in the frame where h
// is +z, so w_i = R_z(phi_h) R_y(theta_h) d; w_o is w_i reflected about h, which in that frame is
// d reflected about +z.
void PairOf(double theta_h, double phi_h, double theta_d, double phi_d, Vec3* w_i, Vec3* w_o) {
  const Vec3 d = SphericalDirection(theta_d, phi_d);
  *w_i = RotateZ(RotateY(d, theta_h), phi_h);
  *w_o = RotateZ(RotateY(Vec3{-d.x, -d.y, d.z}, theta_h), phi_h);
}

// phi_d folded by reciprocity (phi_d -> phi_d + pi) and bilateral symmetry (phi_d -> -phi_d)
// into [0, pi/2]: a triangle wave of period pi.
double FoldPhi(double phi) {
  phi = std::fmod(phi, M_PI);
  if (phi < 0) phi += M_PI;
  return std::min(phi, M_PI - phi);
}

Vec3 MirrorY(const Vec3& v) { return {v.x, -v.y, v.z}; }

// min(w_i.z, w_o.z) of the node (theta_h, theta_d, phi_d) with phi_h = 0, in closed form: from
// PairOf, w_i.z = cos th cos td - sin th sin td cos pd and w_o.z = cos th cos td + sin th sin td
// cos pd.
double LowerZ(double th, double td, double pd) {
  return std::cos(th) * std::cos(td) - std::sin(th) * std::sin(td) * std::abs(std::cos(pd));
}

void NodeAngles(const HalfDiffGrid& grid, int index, int* ih, int* id, int* ip) {
  *ip = index % grid.phi_d_nodes();
  *id = (index / grid.phi_d_nodes()) % grid.theta_d_nodes();
  *ih = index / (grid.phi_d_nodes() * grid.theta_d_nodes());
}

std::vector<Rgb> RandomTable(const HalfDiffGrid& grid, uint64_t seed) {
  Rng rng(seed);
  std::vector<Rgb> values(grid.size());
  for (Rgb& v : values) v = Rgb(0.1 + rng.Uniform(), 0.1 + rng.Uniform(), 0.1 + rng.Uniform());
  return values;
}

TEST(HalfDiffOfTest, InvertsExplicitRotations) {
  Rng rng(1);
  for (int k = 0; k < 3000; ++k) {
    const double th = 0.05 + 1.45 * rng.Uniform(), td = 0.05 + 1.45 * rng.Uniform();
    const double pd = 2 * M_PI * rng.Uniform(), ph = 2 * M_PI * rng.Uniform();
    Vec3 w_i, w_o;
    PairOf(th, ph, td, pd, &w_i, &w_o);
    // acos and atan2 amplify the ~1e-16 rounding of the rotated components by 1 / sin(theta) <=
    // 20 for angles >= 0.05 rad: 1e-13 leaves a factor of 50.
    const HalfDiffAngles a = HalfDiffOf(w_i, w_o);
    EXPECT_NEAR(a.theta_h, th, 1e-13);
    EXPECT_NEAR(a.theta_d, td, 1e-13);
    EXPECT_NEAR(a.phi_d, FoldPhi(pd), 1e-13) << pd;
    // Swapping the directions (phi_d + pi) or mirroring y (phi_d -> -phi_d) folds to the same
    // coordinates.
    for (const HalfDiffAngles& b : {HalfDiffOf(w_o, w_i), HalfDiffOf(MirrorY(w_i), MirrorY(w_o)),
                                    HalfDiffOf(MirrorY(w_o), MirrorY(w_i))}) {
      EXPECT_NEAR(b.theta_h, th, 1e-13);
      EXPECT_NEAR(b.theta_d, td, 1e-13);
      EXPECT_NEAR(b.phi_d, FoldPhi(pd), 1e-13);
    }
  }
}

TEST(HalfDiffOfTest, DegeneratePairs) {
  // h = +z (phi_h undefined; taken as 0, so phi_d is w_i's azimuth, folded).
  const Vec3 w_i = SphericalDirection(0.7, 2.0);
  const HalfDiffAngles normal = HalfDiffOf(w_i, Vec3{-w_i.x, -w_i.y, w_i.z});
  EXPECT_EQ(normal.theta_h, 0.0);
  EXPECT_NEAR(normal.theta_d, 0.7, 1e-15);
  EXPECT_NEAR(normal.phi_d, FoldPhi(2.0), 1e-15);
  // w_i = w_o: theta_d = 0, theta_h = theta. acos near 1 resolves angles to ~sqrt(2 eps) = 2e-8.
  const HalfDiffAngles retro = HalfDiffOf(w_i, w_i);
  EXPECT_NEAR(retro.theta_h, 0.7, 1e-15);
  EXPECT_NEAR(retro.theta_d, 0.0, 3e-8);
  // Opposite directions have no half vector: all zero, nothing undefined.
  const HalfDiffAngles opposite = HalfDiffOf(w_i, -w_i);
  EXPECT_EQ(opposite.theta_h, 0.0);
  EXPECT_EQ(opposite.theta_d, 0.0);
  EXPECT_EQ(opposite.phi_d, 0.0);
}

TEST(HalfDiffGridTest, NodesFollowTheStatedAxesAndDirections) {
  const HalfDiffGrid defaults;
  EXPECT_EQ(defaults.ToString(), "32 x 32 x 16");
  EXPECT_EQ(defaults.size(), 32 * 32 * 16);
  // "the second node is at 0.09 deg for 32 nodes": (pi/2) (1/31)^2 rad.
  EXPECT_NEAR(RadToDeg(defaults.ThetaHalf(1)), 90.0 / 961.0, 1e-13);
  const HalfDiffGrid grid(9, 7, 5);
  for (int index = 0; index < grid.size(); ++index) {
    int ih, id, ip;
    NodeAngles(grid, index, &ih, &id, &ip);
    ASSERT_EQ(grid.Index(ih, id, ip), index);
    const double u = ih / 8.0;
    const double th = 0.5 * M_PI * u * u, td = 0.5 * M_PI * id / 6.0, pd = 0.5 * M_PI * ip / 4.0;
    EXPECT_NEAR(grid.ThetaHalf(ih), th, 1e-15);
    EXPECT_NEAR(grid.ThetaDiff(id), td, 1e-15);
    EXPECT_NEAR(grid.PhiDiff(ip), pd, 1e-15);
    Vec3 w_i, w_o, e_i, e_o;
    grid.Directions(index, &w_i, &w_o);
    PairOf(th, 0.0, td, pd, &e_i, &e_o);
    // Two roundings of sines and cosines apart.
    EXPECT_NEAR(Length(w_i - e_i), 0.0, 1e-15) << index;
    EXPECT_NEAR(Length(w_o - e_o), 0.0, 1e-15) << index;
    // The horizon test against the closed form. Nodes exactly on the horizon (in integers:
    // theta_h + theta_d = pi/2 at phi_d = 0; theta_h or theta_d = pi/2 with the other 0 or phi_d
    // = pi/2), where floating point gives z = +-1e-17, are not strictly above it.
    const bool on_horizon = (ip == 0 && ih * ih * 6 + id * 64 == 64 * 6) ||
                            (ih == 8 && (id == 0 || ip == 4)) || (id == 6 && (ih == 0 || ip == 4));
    const double lower = LowerZ(th, td, pd);
    if (on_horizon) {
      EXPECT_FALSE(grid.NodeAboveHorizon(index)) << index;
    } else {
      ASSERT_GT(std::abs(lower), 1e-3) << index;  // the others are far from it
      EXPECT_EQ(grid.NodeAboveHorizon(index), lower > 0) << index;
    }
  }
}

TEST(HalfDiffGridTest, RejectsNodeCountsOutsideTheRange) {
  EXPECT_THROW(HalfDiffGrid(1, 8, 8), InputError);
  EXPECT_THROW(HalfDiffGrid(8, 513, 8), InputError);
  EXPECT_THROW(HalfDiffGrid(8, 8, 0), InputError);
  EXPECT_NO_THROW(HalfDiffGrid(2, 512, 2));
}

TEST(HalfDiffGridTest, StencilIsTrilinearInTheStatedCoordinates) {
  // A function multilinear in (u = sqrt(theta_h / (pi/2)), theta_d, phi_d) is its own trilinear
  // interpolant, so blending its node values must give it back anywhere.
  const HalfDiffGrid grid(11, 9, 6);
  const auto trilinear = [](double u, double td, double pd) {
    return 0.3 + 0.7 * u - 0.2 * td + 0.4 * pd + 0.5 * u * td - 0.3 * td * pd + 0.2 * u * pd +
           0.9 * u * td * pd;
  };
  std::vector<double> table(grid.size());
  for (int index = 0; index < grid.size(); ++index) {
    int ih, id, ip;
    NodeAngles(grid, index, &ih, &id, &ip);
    table[index] = trilinear(ih / 10.0, grid.ThetaDiff(id), grid.PhiDiff(ip));
  }
  Rng rng(2);
  for (int k = 0; k < 2000; ++k) {
    const double u = rng.Uniform(), td = 0.5 * M_PI * rng.Uniform(),
                 pd = 0.5 * M_PI * rng.Uniform();
    const HalfDiffGrid::Stencil s = grid.StencilOf({0.5 * M_PI * u * u, td, pd});
    double sum = 0, blend = 0;
    for (int n = 0; n < 8; ++n) {
      ASSERT_GE(s.index[n], 0);
      ASSERT_LT(s.index[n], grid.size());
      EXPECT_GE(s.weight[n], 0.0);
      sum += s.weight[n];
      blend += s.weight[n] * table[s.index[n]];
    }
    // Eight products of numbers in [0, 1]: a few ulps.
    EXPECT_NEAR(sum, 1.0, 4e-15);
    // The u coordinate passes through sqrt(u^2): relative 1e-16 times n; values are O(1).
    EXPECT_NEAR(blend, trilinear(u, td, pd), 1e-13);
  }
  // At the nodes the blend is the node's value (of any table).
  const std::vector<Rgb> values = RandomTable(grid, 3);
  for (int index = 0; index < grid.size(); ++index) {
    int ih, id, ip;
    NodeAngles(grid, index, &ih, &id, &ip);
    const HalfDiffGrid::Stencil s =
        grid.StencilOf({grid.ThetaHalf(ih), grid.ThetaDiff(id), grid.PhiDiff(ip)});
    double blend = 0;
    for (int n = 0; n < 8; ++n) blend += s.weight[n] * values[s.index[n]].g;
    EXPECT_NEAR(blend, values[index].g, 1e-13) << index;
  }
}

TEST(TabulatedBrdfTest, EvalIsReciprocalBitForBit) {
  const HalfDiffGrid grid(16, 16, 8);
  const TabulatedBrdf brdf(grid, RandomTable(grid, 4), {}, "test");
  EXPECT_TRUE(brdf.IsReciprocal());
  EXPECT_FALSE(brdf.IsEnergyConserving());
  EXPECT_EQ(brdf.Spec(), "test");
  Rng rng(5);
  for (int k = 0; k < 5000; ++k) {
    const Vec3 a = testing::RandomUpperDirection(rng), b = testing::RandomUpperDirection(rng);
    const Rgb fab = brdf.Eval(a, b), fba = brdf.Eval(b, a);
    ASSERT_EQ(fab, fba) << k;
    // The table is bilaterally symmetric by construction too.
    ASSERT_EQ(brdf.Eval(MirrorY(a), MirrorY(b)), fab) << k;
  }
}

TEST(TabulatedBrdfTest, ConstantTablesEvaluateExactly) {
  const HalfDiffGrid grid(12, 10, 6);
  const Rgb c(0.2, 0.3, 0.4);
  const TabulatedBrdf constant(grid, std::vector<Rgb>(grid.size(), c), {}, "constant");
  Rng rng(6);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 a = testing::RandomUpperDirection(rng), b = testing::RandomUpperDirection(rng);
    const Rgb f = constant.Eval(a, b);
    // Weights summing to 1 up to a few ulps.
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(f[ch], c[ch], 2e-15 * c[ch]);
  }
  // A Lambertian tabulates to its value at every node, below the horizon included (the fill),
  // so its table is exact up to grazing pairs: theta_h up to 89.5 deg at theta_d = 0 lies in
  // the last theta_h cell, whose far nodes (theta_h = pi/2) all lie on or below the horizon and
  // hold the previous row's values.
  const LambertianBrdf lambert(Rgb(0.5, 0.25, 0.8));
  const std::vector<Rgb> table = TabulateBrdf(lambert, grid);
  for (int n = 0; n < grid.size(); ++n) ASSERT_EQ(table[n], lambert.albedo() / M_PI) << n;
  const TabulatedBrdf tabulated(grid, table, {}, "lambert table");
  for (const double theta_deg : {10.0, 60.0, 85.0, 89.5}) {
    const Vec3 w = SphericalDirection(DegToRad(theta_deg), 0.3);
    const Vec3 w2 = SphericalDirection(DegToRad(theta_deg), 0.35);
    for (const auto& [a, b] : {std::pair{w, w}, std::pair{w, w2}}) {
      const Rgb f = tabulated.Eval(a, b);
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_NEAR(f[ch], lambert.albedo()[ch] / M_PI, 1e-15) << theta_deg;
      }
    }
  }
}

// The model at node coordinates (u, theta_d, phi_d), which may lie one step beyond the grid's
// range: there the coordinates continue evenly (u -> -u gives the same theta_h, theta_d -> -theta_d
// is phi_d + pi, phi_d -> -phi_d and pi - phi_d are the symmetries), as the model does.
double ModelAt(const Brdf& brdf, double u, double td, double pd) {
  Vec3 w_i, w_o;
  PairOf(0.5 * M_PI * u * u, 0.0, td, pd, &w_i, &w_o);
  return brdf.Eval(w_i, w_o).g;
}

TEST(TabulatedBrdfTest, SmoothModelWithinTheTrilinearErrorBound) {
  // Trilinear interpolation of a C^2 function errs by at most (1/8) sum_k h_k^2 max |d_k^2 f|
  // over the cell (the 1-D bound h^2 |f''| / 8 per axis). h_k^2 d_k^2 f is estimated from the
  // model itself: its second differences along each axis at the cell's 8 corners. A second
  // difference is f'' averaged over two cells, so the bound doubles it for f'' that grows across
  // the cell. Pairs up to 60 deg keep every corner above the horizon (no filled nodes).
  const HalfDiffGrid grid;  // 32 x 32 x 16
  const GgxBrdf ggx(0.3, 0.3, Rgb(0.04, 0.5, 0.9), Rgb(0.0, 0.1, 0.2));
  const TabulatedBrdf table(grid, TabulateBrdf(ggx, grid), {}, "ggx table");
  const double du = 1.0 / (grid.theta_h_nodes() - 1);
  const double dd = 0.5 * M_PI / (grid.theta_d_nodes() - 1);
  const double dp = 0.5 * M_PI / (grid.phi_d_nodes() - 1);
  Rng rng(7);
  double worst_ratio = 0, worst_relative = 0;
  for (int k = 0; k < 1500; ++k) {
    const Vec3 w_i = testing::RandomUpperDirection(rng, 0.5);
    const Vec3 w_o = testing::RandomUpperDirection(rng, 0.5);
    const HalfDiffGrid::Stencil s = grid.StencilOf(HalfDiffOf(w_i, w_o));
    int ih0, id0, ip0;
    NodeAngles(grid, s.index[0], &ih0, &id0, &ip0);
    double second[3] = {0, 0, 0};
    for (int corner = 0; corner < 8; ++corner) {
      const double u = (ih0 + (corner >> 2)) * du, td = (id0 + ((corner >> 1) & 1)) * dd;
      const double pd = (ip0 + (corner & 1)) * dp;
      const double f0 = ModelAt(ggx, u, td, pd);
      const double steps[3][3] = {{du, 0, 0}, {0, dd, 0}, {0, 0, dp}};
      for (int axis = 0; axis < 3; ++axis) {
        const double* e = steps[axis];
        const double plus = ModelAt(ggx, u + e[0], td + e[1], pd + e[2]);
        const double minus = ModelAt(ggx, u - e[0], td - e[1], pd - e[2]);
        second[axis] = std::max(second[axis], std::abs(plus - 2 * f0 + minus));
      }
    }
    const double bound = 2.0 * (second[0] + second[1] + second[2]) / 8.0;
    const double exact = ggx.Eval(w_i, w_o).g, tabulated = table.Eval(w_i, w_o).g;
    const double error = std::abs(tabulated - exact);
    EXPECT_LE(error, bound + 1e-12 * exact) << k;
    worst_ratio = std::max(worst_ratio, error / (bound + 1e-300));
    worst_relative = std::max(worst_relative, error / exact);
  }
  // Measured: the error reaches 0.48 of the bound, 0.9% of the model at worst.
  EXPECT_LT(worst_relative, 0.02);
  EXPECT_GT(worst_ratio, 0.1);  // the bound is not vacuous
}

TEST(TabulatedBrdfTest, NodesAboveTheHorizonSampleTheModelAndTheOthersTheirNeighbour) {
  const HalfDiffGrid grid(12, 10, 5);
  const GgxBrdf ggx(0.4, 0.4, Rgb(0.9, 0.5, 0.04), Rgb(0.2, 0.1, 0.0));
  const std::vector<Rgb> table = TabulateBrdf(ggx, grid);
  for (int index = 0; index < grid.size(); ++index) {
    int ih, id, ip;
    NodeAngles(grid, index, &ih, &id, &ip);
    if (grid.NodeAboveHorizon(index)) {
      // The mean of the node's pair and its mirror pair (phi_d -> pi - phi_d), which for an
      // isotropic, bilaterally symmetric model is the model. Directions one rounding apart.
      Vec3 w_i, w_o;
      PairOf(grid.ThetaHalf(ih), 0.0, grid.ThetaDiff(id), grid.PhiDiff(ip), &w_i, &w_o);
      const Rgb f = ggx.Eval(w_i, w_o);
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(table[index][ch], f[ch], 1e-12 * f[ch]) << index;
      continue;
    }
    // Below: the nearest node above the horizon at lower theta_d; the theta_h = pi/2 row has
    // none (its nodes are all on or below the horizon) and holds the previous row's values.
    int source = -1;
    for (int j = id - 1; j >= 0 && source < 0; --j) {
      if (grid.NodeAboveHorizon(grid.Index(ih, j, ip))) source = grid.Index(ih, j, ip);
    }
    if (source < 0) {
      ASSERT_EQ(ih, grid.theta_h_nodes() - 1) << index;
      source = grid.Index(ih - 1, id, ip);
    }
    EXPECT_EQ(table[index], table[source]) << index;
    EXPECT_GT(table[index].r, 0.0) << index;
  }
}

TEST(TabulatedBrdfTest, GrazingPairsInterpolateBetweenValuesOfTheModel) {
  // A microfacet model grows like 1 / cos theta towards grazing and is ~1e15 at the 6e-17 that
  // cos(pi/2) rounds to: the theta_h = pi/2 row must not sample it there (it did: 3e13 at 85 deg
  // instead of 0.21). Pairs beyond the last row above the horizon (84.3 deg) take the values of
  // the model at that row's nodes.
  const HalfDiffGrid grid;
  const GgxBrdf ggx(0.4, 0.4, Rgb(0.9, 0.5, 0.04), Rgb(0.2, 0.1, 0.0));
  const TabulatedBrdf table(grid, TabulateBrdf(ggx, grid), {}, "ggx table");
  const int row = grid.theta_h_nodes() - 2;
  double lo = INFINITY, hi = 0;
  for (int id = 0; id < 2; ++id) {
    for (int ip = 0; ip < grid.phi_d_nodes(); ++ip) {
      Vec3 w_i, w_o;
      PairOf(grid.ThetaHalf(row), 0.0, grid.ThetaDiff(id), grid.PhiDiff(ip), &w_i, &w_o);
      lo = std::min(lo, ggx.Eval(w_i, w_o).g);
      hi = std::max(hi, ggx.Eval(w_i, w_o).g);
    }
  }
  for (const double theta_deg : {85.0, 87.0, 89.0, 89.9}) {
    const Vec3 w = SphericalDirection(DegToRad(theta_deg), 0.3);
    const double f = table.Eval(w, w).g;
    EXPECT_GE(f, lo * (1 - 1e-12)) << theta_deg;
    EXPECT_LE(f, hi * (1 + 1e-12)) << theta_deg;
  }
}

TEST(TabulatedBrdfTest, FillBelowHorizonCopiesFromTheStatedNode) {
  // Values are node indices, so each filled node names the node it was copied from.
  const HalfDiffGrid grid(7, 9, 4);
  std::vector<double> values(grid.size());
  for (int n = 0; n < grid.size(); ++n) values[n] = n;
  std::vector<float> floats(values.begin(), values.end());
  FillBelowHorizon(grid, std::span<double>(values));
  FillBelowHorizon(grid, std::span<float>(floats));
  for (int index = 0; index < grid.size(); ++index) {
    int ih, id, ip;
    NodeAngles(grid, index, &ih, &id, &ip);
    int expected = index;
    if (!grid.NodeAboveHorizon(index)) {
      int j = id;
      while (j >= 0 && !grid.NodeAboveHorizon(grid.Index(ih, j, ip))) --j;
      expected =
          j >= 0 ? grid.Index(ih, j, ip) : static_cast<int>(values[grid.Index(ih - 1, id, ip)]);
    }
    EXPECT_EQ(values[index], expected) << index;
    EXPECT_EQ(floats[index], static_cast<float>(expected)) << index;
  }
}

TEST(TabulatedBrdfTest, SigmaIsInterpolatedLikeTheValues) {
  const HalfDiffGrid grid(8, 8, 4);
  const std::vector<Rgb> values = RandomTable(grid, 8);
  const TabulatedBrdf with(grid, values, values, "with sigma");
  const TabulatedBrdf without(grid, values, {}, "without sigma");
  Rng rng(9);
  for (int k = 0; k < 200; ++k) {
    const Vec3 a = testing::RandomUpperDirection(rng), b = testing::RandomUpperDirection(rng);
    EXPECT_EQ(with.EvalSigma(a, b), with.Eval(a, b));
    EXPECT_EQ(without.EvalSigma(a, b), Rgb());
  }
  const Vec3 up{0, 0, 1}, below = Normalize(Vec3{0.3, 0.1, -0.5});
  EXPECT_EQ(with.Eval(below, up), Rgb());
  EXPECT_EQ(with.Eval(up, below), Rgb());
  EXPECT_EQ(with.EvalSigma(below, up), Rgb());
}

TEST(TabulatedBrdfTest, RejectsBadSizesAndValues) {
  const HalfDiffGrid grid(4, 4, 3);
  const std::vector<Rgb> good = RandomTable(grid, 10);
  const auto expect_rejected = [&](std::vector<Rgb> values, std::vector<Rgb> sigma,
                                   const std::string& what) {
    try {
      TabulatedBrdf(grid, std::move(values), std::move(sigma), "spec-under-test");
      ADD_FAILURE() << "accepted " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("spec-under-test"), std::string::npos) << e.what();
    }
  };
  expect_rejected(std::vector<Rgb>(good.begin(), good.end() - 1), {}, "a short table");
  expect_rejected(good, std::vector<Rgb>(3), "a short sigma");
  for (const double bad : {-1e-3, std::nan(""), std::numeric_limits<double>::infinity()}) {
    std::vector<Rgb> values = good;
    values[17].b = bad;
    expect_rejected(values, {}, "value " + std::to_string(bad));
    std::vector<Rgb> sigma = good;
    sigma[5].r = bad;
    expect_rejected(good, sigma, "sigma " + std::to_string(bad));
  }
  EXPECT_NO_THROW(TabulatedBrdf(grid, std::vector<Rgb>(grid.size()), {}, "zeros"));
}

TEST(TabulatedBrdfTest, SamplesWithItsProxy) {
  // Sample and Pdf are the half-vector proxy's (brdf/proxy_sampler.h), fitted to the table: its
  // density is piecewise constant in theta_h with the 1 / (4 |w_o.h|) Jacobian. 10 x 20 bins
  // expect ~250 samples each (noise 6%), so expected counts need only 1e-3; the normalization
  // cubature at 1e-4 per cell (measured 5e-5 off in total) against the 1e-3 bound that
  // proxy_sampler_test.cc uses. Looser than there, to keep the test under a second.
  const HalfDiffGrid grid(32, 24, 8);
  const GgxBrdf ggx(0.15, 0.15, Rgb(0.6), Rgb(0.1));
  const TabulatedBrdf table(grid, TabulateBrdf(ggx, grid), {}, "ggx table");
  testing::SamplingCheckOptions options;
  options.samples = 50000;
  options.radial_bins = 10;
  options.phi_bins = 20;
  options.cubature = {1e-9, 1e-3, 2, 7};
  options.integral_cubature = {1e-9, 1e-4, 2, 7};
  EXPECT_SAMPLING_MATCHES_PDF(table, SphericalDirection(0.6, 1.0), 93, 1e-3, options);
  EXPECT_GT(table.GlossyProbability(SphericalDirection(0.6, 1.0)), 0.05);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
