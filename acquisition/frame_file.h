// Raw frames on disk: lossless 16-bit TIFF, one sample per pixel (the sensor's mosaic as read
// out, never demosaiced), Zstandard-compressed (TIFF compression 50000, level 1).
//
// Why TIFF/zstd and not PNG: on the thesis camera's 1360x1024 12-bit frames it is as small as
// PNG (1.28 vs 1.33 MB) and decodes 4.5x faster (3.7 vs 17 ms) and encodes 3.5x faster
// (12 vs 43 ms), which is what keeps `zbrdf process` of a 150-frame session under 5 s.
// Readers: libtiff >= 4.0.10 built with zstd (Debian, Fedora, conda), OpenCV, GDAL, Fiji,
// Python tifffile + imagecodecs. Sessions written with PNG frames read as well.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "drivers/camera.h"

namespace zbrdf {

// The frame's samples as a TIFF file's bytes. Only raw layouts (mono or Bayer) are accepted;
// the layout, bit depth, exposure and the checksum of the samples are recorded in
// ImageDescription:
//   zbrdf raw frame: layout bayer-rggb, 12 significant bits, exposure 69564.000 us, samples
//   xxh3-64:2bba29679ceb26b9
// so that a frame's damage is found from the file alone, even without its journal line. Nothing
// run-dependent (frame ids, times) goes into the file: the same samples give the same bytes, so a
// resumed session's frames are byte-identical to an uninterrupted one's; the journal has the
// rest. Throws DeviceError for an RGB or mis-sized frame.
std::string EncodeFrameFile(const Frame& frame);

// XXH3 64 of the samples as little-endian 16-bit words (what ImageDescription records).
uint64_t FrameSamplesChecksum(const std::vector<uint16_t>& samples);
// FNV-1a 64 of the same bytes: what frames written before XXH3 record ("samples fnv1a64:").
uint64_t FrameSamplesFnv1a64(const std::vector<uint16_t>& samples);

// Decodes a TIFF (or PNG) frame file's bytes into samples, checking it is a 16-bit single-
// channel image of the expected size and, for a frame that records the checksum of its samples
// (XXH3, or FNV-1a in frames written before it), that they match it. Frames of earlier versions
// (no checksum in ImageDescription, or PNG) are read without that check. Throws InputError naming
// `what` otherwise.
std::vector<uint16_t> DecodeFrameFile(const std::string& bytes, int width, int height,
                                      const std::string& what);

}  // namespace zbrdf
