#include "brdf/tensor_file.h"

#include <cstring>
#include <fstream>
#include <iterator>

#include "basis/atomic_file.h"
#include "basis/error.h"

namespace zbrdf {
namespace {

constexpr char kMagic[12] = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', '\0'};

void PutLittleEndian(uint64_t value, int bytes, std::string* out) {
  for (int k = 0; k < bytes; ++k) out->push_back(static_cast<char>((value >> (8 * k)) & 0xff));
}

uint64_t GetLittleEndian(const std::vector<uint8_t>& data, size_t* pos, int bytes,
                         const std::string& path) {
  if (*pos + bytes > data.size()) {
    throw InputError("tensor file " + path +
                     ": truncated in the field headers; the file is incomplete or not a .bsdf "
                     "tensor file");
  }
  uint64_t value = 0;
  for (int k = 0; k < bytes; ++k) value |= static_cast<uint64_t>(data[*pos + k]) << (8 * k);
  *pos += bytes;
  return value;
}

}  // namespace

uint64_t TensorField::Count() const {
  uint64_t n = 1;
  for (uint64_t s : shape) n *= s;
  return n;
}

size_t TensorField::TypeSize(Type type) {
  switch (type) {
    case Type::kUInt8:
    case Type::kInt8:
      return 1;
    case Type::kUInt16:
    case Type::kInt16:
    case Type::kFloat16:
      return 2;
    case Type::kUInt32:
    case Type::kInt32:
    case Type::kFloat32:
      return 4;
    case Type::kUInt64:
    case Type::kInt64:
    case Type::kFloat64:
      return 8;
  }
  return 0;
}

TensorField TensorField::Float32(std::vector<uint64_t> shape, std::span<const float> values) {
  TensorField field;
  field.type = Type::kFloat32;
  field.shape = std::move(shape);
  ZBRDF_ASSERT(field.Count() == values.size(), "float32 tensor: shape and value count differ");
  field.bytes.resize(values.size() * 4);
  for (size_t i = 0; i < values.size(); ++i) {
    uint32_t bits;
    std::memcpy(&bits, &values[i], 4);
    for (int k = 0; k < 4; ++k) field.bytes[4 * i + k] = static_cast<uint8_t>(bits >> (8 * k));
  }
  return field;
}

TensorField TensorField::UInt8(std::vector<uint64_t> shape, std::span<const uint8_t> values) {
  TensorField field;
  field.type = Type::kUInt8;
  field.shape = std::move(shape);
  ZBRDF_ASSERT(field.Count() == values.size(), "uint8 tensor: shape and value count differ");
  field.bytes.assign(values.begin(), values.end());
  return field;
}

std::vector<float> TensorField::AsFloat32(const std::string& what) const {
  if (type != Type::kFloat32) {
    throw InputError(what + " must be a float32 array (type 10), but has type " +
                     std::to_string(static_cast<int>(type)));
  }
  std::vector<float> values(Count());
  for (size_t i = 0; i < values.size(); ++i) {
    uint32_t bits = 0;
    for (int k = 0; k < 4; ++k) bits |= static_cast<uint32_t>(bytes[4 * i + k]) << (8 * k);
    std::memcpy(&values[i], &bits, 4);
  }
  return values;
}

void WriteTensorFile(const std::string& path, const TensorFile& tensors) {
  size_t header_size = sizeof(kMagic) + 2 + 4;
  for (const auto& [name, field] : tensors) {
    header_size += 2 + name.size() + 2 + 1 + 8 + 8 * field.shape.size();
  }
  std::string out(kMagic, sizeof(kMagic));
  out.push_back(1);
  out.push_back(0);
  PutLittleEndian(tensors.size(), 4, &out);
  uint64_t offset = (header_size + 7) / 8 * 8;
  std::vector<uint64_t> offsets;
  for (const auto& [name, field] : tensors) {
    ZBRDF_ASSERT(name.size() < 65536 && field.shape.size() < 65536, "tensor field too large");
    ZBRDF_ASSERT(field.bytes.size() == field.Count() * TensorField::TypeSize(field.type),
                 "tensor field " + name + ": data size does not match its shape");
    PutLittleEndian(name.size(), 2, &out);
    out += name;
    PutLittleEndian(field.shape.size(), 2, &out);
    out.push_back(static_cast<char>(field.type));
    PutLittleEndian(offset, 8, &out);
    for (uint64_t s : field.shape) PutLittleEndian(s, 8, &out);
    offsets.push_back(offset);
    offset = (offset + field.bytes.size() + 7) / 8 * 8;
  }
  size_t k = 0;
  for (const auto& [name, field] : tensors) {
    out.resize(offsets[k++], '\0');
    out.append(reinterpret_cast<const char*>(field.bytes.data()), field.bytes.size());
  }
  WriteFileAtomically(path, out);
}

TensorFile ReadTensorFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError("tensor file " + path + ": cannot open it; check the path");
  const std::vector<uint8_t> data((std::istreambuf_iterator<char>(file)),
                                  std::istreambuf_iterator<char>());
  if (data.size() < sizeof(kMagic) + 6 || std::memcmp(data.data(), kMagic, sizeof(kMagic)) != 0) {
    throw InputError("tensor file " + path +
                     ": it does not start with \"tensor_file\"; it is not an RGL .bsdf file");
  }
  if (data[12] != 1 || data[13] != 0) {
    throw InputError("tensor file " + path + ": version " + std::to_string(data[12]) + "." +
                     std::to_string(data[13]) + " is not supported (only 1.0)");
  }
  size_t pos = 14;
  const uint64_t count = GetLittleEndian(data, &pos, 4, path);
  TensorFile tensors;
  for (uint64_t f = 0; f < count; ++f) {
    const size_t name_length = GetLittleEndian(data, &pos, 2, path);
    if (pos + name_length > data.size()) {
      throw InputError("tensor file " + path + ": truncated in a field name");
    }
    const std::string name(reinterpret_cast<const char*>(data.data()) + pos, name_length);
    pos += name_length;
    const size_t rank = GetLittleEndian(data, &pos, 2, path);
    const int type = static_cast<int>(GetLittleEndian(data, &pos, 1, path));
    const uint64_t offset = GetLittleEndian(data, &pos, 8, path);
    if (type < 1 || type > 11) {
      throw InputError("tensor file " + path + ": field '" + name + "' has unknown type " +
                       std::to_string(type));
    }
    TensorField field;
    field.type = static_cast<TensorField::Type>(type);
    // The product of the shape can overflow 64 bits: check each factor against the bytes left,
    // so that a corrupt shape cannot pass as a small (wrapped-around) size.
    uint64_t size = TensorField::TypeSize(field.type);
    for (size_t r = 0; r < rank; ++r) {
      const uint64_t extent = GetLittleEndian(data, &pos, 8, path);
      field.shape.push_back(extent);
      if (size != 0 && extent > data.size() / size) {
        throw InputError("tensor file " + path + ": field '" + name + "' has dimension " +
                         std::to_string(r) + " of " + std::to_string(extent) +
                         ", more values than the file holds; the file is corrupt");
      }
      size *= extent;
    }
    if (offset > data.size() || size > data.size() - offset) {
      throw InputError("tensor file " + path + ": the data of field '" + name +
                       "' reaches past the end of the file; the file is truncated");
    }
    field.bytes.assign(data.begin() + offset, data.begin() + offset + size);
    tensors[name] = std::move(field);
  }
  return tensors;
}

}  // namespace zbrdf
