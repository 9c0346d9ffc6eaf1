#include "calibration/float_image.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>

#include "basis/atomic_file.h"
#include "basis/error.h"

namespace zbrdf {

void WriteFloatImage(const std::string& path, const FloatImage& image) {
  const size_t pixels = static_cast<size_t>(image.width) * image.height;
  if (image.width <= 0 || image.height <= 0) {
    throw InternalError("WriteFloatImage: empty image for " + path);
  }
  Imf::Header header(image.width, image.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  Imf::FrameBuffer fb;
  for (const auto& [name, values] : image.channels) {
    if (values.size() != pixels) {
      throw InternalError("WriteFloatImage: channel " + name + " has the wrong size for " + path);
    }
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    fb.insert(name, Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(values.data())),
                               sizeof(float), sizeof(float) * image.width));
  }
  Imf::StdOSStream stream;  // encoded in memory, written through basis/atomic_file.h
  try {
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(fb);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    throw InputError("cannot encode " + path + ": " + e.what());
  }
  WriteFileAtomically(path, stream.str());
}

FloatImage ReadFloatImage(const std::string& path, const std::vector<std::string>& required) {
  FloatImage image;
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    image.width = window.max.x - window.min.x + 1;
    image.height = window.max.y - window.min.y + 1;
    const size_t pixels = static_cast<size_t>(image.width) * image.height;
    Imf::FrameBuffer fb;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
      std::vector<float>& values = image.channels[it.name()];
      values.assign(pixels, 0.0f);
      char* base = reinterpret_cast<char*>(values.data()) -
                   (static_cast<ptrdiff_t>(window.min.y) * image.width + window.min.x) * sizeof(float);
      fb.insert(it.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * image.width));
    }
    file.setFrameBuffer(fb);
    file.readPixels(window.min.y, window.max.y);
  } catch (const std::exception& e) {
    throw InputError("cannot read " + path + " (" + e.what() +
                     "); re-run the calibration step that writes it");
  }
  for (const std::string& name : required) {
    if (!image.channels.count(name)) {
      throw InputError(path + " has no channel '" + name + "'; re-run the calibration step that writes it");
    }
  }
  return image;
}

}  // namespace zbrdf
