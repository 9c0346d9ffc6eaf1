#include "pictures/dome_drawing.h"

#include <cmath>
#include <cstdio>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/zone.h"
#include "pictures/image.h"

namespace zbrdf {

namespace {

// Blue at theta = 0 through green to red at 90 deg (BGR).
cv::Scalar ThetaColor(double theta_rad) {
  const double t = std::clamp(theta_rad / (M_PI / 2), 0.0, 1.0);
  return cv::Scalar(255 * (1 - t), 255 * (1 - std::abs(2 * t - 1)), 255 * t);
}

}  // namespace

void DrawDomeCrossSection(const OpticalSystem& optics, const std::string& png_path) {
  const Rig& rig = optics.rig();
  const DomeDesign& design = optics.design();
  double r_max = rig.sample_diameter_mm;
  for (const auto& p : design.profile) r_max = std::max(r_max, p.r_mm);
  const double z_top = rig.camera.position_mm.z + 20;
  const double margin = 20;
  const int width = 1000;
  const double scale = (width - 2 * margin) / (2 * r_max);
  const int height = static_cast<int>(z_top * scale + 2 * margin + 30);
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  auto to_pixel = [&](double x_mm, double z_mm) {
    return cv::Point(static_cast<int>(std::lround(width / 2.0 + x_mm * scale)),
                     static_cast<int>(std::lround(height - margin - 30 - z_mm * scale)));
  };
  // Sample and table.
  cv::line(image, to_pixel(-r_max, 0), to_pixel(r_max, 0), cv::Scalar(180, 180, 180), 1);
  cv::line(image, to_pixel(-rig.sample_diameter_mm / 2, 0), to_pixel(rig.sample_diameter_mm / 2, 0),
           cv::Scalar(0, 0, 0), 3);
  // Chief rays along the middle row of the camera image.
  const ThinLens& camera = optics.camera();
  const int cols = rig.camera.width;
  for (int k = 0; k <= 40; ++k) {
    const double px = (k + 0.5) * cols / 41.0;
    std::vector<Vec3> vertices;
    const auto path = optics.TraceToSample(camera.ChiefRay(px, rig.camera.height / 2.0), &vertices);
    if (path.status != OpticalSystem::PathStatus::kLanded) continue;
    const cv::Scalar color = ThetaColor(SphericalTheta(path.w));
    for (size_t i = 1; i < vertices.size(); ++i) {
      cv::line(image, to_pixel(vertices[i - 1].x, vertices[i - 1].z),
               to_pixel(vertices[i].x, vertices[i].z), color, 1, cv::LINE_AA);
    }
  }
  // Parabola.
  std::vector<cv::Point> parabola;
  const ParabolaParams& p = rig.parabola;
  for (int i = -100; i <= 100; ++i) {
    const double r = p.rim_radius_mm * i / 100.0;
    parabola.push_back(to_pixel(r, p.vertex_height_mm - r * r / (4 * p.focal_length_mm)));
  }
  cv::polylines(image, parabola, false, cv::Scalar(0, 0, 0), 2, cv::LINE_AA);
  // Dome profile on both sides.
  for (int side : {-1, 1}) {
    std::vector<cv::Point> dome;
    for (size_t i = 0; i < design.profile.size(); i += std::max<size_t>(1, design.profile.size() / 500)) {
      dome.push_back(to_pixel(side * design.profile[i].r_mm, design.profile[i].z_mm));
    }
    dome.push_back(to_pixel(side * design.profile.back().r_mm, design.profile.back().z_mm));
    cv::polylines(image, dome, false, cv::Scalar(60, 60, 60), 2, cv::LINE_AA);
  }
  // Camera.
  const Vec3 c = rig.camera.position_mm;
  cv::rectangle(image, to_pixel(c.x - 12, c.z), to_pixel(c.x + 12, c.z + 15), cv::Scalar(0, 0, 0), -1);
  char caption[256];
  std::snprintf(caption, sizeof(caption), "%s: zone %.1f-%.1f deg, %.1f%% of the hemisphere, >= %.1f px/deg",
                rig.name.c_str(), RadToDeg(design.zone_min_rad), RadToDeg(design.zone_max_rad),
                100 * design.coverage_fraction, design.pixels_per_degree_min);
  cv::putText(image, caption, cv::Point(10, height - 10), cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  WritePng(png_path, image);
}

void WriteDomeProfileCsv(const DomeDesign& design, const std::string& csv_path) {
  std::string out = "r_mm,z_mm,normal_r,normal_z,theta_deg,camera_angle_deg\n";
  char line[256];
  for (const auto& p : design.profile) {
    std::snprintf(line, sizeof(line), "%.9g,%.9g,%.12g,%.12g,%.9g,%.9g\n", p.r_mm, p.z_mm,
                  p.normal_r, p.normal_z, RadToDeg(p.theta_rad), RadToDeg(p.camera_angle_rad));
    out += line;
  }
  WriteFileAtomically(csv_path, out);
}

}  // namespace zbrdf
