// Bayer demosaicing of raw camera frames into linear float RGB.
//
// Acquisition merges exposures on raw values and needs color only afterwards; this helper turns
// a Frame into a 3-channel float image with OpenCV's bilinear demosaicing (cv::cvtColor with the
// COLOR_Bayer****2RGB code that matches the frame's PixelLayout, on 16-bit data, so 12- and 16-bit
// sensor values keep all their bits).
//
// Output: cv::Mat of type CV_32FC3, frame.height x frame.width, channels in R, G, B order (not
// OpenCV's usual B, G, R), values in the sensor's digital numbers (no black-level removal, no
// scaling to [0, 1]: divide by 2^bit_depth - 1 if you want that).
//   Bayer layouts: demosaiced. kRgb: converted to float. kMono: the gray value in all three
//   channels. Border pixels follow OpenCV's bilinear rule (edge replication), so the outermost
//   row and column are less accurate than the interior.
// Throws InputError if frame.data does not hold width * height * SamplesPerPixel samples.
#pragma once

#include <opencv2/core.hpp>

#include "drivers/camera.h"

namespace zbrdf {

cv::Mat DemosaicToRgb(const Frame& frame);

// The OpenCV color conversion code DemosaicToRgb uses for a Bayer layout (e.g.
// cv::COLOR_BayerRGGB2RGB for kBayerRGGB); throws InputError for kMono and kRgb.
int BayerToRgbConversionCode(PixelLayout layout);

}  // namespace zbrdf
