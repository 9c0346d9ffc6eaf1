#include "pictures/brdf_figure.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/parallel.h"
#include "drivers/bgr_png.h"
#include "pictures/image.h"

namespace zbrdf {

cv::Mat DrawSphereFigure(const std::vector<FigurePanel>& panels, int size, FigureStats* stats_out) {
  if (panels.empty() || size < 16) throw InputError("figure: no panels or a size below 16 pixels");
  const Vec3 view{0, 0, 1};
  const double light_angle = 40.0 * M_PI / 180.0;
  const Vec3 light = Normalize(Vec3{-std::sin(light_angle) * M_SQRT1_2, std::sin(light_angle) * M_SQRT1_2,
                                    std::cos(light_angle)});
  // Radiance per panel and pixel (NaN off the sphere).
  std::vector<std::vector<Rgb>> radiance(panels.size(), std::vector<Rgb>(size * size));
  std::vector<uint8_t> on_sphere(size * size, 0);
  for (size_t p = 0; p < panels.size(); ++p) {
    ParallelFor(size, 4, [&](int64_t y0, int64_t y1) {
      for (int64_t y = y0; y < y1; ++y) {
        for (int x = 0; x < size; ++x) {
          const double u = (x + 0.5) / size * 2 - 1, v = 1 - (y + 0.5) / size * 2;
          const double r2 = u * u + v * v;
          const int index = static_cast<int>(y) * size + x;
          if (r2 >= 1) continue;
          on_sphere[index] = 1;
          const Vec3 n{u, v, std::sqrt(1 - r2)};
          // Sample frame: normal n, tangent along the image's x axis projected on the surface.
          const Vec3 t = Normalize(Vec3{1, 0, 0} - n * n.x);
          const Vec3 b = Cross(n, t);
          const Vec3 wi{Dot(light, t), Dot(light, b), Dot(light, n)};
          const Vec3 wo{Dot(view, t), Dot(view, b), Dot(view, n)};
          Rgb f;
          if (wi.z > 0 && wo.z > 0) panels[p].f_hat(wo, std::span<const Vec3>(&wi, 1), std::span<Rgb>(&f, 1));
          radiance[p][index] = f;
        }
      }
    });
  }
  // Exposure from the first panel.
  std::vector<double> values;
  for (int i = 0; i < size * size; ++i) {
    if (on_sphere[i]) values.push_back(radiance[0][i].Max());
  }
  std::sort(values.begin(), values.end());
  double scale = values.empty() ? 1.0 : values[static_cast<size_t>(0.995 * (values.size() - 1))];
  if (!(scale > 0)) scale = 1.0;
  const int caption = 40;
  cv::Mat image(size + caption, size * static_cast<int>(panels.size()), CV_8UC3, cv::Scalar(40, 40, 40));
  FigureStats stats;
  for (size_t p = 0; p < panels.size(); ++p) {
    int negative = 0, total = 0;
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < size; ++x) {
        const int i = y * size + x;
        if (!on_sphere[i]) continue;
        ++total;
        const Rgb& f = radiance[p][i];
        cv::Vec3b& pixel = image.at<cv::Vec3b>(y, static_cast<int>(p) * size + x);
        if (f.r < 0 || f.g < 0 || f.b < 0) {
          ++negative;
          pixel = cv::Vec3b(255, 0, 255);
          continue;
        }
        for (int ch = 0; ch < 3; ++ch) {
          pixel[2 - ch] = static_cast<uint8_t>(std::lround(255 * SrgbEncode(f[ch] / scale)));
        }
      }
    }
    const double fraction = total > 0 ? static_cast<double>(negative) / total : 0.0;
    stats.negative_pixel_fraction.push_back(fraction);
    char text[64];
    std::snprintf(text, sizeof(text), "negative: %.1f%%", 100 * fraction);
    cv::putText(image, panels[p].label, cv::Point(static_cast<int>(p) * size + 6, size + 16),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    cv::putText(image, text, cv::Point(static_cast<int>(p) * size + 6, size + 34),
                cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(255, 0, 255), 1, cv::LINE_AA);
  }
  if (stats_out != nullptr) *stats_out = stats;
  return image;
}

FigureStats WriteSphereFigure(const std::string& path, const std::vector<FigurePanel>& panels,
                              int size) {
  FigureStats stats;
  const cv::Mat image = DrawSphereFigure(panels, size, &stats);
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".png") throw InputError("cannot write figure " + path + ": give it a .png name");
  WriteFileAtomically(path, EncodeBgrPng(image));
  return stats;
}

}  // namespace zbrdf
