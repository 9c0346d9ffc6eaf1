// Animated PNG (APNG, Mozilla's extension of PNG; every current browser shows it, and a viewer
// without APNG support shows the first frame): the frames of a turntable or an environment
// sequence as one image for the session report.
//
// Each frame is encoded by OpenCV's PNG encoder; its IHDR and IDAT chunks are rearranged into the
// APNG layout: IHDR, acTL (frame count, loop forever), then per frame an fcTL (sequence number,
// full-size region, delay 1/fps s, no disposal, source blending) followed by the frame's data:
// IDAT chunks for frame 0, fdAT chunks (sequence number + the IDAT payload) for the others.
// CRC-32 as PNG specifies (zlib's crc32).
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace zbrdf {

// frames: 8-bit BGR images of one size (at least one). fps in [1, 120]. Throws InputError
// otherwise.
std::string EncodeAnimatedPng(const std::vector<cv::Mat>& frames, int fps);
// Writes the encoding atomically.
void WriteAnimatedPng(const std::string& path, const std::vector<cv::Mat>& frames, int fps);

}  // namespace zbrdf
