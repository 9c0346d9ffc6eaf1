#include "brdf/merl_table.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "basis/atomic_file.h"
#include "basis/error.h"

namespace zbrdf {
namespace {

constexpr std::array<double, 3> kScales = {MerlTable::kRedScale, MerlTable::kGreenScale,
                                           MerlTable::kBlueScale};
constexpr std::array<const char*, 3> kMerlChannelNames = {"red", "green", "blue"};
constexpr size_t kMerlHeaderBytes = 3 * sizeof(int32_t);
constexpr size_t kDataBytes = 3 * MerlTable::kBinCount * sizeof(double);

// Little-endian decoding and encoding, whatever the host's byte order.
template <typename T>
T DecodeLittleEndian(const unsigned char* bytes) {
  uint64_t bits = 0;
  for (size_t k = 0; k < sizeof(T); ++k) bits |= static_cast<uint64_t>(bytes[k]) << (8 * k);
  T value;
  if constexpr (sizeof(T) == 4) {
    const uint32_t narrow = static_cast<uint32_t>(bits);
    std::memcpy(&value, &narrow, sizeof(T));
  } else {
    std::memcpy(&value, &bits, sizeof(T));
  }
  return value;
}

template <typename T>
void EncodeLittleEndian(T value, unsigned char* bytes) {
  uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof(T));
  for (size_t k = 0; k < sizeof(T); ++k) bytes[k] = static_cast<unsigned char>(bits >> (8 * k));
}

int Clamp(double index, int bins) {
  // NaN and negatives go to bin 0, like the reference reader's guards.
  if (!(index > 0)) return 0;
  return std::min(static_cast<int>(index), bins - 1);
}

// Right-handed rotation of v about the unit axis a by angle t (Rodrigues):
// v cos t + a (a.v)(1 - cos t) + (a x v) sin t, as MERL's rotate_vector().
Vec3 Rotate(const Vec3& v, const Vec3& a, double t) {
  const double c = std::cos(t), s = std::sin(t);
  return v * c + a * (Dot(a, v) * (1.0 - c)) + Cross(a, v) * s;
}

}  // namespace

MerlBin MerlBinOf(const Vec3& w_i, const Vec3& w_o) {
  const Vec3 h = Normalize(w_i + w_o);
  const double theta_h = std::acos(std::clamp(h.z, -1.0, 1.0));
  const double phi_h = std::atan2(h.y, h.x);
  const Vec3 d = Rotate(Rotate(w_i, {0.0, 0.0, 1.0}, -phi_h), {0.0, 1.0, 0.0}, -theta_h);
  const double theta_d = std::acos(std::clamp(d.z, -1.0, 1.0));
  double phi_d = std::atan2(d.y, d.x);
  if (phi_d < 0) phi_d += M_PI;  // reciprocity: f is unchanged under phi_d -> phi_d + pi
  MerlBin bin;
  bin.theta_half = Clamp(std::sqrt(theta_h / (0.5 * M_PI)) * MerlTable::kThetaHalfBins,
                         MerlTable::kThetaHalfBins);
  bin.theta_diff =
      Clamp(theta_d / (0.5 * M_PI) * MerlTable::kThetaDiffBins, MerlTable::kThetaDiffBins);
  bin.phi_diff = Clamp(phi_d / M_PI * MerlTable::kPhiDiffBins, MerlTable::kPhiDiffBins);
  return bin;
}

