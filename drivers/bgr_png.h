// OpenCV images as PNG files: what the layers that draw with OpenCV (calibration's and pictures'
// figures) write, through basis/png.h.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace zbrdf {

// The PNG file of an 8- or 16-bit gray, BGR or BGRA image (written as gray, RGB or RGBA).
// Throws InputError for an empty image or another type.
std::string EncodeBgrPng(const cv::Mat& image);

}  // namespace zbrdf
