#include "pictures/material_ball.h"

#include <cmath>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "brdf/sampling.h"
#include "pictures/ball_geometry.h"

namespace zbrdf {
namespace {

using ball::Frame;
using ball::PixelRng;

// Veach & Guibas 1995, the power heuristic with beta = 2: the weight of a sample drawn with
// density a when the other strategy would have drawn it with density b.
double PowerHeuristic(double a, double b) {
  const double a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0;
}

// The radiance a sample frame reflects toward w_o under the environment, one sample's estimate.
Rgb EnvironmentEstimate(const Brdf& brdf, const Environment& env, const Frame& frame,
                        const Vec3& w_o, BallOptions::Sampling sampling, PixelRng& rng) {
  using Sampling = BallOptions::Sampling;
  Rgb sum;
  if (sampling == Sampling::kMis || sampling == Sampling::kBrdf) {
    const double u_lobe = rng.Uniform(), u0 = rng.Uniform(), u1 = rng.Uniform();
    const BrdfSample s = brdf.Sample(w_o, u_lobe, u0, u1);
    if (s.pdf > 0 && s.w_i.z > 0) {
      const Vec3 d = frame.ToWorld(s.w_i);
      if (s.is_delta) {
        sum += s.delta_reflectance * env.Radiance(d);
      } else {
        const double weight = sampling == Sampling::kMis ? PowerHeuristic(s.pdf, env.Pdf(d)) : 1.0;
        sum += brdf.Eval(s.w_i, w_o) * env.Radiance(d) * (s.w_i.z * weight / s.pdf);
      }
    }
  }
  if (sampling == Sampling::kMis || sampling == Sampling::kLight) {
    double pdf = 0;
    const Vec3 d = env.Sample(rng.Uniform(), rng.Uniform(), &pdf);
    const Vec3 w_i = frame.ToLocal(d);
    if (pdf > 0 && w_i.z > 0) {
      const double weight =
          sampling == Sampling::kMis ? PowerHeuristic(pdf, brdf.Pdf(w_o, w_i)) : 1.0;
      sum += brdf.Eval(w_i, w_o) * env.Radiance(d) * (w_i.z * weight / pdf);
    }
  }
  if (sampling == Sampling::kCosine) {
    const Vec3 w_i = SampleCosineHemisphere(rng.Uniform(), rng.Uniform());
    const double pdf = CosineHemispherePdf(w_i);
    if (pdf > 0) sum += brdf.Eval(w_i, w_o) * env.Radiance(frame.ToWorld(w_i)) * (w_i.z / pdf);
  }
  return sum;
}

}  // namespace

void BallOptions::Validate() const {
  OptionChecker check("BallOptions");
  check.InRange("size", size, 8, 8192).AtLeast("spp", spp, 1);
  if (light_direction) {
    const Vec3& d = *light_direction;
    check.Require(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z) && Length(d) > 0,
                  "light_direction", "must be a finite, non-zero vector");
  }
  check.Require(light_irradiance >= 0 && std::isfinite(light_irradiance), "light_irradiance",
                "must be >= 0 and finite (got " + FormatOptionValue(light_irradiance) + ")")
      .ThrowIfInvalid();
}

BallImage RenderBall(const Brdf& brdf, const Environment* env, const BallOptions& options) {
  options.Validate();
  const bool directional = options.light_direction.has_value();
  if (!directional && env == nullptr) {
    throw InputError("preview: no light: give a directional light or an environment");
  }
  const Vec3 light = directional ? Normalize(*options.light_direction) : Vec3();
  const int size = options.size;
  BallImage out;
  out.image = RgbImage(size, size);
  out.coverage.assign(static_cast<size_t>(size) * size, 0);
  ParallelFor(size, 1, [&](int64_t row_begin, int64_t row_end) {
    for (int y = static_cast<int>(row_begin); y < row_end; ++y) {
      for (int x = 0; x < size; ++x) {
        PixelRng rng(options.seed, x, y);
        Rgb sum;
        for (int k = 0; k < options.spp; ++k) {
          // Pixel centre for the first sample, jittered after it.
          const bool centre = k == 0 || !options.jitter;
          const double jx = centre ? 0.5 : rng.Uniform(), jy = centre ? 0.5 : rng.Uniform();
          const ball::PixelView view = ball::ViewThrough(options, x + jx, y + jy);
          if (!view.on_ball) {
            sum += directional ? options.background : env->Radiance(view.direction);
            continue;
          }
          if (k == 0) out.coverage[static_cast<size_t>(y) * size + x] = 1;
          const Vec3& w_o = view.w_o;
          if (w_o.z <= 0) continue;
          if (directional) {
            const Vec3 w_i = view.frame.ToLocal(light);
            if (w_i.z > 0) sum += brdf.Eval(w_i, w_o) * (w_i.z * options.light_irradiance);
          } else {
            sum += EnvironmentEstimate(brdf, *env, view.frame, w_o, options.sampling, rng);
          }
        }
        out.image.At(x, y) = sum / options.spp;
      }
    }
  });
  return out;
}

double BallRmse(const BallImage& a, const BallImage& b) {
  ZBRDF_ASSERT(a.image.width == b.image.width && a.image.height == b.image.height,
               "BallRmse: images differ in size");
  double sum = 0;
  int64_t count = 0;
  for (size_t i = 0; i < a.image.pixels.size(); ++i) {
    if (!a.coverage[i] || !b.coverage[i]) continue;
    for (int c = 0; c < 3; ++c) {
      const double d = a.image.pixels[i][c] - b.image.pixels[i][c];
      sum += d * d;
    }
    count += 3;
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

}  // namespace zbrdf