MerlTable ReadMerlBinary(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file || !std::filesystem::is_regular_file(path)) {
    throw InputError("MERL file " + path + ": cannot open it" +
                     (std::filesystem::is_directory(path) ? " (a folder)" : "") +
                     "; check the path and permissions");
  }
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(file)),
                                   std::istreambuf_iterator<char>());
  if (bytes.size() < kMerlHeaderBytes) {
    throw InputError("MERL file " + path + ": truncated: " + std::to_string(bytes.size()) +
                     " bytes, too short for the 12-byte header of three int32 dimensions");
  }
  const std::array<int32_t, 3> dims = {DecodeLittleEndian<int32_t>(&bytes[0]),
                                       DecodeLittleEndian<int32_t>(&bytes[4]),
                                       DecodeLittleEndian<int32_t>(&bytes[8])};
  if (dims[0] != MerlTable::kThetaHalfBins || dims[1] != MerlTable::kThetaDiffBins ||
      dims[2] != MerlTable::kPhiDiffBins) {
    throw InputError("MERL file " + path + ": dimensions are " + std::to_string(dims[0]) + " " +
                     std::to_string(dims[1]) + " " + std::to_string(dims[2]) +
                     ", expected 90 90 180; it is not an isotropic MERL .binary table");
  }
  const size_t data_bytes = bytes.size() - kMerlHeaderBytes;
  if (data_bytes < kDataBytes) {
    throw InputError("MERL file " + path + ": truncated: " + std::to_string(data_bytes) +
                     " bytes of data, expected " + std::to_string(kDataBytes) +
                     " (3 x 90 x 90 x 180 float64); the file is incomplete");
  }
  if (data_bytes > kDataBytes) {
    throw InputError("MERL file " + path + ": " + std::to_string(data_bytes - kDataBytes) +
                     " unexpected bytes after the " + std::to_string(kDataBytes) +
                     " bytes of data; the file is corrupt or not a MERL .binary table");
  }
  MerlTable table;
  table.f.resize(MerlTable::kBinCount);
  const unsigned char* data = bytes.data() + kMerlHeaderBytes;
  for (int channel = 0; channel < 3; ++channel) {
    for (size_t k = 0; k < MerlTable::kBinCount; ++k) {
      const double stored =
          DecodeLittleEndian<double>(data + (channel * MerlTable::kBinCount + k) * sizeof(double));
      if (!std::isfinite(stored)) {
        throw InputError("MERL file " + path + ": the " + kMerlChannelNames[channel] +
                         " value of bin " + std::to_string(k) +
                         " is not a finite number; the file is corrupt");
      }
      table.f[k][channel] = stored * kScales[channel];
    }
  }
  return table;
}

void WriteMerlBinary(const std::string& path, const MerlTable& table) {
  if (table.f.size() != MerlTable::kBinCount) {
    throw InputError("WriteMerlBinary " + path + ": the table has " +
                     std::to_string(table.f.size()) +
                     " bins, expected 90 x 90 x 180 = " + std::to_string(MerlTable::kBinCount));
  }
  std::vector<unsigned char> bytes(kMerlHeaderBytes + kDataBytes);
  EncodeLittleEndian<int32_t>(MerlTable::kThetaHalfBins, &bytes[0]);
  EncodeLittleEndian<int32_t>(MerlTable::kThetaDiffBins, &bytes[4]);
  EncodeLittleEndian<int32_t>(MerlTable::kPhiDiffBins, &bytes[8]);
  unsigned char* data = bytes.data() + kMerlHeaderBytes;
  for (int channel = 0; channel < 3; ++channel) {
    for (size_t k = 0; k < MerlTable::kBinCount; ++k) {
      EncodeLittleEndian<double>(table.f[k][channel] / kScales[channel],
                                 data + (channel * MerlTable::kBinCount + k) * sizeof(double));
    }
  }
  WriteFileAtomically(path, std::string(bytes.begin(), bytes.end()));
}

MerlBrdf::MerlBrdf(MerlTable table, std::string spec)
    : table_(std::move(table)), spec_(std::move(spec)) {
  if (table_.f.size() != MerlTable::kBinCount) {
    throw InputError("MERL table " + spec_ + ": has " + std::to_string(table_.f.size()) +
                     " bins, expected " + std::to_string(MerlTable::kBinCount));
  }
  for (const Rgb& f : table_.f) {
    invalid_entry_count_ += (f.r < 0) + (f.g < 0) + (f.b < 0);
  }
  FitProxySampler();
}

std::unique_ptr<MerlBrdf> MerlBrdf::FromFile(const std::string& path) {
  return std::make_unique<MerlBrdf>(ReadMerlBinary(path), "file:" + path);
}

Rgb MerlBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  const MerlBin bin = MerlBinOf(w_i, w_o);
  const Rgb& f = table_.f[MerlTable::Index(bin.theta_half, bin.theta_diff, bin.phi_diff)];
  return {std::max(f.r, 0.0), std::max(f.g, 0.0), std::max(f.b, 0.0)};
}

}  // namespace zbrdf
