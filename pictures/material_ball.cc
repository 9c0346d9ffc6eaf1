#include "pictures/material_ball.h"

#include <cmath>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "brdf/sampling.h"

namespace zbrdf {
namespace {

// SplitMix64 (Steele, Lea & Flood 2014): a small, fast generator, seeded per pixel so that the
// image does not depend on how rows are split among threads.
class PixelRng {
 public:
  PixelRng(uint64_t seed, int x, int y)
      : state_(seed * 0x9E3779B97F4A7C15ull ^
               (static_cast<uint64_t>(y) << 32 | static_cast<uint32_t>(x))) {
    Next();
  }
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1p-53; }

 private:
  uint64_t Next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  uint64_t state_;
};

struct Frame {
  Vec3 t, b, n;
  Vec3 ToLocal(const Vec3& d) const { return {Dot(d, t), Dot(d, b), Dot(d, n)}; }
  Vec3 ToWorld(const Vec3& d) const { return FromLocalFrame(d, t, b, n); }
};

// Tangent along the horizontal circle through the point (see material_ball.h).
Frame ShadingFrame(const Vec3& n) {
  Frame f;
  f.n = n;
  const Vec3 around = Cross(Vec3{0, 1, 0}, n);
  if (Dot(around, around) > 1e-12) {
    f.t = Normalize(around);
    f.b = Cross(n, f.t);
  } else {
    OrthonormalBasis(n, &f.t, &f.b);
  }
  return f;
}

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
  // Image plane extent: the ball (radius 1) fills 1 / 1.1 of the frame.
  const double extent = 1.1;
  // Pinhole: camera at distance 4 on +z; the field of view frames the ball's silhouette.
  const double distance = 4.0;
  const double tan_half = std::tan(std::asin(1.0 / distance)) * extent;
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
          const double jx = k == 0 ? 0.5 : rng.Uniform(), jy = k == 0 ? 0.5 : rng.Uniform();
          const double sx = (2.0 * (x + jx) / size - 1.0) * extent;
          const double sy = (1.0 - 2.0 * (y + jy) / size) * extent;
          Vec3 origin, direction;
          if (options.camera == BallOptions::Camera::kOrthographic) {
            origin = {sx, sy, 10.0};
            direction = {0, 0, -1};
          } else {
            origin = {0, 0, distance};
            direction = Normalize(Vec3{sx / extent * tan_half, sy / extent * tan_half, -1.0});
          }
          // Ray-sphere intersection, |origin + s direction| = 1.
          const double b = Dot(origin, direction);
          const double c = Dot(origin, origin) - 1.0;
          const double disc = b * b - c;
          if (disc <= 0) {
            sum += directional ? options.background : env->Radiance(direction);
            continue;
          }
          if (k == 0) out.coverage[static_cast<size_t>(y) * size + x] = 1;
          const Vec3 p = origin + direction * (-b - std::sqrt(disc));
          const Frame frame = ShadingFrame(Normalize(p));
          const Vec3 w_o = frame.ToLocal(-direction);
          if (w_o.z <= 0) continue;
          if (directional) {
            const Vec3 w_i = frame.ToLocal(light);
            if (w_i.z > 0) sum += brdf.Eval(w_i, w_o) * (w_i.z * options.light_irradiance);
          } else {
            sum += EnvironmentEstimate(brdf, *env, frame, w_o, options.sampling, rng);
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
