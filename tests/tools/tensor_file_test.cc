// The tensor-file container of .bsdf files.
#include "tools/tensor_file.h"

#include <gtest/gtest.h>

#include <vector>

#include "basis/error.h"
#include "tools_test_util.h"

namespace zbrdf {
namespace {

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

}  // namespace
}  // namespace zbrdf
