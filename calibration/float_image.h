// Single-precision images in OpenEXR files: the calibration folder's per-pixel data (flat
// fields, gray-code correspondences), readable by any EXR viewer.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace zbrdf {

struct FloatImage {
  int width = 0, height = 0;
  // Channel name -> width * height values, row-major.
  std::map<std::string, std::vector<float>> channels;
};

// Writes all channels as FLOAT, ZIP-compressed. Throws InputError naming the file on failure.
void WriteFloatImage(const std::string& path, const FloatImage& image);
// Reads every channel as float. Throws InputError naming the file if it is missing, damaged,
// or lacks one of `required` channels.
FloatImage ReadFloatImage(const std::string& path, const std::vector<std::string>& required = {});

}  // namespace zbrdf
