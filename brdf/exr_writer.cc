#include "brdf/exr_writer.h"

#include <ImfChannelList.h>
#include <ImfDoubleAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIntAttribute.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>

#include <deque>

#include "basis/atomic_file.h"
#include "basis/error.h"

namespace zbrdf {

struct TwoPartExrWriter::Impl {
  Imf::Header image_header, tensor_header;
  Imf::FrameBuffer image_fb, tensor_fb;
  int height = 0, tensor_size = 0;
  std::deque<std::vector<float>> storage;  // owned channels; a deque never moves its elements

  void Insert(Imf::Header& header, Imf::FrameBuffer& fb, const std::string& name,
              const float* base, size_t x_stride, size_t y_stride) {
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(base)),
                               sizeof(float) * x_stride, sizeof(float) * y_stride));
  }
};

TwoPartExrWriter::TwoPartExrWriter(const std::string& image_part, int width, int height,
                                   const std::string& tensor_part, int tensor_size)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.height = height;
  m.tensor_size = tensor_size;
  m.image_header = Imf::Header(width, height);
  m.image_header.setName(image_part);
  m.image_header.setType(Imf::SCANLINEIMAGE);
  m.image_header.compression() = Imf::ZIP_COMPRESSION;
  m.tensor_header =
      Imf::Header(m.image_header.displayWindow(),
                  Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(tensor_size - 1, tensor_size - 1)));
  m.tensor_header.setName(tensor_part);
  m.tensor_header.setType(Imf::SCANLINEIMAGE);
  m.tensor_header.compression() = Imf::ZIP_COMPRESSION;
}

TwoPartExrWriter::~TwoPartExrWriter() = default;

void TwoPartExrWriter::SetString(const std::string& name, const std::string& value) {
  for (Imf::Header* h : {&impl_->image_header, &impl_->tensor_header}) {
    h->insert(name, Imf::StringAttribute(value));
  }
}

void TwoPartExrWriter::SetDouble(const std::string& name, double value) {
  for (Imf::Header* h : {&impl_->image_header, &impl_->tensor_header}) {
    h->insert(name, Imf::DoubleAttribute(value));
  }
}

void TwoPartExrWriter::SetInt(const std::string& name, int value) {
  for (Imf::Header* h : {&impl_->image_header, &impl_->tensor_header}) {
    h->insert(name, Imf::IntAttribute(value));
  }
}

void TwoPartExrWriter::AddImageChannel(const std::string& name, const float* base,
                                       size_t x_stride, size_t y_stride) {
  impl_->Insert(impl_->image_header, impl_->image_fb, name, base, x_stride, y_stride);
}

void TwoPartExrWriter::AddImageChannel(const std::string& name, std::vector<float> values) {
  const size_t width = static_cast<size_t>(impl_->image_header.dataWindow().size().x + 1);
  impl_->storage.push_back(std::move(values));
  impl_->Insert(impl_->image_header, impl_->image_fb, name, impl_->storage.back().data(), 1,
                width);
}

void TwoPartExrWriter::AddTensorChannel(const std::string& name, std::vector<float> values) {
  impl_->storage.push_back(std::move(values));
  impl_->Insert(impl_->tensor_header, impl_->tensor_fb, name, impl_->storage.back().data(), 1,
                static_cast<size_t>(impl_->tensor_size));
}

void WriteScanlineExr(const std::string& path, const Imf::Header& header,
                      const Imf::FrameBuffer& frame_buffer, int rows, const std::string& what) {
  Imf::StdOSStream stream;  // encoded in memory, written through basis/atomic_file.h
  try {
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(frame_buffer);
    file.writePixels(rows);
  } catch (const std::exception& e) {
    throw InputError("cannot write " + what + " " + path + ": " + e.what());
  }
  WriteFileAtomically(path, stream.str());
}

void TwoPartExrWriter::Write(const std::string& path, const std::string& what) const {
  const Impl& m = *impl_;
  Imf::StdOSStream stream;  // encoded in memory, written through basis/atomic_file.h
  try {
    const Imf::Header headers[2] = {m.image_header, m.tensor_header};
    Imf::MultiPartOutputFile file(stream, headers, 2);
    Imf::OutputPart image(file, 0);
    image.setFrameBuffer(m.image_fb);
    image.writePixels(m.height);
    Imf::OutputPart tensor(file, 1);
    tensor.setFrameBuffer(m.tensor_fb);
    tensor.writePixels(m.tensor_size);
  } catch (const std::exception& e) {
    throw InputError("cannot write " + what + ": " + e.what());
  }
  WriteFileAtomically(path, stream.str());
}

}  // namespace zbrdf
