// The writer of zbrdf's two-part OpenEXR files (zonal.exr, SH files): an image part over the
// exitant grid and an n x n tensor part, both scanline, ZIP-compressed (lossless), every channel
// 32-bit float, the same zbrdf.* attributes on both parts (OpenEXR keeps attributes per part; a
// reader that opens only one part still sees them). Parts of a multi-part file share a display
// window: the tensor part has the image's display window and its own data window at the origin.
//
// WriteScanlineExr: the one-part files (D-BRDF, tabulated BRDF, prior), encoded in memory and
// written whole through basis/atomic_file.h.
#pragma once

#include <ImfFrameBuffer.h>
#include <ImfHeader.h>

#include <memory>
#include <string>
#include <vector>

namespace zbrdf {

// Encodes one scanline part (header, frame buffer, `rows` scanlines) and writes it whole. Throws
// InputError("cannot write " + what + " " + path + ": " + OpenEXR's message), or basis/
// atomic_file.h's FileWriteError for the write itself.
void WriteScanlineExr(const std::string& path, const Imf::Header& header,
                      const Imf::FrameBuffer& frame_buffer, int rows, const std::string& what);

class TwoPartExrWriter {
 public:
  // The image part is width x height pixels, the tensor part tensor_size x tensor_size.
  TwoPartExrWriter(const std::string& image_part, int width, int height,
                   const std::string& tensor_part, int tensor_size);
  ~TwoPartExrWriter();
  TwoPartExrWriter(const TwoPartExrWriter&) = delete;
  TwoPartExrWriter& operator=(const TwoPartExrWriter&) = delete;

  // Attributes of both parts.
  void SetString(const std::string& name, const std::string& value);
  void SetDouble(const std::string& name, double value);
  void SetInt(const std::string& name, int value);

  // A channel of the image part: pixel (x, y) is at base[y * y_stride + x * x_stride] (strides in
  // floats). The memory must stay valid until Write() returns.
  void AddImageChannel(const std::string& name, const float* base, size_t x_stride,
                       size_t y_stride);
  // A channel of the image part, width * height values (x fastest), kept by the writer.
  void AddImageChannel(const std::string& name, std::vector<float> values);
  // A channel of the tensor part, tensor_size^2 values (row-major), kept by the writer.
  void AddTensorChannel(const std::string& name, std::vector<float> values);

  // Writes the file. Throws InputError("cannot write " + what + ": " + OpenEXR's message).
  void Write(const std::string& path, const std::string& what) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace zbrdf
