#include "brdf/exr_writer.h"

#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfDoubleAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfIntAttribute.h>
#include <ImfMultiPartInputFile.h>
#include <ImfStringAttribute.h>

#include <string>
#include <vector>

#include "basis/error.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::TempDir;

// Reads one FLOAT channel of a part with OpenEXR directly.
std::vector<float> ReadChannel(Imf::MultiPartInputFile& file, int part, const std::string& name) {
  const Imath::Box2i window = file.header(part).dataWindow();
  const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
  std::vector<float> values(static_cast<size_t>(width) * height);
  Imf::FrameBuffer fb;
  fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data()), sizeof(float),
                             sizeof(float) * width));
  Imf::InputPart input(file, part);
  input.setFrameBuffer(fb);
  input.readPixels(window.min.y, window.max.y);
  return values;
}

TEST(TwoPartExrWriter, PartsAttributesAndChannelsReadBackWithOpenExr) {
  TempDir dir("exr_writer");
  const int width = 3, height = 2, n = 4;
  // A strided view: two interleaved channels in one buffer, x stride 2, y stride 2 * width.
  const std::vector<float> interleaved = {0, 10, 1, 11, 2, 12, 3, 13, 4, 14, 5, 15};
  std::vector<float> tensor(n * n);
  for (int i = 0; i < n * n; ++i) tensor[i] = 0.5f * i;
  TwoPartExrWriter writer("grid", width, height, "tensor", n);
  writer.SetString("zbrdf.format", "test-v1");
  writer.SetDouble("zbrdf.value", 0.125);
  writer.SetInt("zbrdf.order", 7);
  writer.AddImageChannel("a", interleaved.data(), 2, 2 * width);
  writer.AddImageChannel("b", interleaved.data() + 1, 2, 2 * width);
  writer.AddImageChannel("c", std::vector<float>{6, 7, 8, 9, 10, 11});
  writer.AddTensorChannel("t", tensor);
  const std::string path = dir.File("two.exr");
  writer.Write(path, "test file");

  Imf::MultiPartInputFile file(path.c_str());
  ASSERT_EQ(file.parts(), 2);
  EXPECT_EQ(file.header(0).name(), "grid");
  EXPECT_EQ(file.header(1).name(), "tensor");
  for (int part = 0; part < 2; ++part) {
    const Imf::Header& h = file.header(part);
    EXPECT_EQ(h.findTypedAttribute<Imf::StringAttribute>("zbrdf.format")->value(), "test-v1");
    EXPECT_EQ(h.findTypedAttribute<Imf::DoubleAttribute>("zbrdf.value")->value(), 0.125);
    EXPECT_EQ(h.findTypedAttribute<Imf::IntAttribute>("zbrdf.order")->value(), 7);
    EXPECT_EQ(h.compression(), Imf::ZIP_COMPRESSION);
    EXPECT_EQ(h.dataWindow().min, Imath::V2i(0, 0));
    EXPECT_EQ(h.displayWindow(), file.header(0).displayWindow());
  }
  EXPECT_EQ(file.header(1).dataWindow().max, Imath::V2i(n - 1, n - 1));
  EXPECT_EQ(ReadChannel(file, 0, "a"), (std::vector<float>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(ReadChannel(file, 0, "b"), (std::vector<float>{10, 11, 12, 13, 14, 15}));
  EXPECT_EQ(ReadChannel(file, 0, "c"), (std::vector<float>{6, 7, 8, 9, 10, 11}));
  EXPECT_EQ(ReadChannel(file, 1, "t"), tensor);
}

TEST(TwoPartExrWriter, AnUnwritablePathIsAnInputErrorNamingTheFile) {
  TwoPartExrWriter writer("grid", 1, 1, "tensor", 1);
  writer.AddImageChannel("a", std::vector<float>{1});
  writer.AddTensorChannel("t", std::vector<float>{1});
  try {
    writer.Write("/nonexistent-folder/x.exr", "zonal file x.exr");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    // Written through basis/atomic_file.h, which names the file and what is wrong with it.
    EXPECT_NE(std::string(e.what()).find("cannot write /nonexistent-folder/x.exr: folder "
                                         "/nonexistent-folder does not exist"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
