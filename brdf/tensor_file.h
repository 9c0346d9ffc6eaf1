// The "tensor_file" container of the RGL material database (.bsdf files; Dupuy & Jakob 2018),
// as Mitsuba 3's TensorFile and pbrt-v4's measured BxDF read it: named n-dimensional arrays.
//
// Layout, all integers little-endian:
//   12 bytes  "tensor_file" and a NUL
//   2 bytes   version: major 1, minor 0
//   uint32    number of fields
//   per field: uint16 name length, the name (no NUL), uint16 rank, uint8 type, uint64 offset of
//              the data from the start of the file, rank x uint64 shape
//   the data of each field: product(shape) values, C order (last index fastest)
// Types: 1 uint8, 2 int8, 3 uint16, 4 int16, 5 uint32, 6 int32, 7 uint64, 8 int64, 9 float16,
// 10 float32, 11 float64. The writer aligns every field's data to 8 bytes.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace zbrdf {

struct TensorField {
  enum class Type : uint8_t {
    kUInt8 = 1,
    kInt8,
    kUInt16,
    kInt16,
    kUInt32,
    kInt32,
    kUInt64,
    kInt64,
    kFloat16,
    kFloat32,
    kFloat64
  };
  Type type = Type::kFloat32;
  std::vector<uint64_t> shape;
  std::vector<uint8_t> bytes;  // the raw values, little-endian

  uint64_t Count() const;
  static size_t TypeSize(Type type);

  static TensorField Float32(std::vector<uint64_t> shape, std::span<const float> values);
  static TensorField UInt8(std::vector<uint64_t> shape, std::span<const uint8_t> values);
  // The values of a float32 field. Throws InputError naming `what` for another type.
  std::vector<float> AsFloat32(const std::string& what) const;
};

// Fields by name.
using TensorFile = std::map<std::string, TensorField>;

// Writes the file atomically (temporary file and rename). Throws InputError if it cannot.
void WriteTensorFile(const std::string& path, const TensorFile& tensors);

// Reads every field. Throws InputError naming the file and the problem: not a tensor file, an
// unknown version or type, a field that reaches past the end of the file.
TensorFile ReadTensorFile(const std::string& path);

}  // namespace zbrdf
