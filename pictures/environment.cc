#include "pictures/environment.h"

#include <algorithm>
#include <cmath>

#include "basis/error.h"

namespace zbrdf {
namespace {

Rgb Mix(const Rgb& a, const Rgb& b, double t) { return a * (1.0 - t) + b * t; }

// The procedural sky without the sun (see environment.h).
Rgb SkyGradient(const Vec3& d) {
  const Rgb zenith(0.15, 0.27, 0.55), horizon(0.70, 0.75, 0.85), ground(0.16, 0.13, 0.10);
  const Rgb upper = Mix(horizon, zenith, std::sqrt(std::max(0.0, d.y)));
  // A soft horizon line, 2 deg wide.
  const double t = std::clamp(d.y / std::sin(2.0 * M_PI / 180.0) * 0.5 + 0.5, 0.0, 1.0);
  return Mix(ground, upper, t);
}

}  // namespace

Environment::Environment(RgbImage latlong, double rotation_rad) : rotation_rad_(rotation_rad) {
  if (latlong.width < 1 || latlong.height < 1) throw InputError("environment map is empty");
  auto data = std::make_shared<Data>();
  data->image = std::move(latlong);
  const RgbImage& image = data->image;
  std::vector<double> weights(image.pixels.size());
  double total = 0;
  for (int y = 0; y < image.height; ++y) {
    const double sin_theta = std::sin(M_PI * (y + 0.5) / image.height);
    for (int x = 0; x < image.width; ++x) {
      const double w = image.At(x, y).Max() * sin_theta;
      weights[static_cast<size_t>(y) * image.width + x] = w;
      total += w;
    }
  }
  // Each pixel of row y spans (2 pi / width) (cos theta_y - cos theta_(y+1)) sr; the sphere 4 pi.
  double mean = 0;
  for (int y = 0; y < image.height; ++y) {
    const double solid_angle = 2.0 * M_PI / image.width *
                               (std::cos(M_PI * y / image.height) -
                                std::cos(M_PI * (y + 1) / image.height));
    for (int x = 0; x < image.width; ++x) mean += image.At(x, y).Max() * solid_angle;
  }
  data->mean_max_radiance = mean / (4.0 * M_PI);
  if (total > 0) {
    data->distribution = std::make_unique<Distribution2D>(weights, image.width, image.height);
  }
  data_ = std::move(data);
}

Environment Environment::FromFile(const std::string& path, double rotation_rad,
                                  int* negative_pixels) {
  return Environment(ReadEnvironmentImage(path, negative_pixels), rotation_rad);
}

// Direction() has (x, z) = sin(theta) (sin phi, -cos phi), and a turn r adds r to phi.
TurnAboutY::TurnAboutY(double turn_rad)
    : cos_turn(std::cos(turn_rad)), sin_turn(std::sin(turn_rad)) {}

Environment Environment::Rotated(double rotation_rad) const {
  Environment copy = *this;
  copy.rotation_rad_ += rotation_rad;
  if (Dot(sun_, sun_) > 0) copy.sun_ = TurnAboutY(rotation_rad).Forward(sun_);  // the sun turns too
  return copy;
}

std::optional<double> Environment::TurnSince(const Environment& earlier) const {
  if (data_ != earlier.data_) return std::nullopt;
  return rotation_rad_ - earlier.rotation_rad_;
}

Environment Environment::Constant(const Rgb& radiance) {
  RgbImage image(8, 4);
  std::fill(image.pixels.begin(), image.pixels.end(), radiance);
  return Environment(std::move(image));
}

Environment Environment::Sky() {
  constexpr int kWidth = 1024, kHeight = 512, kSuper = 4;
  const Vec3 sun = Normalize(Vec3{-0.46, 0.643, 0.613});
  const double sun_radius = 2.0 * M_PI / 180.0;
  const double cos_sun = std::cos(sun_radius);
  RgbImage image(kWidth, kHeight);
  std::vector<double> coverage(image.pixels.size(), 0.0);
  // Pixel directions follow the map convention with no rotation.
  auto direction = [](double u, double v) {
    const double phi = 2.0 * M_PI * (u - 0.5), theta = M_PI * v;
    return Vec3{std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
  };
  double sun_solid_angle = 0;
  for (int y = 0; y < kHeight; ++y) {
    const double pixel_solid_angle =
        2.0 * M_PI / kWidth * (std::cos(M_PI * y / kHeight) - std::cos(M_PI * (y + 1) / kHeight));
    for (int x = 0; x < kWidth; ++x) {
      Rgb sum;
      int inside = 0;
      for (int sy = 0; sy < kSuper; ++sy) {
        for (int sx = 0; sx < kSuper; ++sx) {
          const Vec3 d =
              direction((x + (sx + 0.5) / kSuper) / kWidth, (y + (sy + 0.5) / kSuper) / kHeight);
          sum += SkyGradient(d);
          if (Dot(d, sun) >= cos_sun) ++inside;
        }
      }
      const size_t i = static_cast<size_t>(y) * kWidth + x;
      image.pixels[i] = sum / (kSuper * kSuper);
      coverage[i] = static_cast<double>(inside) / (kSuper * kSuper);
      sun_solid_angle += coverage[i] * pixel_solid_angle;
    }
  }
  // Sun radiance for an irradiance of 2.5 pi at normal incidence (the disk is small enough that
  // cos over it is 1 to 6e-4).
  const Rgb sun_color(1.0, 0.93, 0.82);
  const Rgb sun_radiance = sun_color * (2.5 * M_PI / sun_solid_angle / sun_color.Luminance());
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] += sun_radiance * coverage[i];
  Environment env(std::move(image));
  env.sun_ = sun;
  return env;
}

Environment Environment::Studio() {
  constexpr int kWidth = 1024, kHeight = 512, kSuper = 4;
  // Direction of the map's pixel centre (u, v), no rotation.
  auto direction = [](double u, double v) {
    const double phi = 2.0 * M_PI * (u - 0.5), theta = M_PI * v;
    return Vec3{std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
  };
  struct Light {
    Vec3 center;       // unit
    double half_u, half_v;  // half extents in radians along the light's two tangents
    Rgb radiance;
  };
  // Two soft boxes (key upper left, fill right) and a small bright spot behind upper right.
  const std::vector<Light> lights = {
      {Normalize(Vec3{-0.6, 0.55, 0.58}), 0.28, 0.18, Rgb(6.0, 5.8, 5.4)},
      {Normalize(Vec3{0.85, 0.25, 0.45}), 0.12, 0.35, Rgb(1.6, 1.8, 2.2)},
      {Normalize(Vec3{0.45, 0.7, -0.55}), 0.03, 0.03, Rgb(120.0, 110.0, 95.0)},
  };
  RgbImage image(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      Rgb sum;
      for (int sy = 0; sy < kSuper; ++sy) {
        for (int sx = 0; sx < kSuper; ++sx) {
          const Vec3 d =
              direction((x + (sx + 0.5) / kSuper) / kWidth, (y + (sy + 0.5) / kSuper) / kHeight);
          // A dim room: darker floor, a faint gradient up the walls.
          Rgb c = d.y < 0 ? Rgb(0.015, 0.014, 0.013) : Rgb(0.03 + 0.03 * d.y);
          for (const Light& light : lights) {
            Vec3 t, b;
            OrthonormalBasis(light.center, &t, &b);
            const double along = Dot(d, light.center);
            if (along <= 0) continue;
            if (std::abs(std::atan2(Dot(d, t), along)) <= light.half_u &&
                std::abs(std::atan2(Dot(d, b), along)) <= light.half_v) {
              c = light.radiance;
            }
          }
          sum += c;
        }
      }
      image.pixels[static_cast<size_t>(y) * kWidth + x] = sum / (kSuper * kSuper);
    }
  }
  return Environment(std::move(image));
}

void Environment::MapCoordinates(const Vec3& d, double* u, double* v) const {
  double phi = std::atan2(d.x, -d.z) - rotation_rad_;
  *u = 0.5 + phi / (2.0 * M_PI);
  *u -= std::floor(*u);
  *v = std::acos(std::clamp(d.y, -1.0, 1.0)) / M_PI;
}

Vec3 Environment::Direction(double u, double v) const {
  const double phi = 2.0 * M_PI * (u - 0.5) + rotation_rad_, theta = M_PI * v;
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

Rgb Environment::Radiance(const Vec3& d) const {
  double u, v;
  MapCoordinates(d, &u, &v);
  const RgbImage& image = data_->image;
  const int x = std::min(static_cast<int>(u * image.width), image.width - 1);
  const int y = std::min(static_cast<int>(v * image.height), image.height - 1);
  return image.At(x, y);
}

Vec3 Environment::Sample(double u0, double u1, double* pdf) const {
  if (!data_->distribution) {
    *pdf = 0;
    return {0, 1, 0};
  }
  double pdf_uv = 0;
  const auto [u, v] = data_->distribution->Sample(u0, u1, &pdf_uv);
  const double sin_theta = std::sin(M_PI * v);
  *pdf = sin_theta > 0 ? pdf_uv / (2.0 * M_PI * M_PI * sin_theta) : 0.0;
  return Direction(u, v);
}

double Environment::Pdf(const Vec3& d) const {
  if (!data_->distribution) return 0;
  double u, v;
  MapCoordinates(d, &u, &v);
  const double sin_theta = std::sin(M_PI * v);
  return sin_theta > 0 ? data_->distribution->Pdf(u, v) / (2.0 * M_PI * M_PI * sin_theta) : 0.0;
}

}  // namespace zbrdf
