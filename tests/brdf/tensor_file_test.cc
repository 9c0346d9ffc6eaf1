// The tensor-file container of .bsdf files.
#include "brdf/tensor_file.h"

#include <gtest/gtest.h>

#include <vector>

#include "basis/error.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(TensorFile, RoundTripAndDamage) {
  testing::TempDir dir("tensor");
  TensorFile file;
  const std::vector<float> values = {1.5f, -2.0f, 3.25f, 0.0f, 1e-20f, 7.0f};
  file["a"] = TensorField::Float32({2, 3}, values);
  const std::vector<uint8_t> bytes = {'h', 'i'};
  file["description"] = TensorField::UInt8({2}, bytes);
  WriteTensorFile(dir.File("t.bsdf"), file);
  const TensorFile back = ReadTensorFile(dir.File("t.bsdf"));
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back.at("a").shape, (std::vector<uint64_t>{2, 3}));
  EXPECT_EQ(back.at("a").AsFloat32("a"), values);
  EXPECT_EQ(back.at("description").bytes, bytes);
  EXPECT_THROW(back.at("description").AsFloat32("description"), InputError);
  // Truncated: the last field's data reaches past the end.
  std::string content = testing::ReadFile(dir.File("t.bsdf"));
  testing::WriteFile(dir.File("short.bsdf"), content.substr(0, content.size() - 5));
  EXPECT_THROW(ReadTensorFile(dir.File("short.bsdf")), InputError);
  content[12] = 2;  // version 2.0
  testing::WriteFile(dir.File("v2.bsdf"), content);
  EXPECT_THROW(ReadTensorFile(dir.File("v2.bsdf")), InputError);
}

// Found by fuzz/tensor_file_fuzz (rgl_bsdf_fuzz): a shape of 2^32 x 2^32 float32 values is
// 2^66 bytes, which wrapped around to 0 and passed the size check; AsFloat32 then threw
// std::length_error. The reader must reject the shape.
TEST(TensorFile, ShapeWhoseSizeOverflowsIsAnInputError) {
  testing::TempDir dir("tensor-overflow");
  std::string bytes("tensor_file\0\1\0", 14);
  auto put = [&](uint64_t value, int size) {
    for (int k = 0; k < size; ++k) bytes.push_back(static_cast<char>(value >> (8 * k)));
  };
  put(1, 4);  // one field
  put(1, 2);
  bytes += "x";
  put(2, 2);   // rank
  put(10, 1);  // float32
  put(0, 8);   // offset
  put(uint64_t{1} << 32, 8);
  put(uint64_t{1} << 32, 8);
  testing::WriteFile(dir.File("overflow.bsdf"), bytes);
  EXPECT_THROW(ReadTensorFile(dir.File("overflow.bsdf")), InputError);
}

// Found by fuzz/tensor_file_fuzz: a field name of length 0 at the very end of the file indexed
// one past the data (a _GLIBCXX_ASSERTIONS abort) before the truncation was noticed.
TEST(TensorFile, EmptyNameAtTheEndIsAnInputError) {
  testing::TempDir dir("tensor-empty-name");
  // One field (count 0x78000001, as the fuzzer had it), a name of length 0, then nothing.
  testing::WriteFile(dir.File("cut.bsdf"), std::string("tensor_file\0\1\0\1\0\0x\0\0", 20));
  EXPECT_THROW(ReadTensorFile(dir.File("cut.bsdf")), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
