#include "brdf/dbrdf_file.h"

#include <cmath>
#include <vector>

#include <ImfChannelList.h>
#include <ImfDoubleAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>
#include <ImfVecAttribute.h>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "brdf/exr_writer.h"
#include "brdf/exr_header.h"

namespace zbrdf {
namespace {

constexpr char kDBrdfFormat[] = "zbrdf-dbrdf-v1";
constexpr char kDBrdfModel[] =
    "f_r = c p(h) F(w_i.h) / (w_i.n + w_o.n - (w_i.n)(w_o.n)) + kd / pi; "
    "F = F0 + (1 - F0) (1 - w_i.h)^5; p at theta_h = y (pi/2) / (height - 1), "
    "phi_h = x 2 pi / width, linear in between";

Imath::V3d ToV3d(const Rgb& c) { return {c.r, c.g, c.b}; }
Rgb FromV3d(const Imath::V3d& v) { return {v.x, v.y, v.z}; }

}  // namespace

void WriteDBrdfFile(const std::string& path, const DBrdf& model, const nlohmann::json& info) {
  const HalfVectorTable& table = model.table();
  Imf::Header header(table.phi_samples, table.theta_samples);
  header.compression() = Imf::ZIP_COMPRESSION;
  header.insert("zbrdf.format", Imf::StringAttribute(kDBrdfFormat));
  header.insert("zbrdf.model", Imf::StringAttribute(kDBrdfModel));
  header.insert("zbrdf.c", Imf::V3dAttribute(ToV3d(model.c())));
  header.insert("zbrdf.F0", Imf::DoubleAttribute(model.f0()));
  header.insert("zbrdf.kd", Imf::V3dAttribute(ToV3d(model.kd())));
  header.insert("zbrdf.theta_samples", Imf::IntAttribute(table.theta_samples));
  header.insert("zbrdf.phi_samples", Imf::IntAttribute(table.phi_samples));
  header.insert("zbrdf.info", Imf::StringAttribute(info.dump()));
  header.channels().insert("p", Imf::Channel(Imf::FLOAT));
  std::vector<float> p(table.p.begin(), table.p.end());
  Imf::FrameBuffer fb;
  fb.insert("p", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(p.data()), sizeof(float),
                            sizeof(float) * table.phi_samples));
  WriteScanlineExr(path, header, fb, table.theta_samples, "D-BRDF file");
}

namespace {

struct DBrdfContents {
  DBrdfParams params;
  nlohmann::json info = nlohmann::json::object();
};

DBrdfContents ReadContents(const std::string& path) {
  DBrdfContents out;
  CheckExrHeaderSizes(path, path);
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& h = file.header();
    const auto* format = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.format");
    if (!format || format->value() != kDBrdfFormat) {
      throw InputError(path + " is not a zbrdf D-BRDF file (zbrdf.format is not " +
                       std::string(kDBrdfFormat) + ")");
    }
    auto v3 = [&](const char* name) {
      const auto* a = h.findTypedAttribute<Imf::V3dAttribute>(name);
      if (!a) throw InputError(path + ": header attribute " + name + " is missing");
      return FromV3d(a->value());
    };
    const auto* f0 = h.findTypedAttribute<Imf::DoubleAttribute>("zbrdf.F0");
    if (!f0) throw InputError(path + ": header attribute zbrdf.F0 is missing");
    out.params.c = v3("zbrdf.c");
    out.params.kd = v3("zbrdf.kd");
    out.params.f0 = f0->value();
    if (const auto* info = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.info")) {
      out.info = nlohmann::json::parse(info->value(), nullptr, false);
      if (out.info.is_discarded()) {
        throw InputError(path + ": header attribute zbrdf.info is not valid JSON");
      }
    }
    const Imath::Box2i window = h.dataWindow();
    RequireWindowAtOrigin(window.min.x, window.min.y, window.max.x, window.max.y,
                          "D-BRDF file " + path, "p table");
    const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
    if (!h.channels().findChannel("p")) throw InputError(path + ": channel p is missing");
    std::vector<float> p(static_cast<size_t>(width) * height);
    Imf::FrameBuffer fb;
    char* base = reinterpret_cast<char*>(p.data()) -
                 (static_cast<ptrdiff_t>(window.min.y) * width + window.min.x) * sizeof(float);
    fb.insert("p", Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * width));
    file.setFrameBuffer(fb);
    file.readPixels(window.min.y, window.max.y);
    out.params.p_h.theta_samples = height;
    out.params.p_h.phi_samples = width;
    out.params.p_h.p.assign(p.begin(), p.end());
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read D-BRDF file " + path + ": " + e.what());
  }
  if (const std::string problems = out.params.p_h.Problems(); !problems.empty()) {
    throw InputError(path + ": " + problems);
  }
  return out;
}

}  // namespace

std::unique_ptr<DBrdf> ReadDBrdfFile(const std::string& path) {
  DBrdfContents contents = ReadContents(path);
  DBrdfParams& params = contents.params;
  const double integral = params.p_h.NormalizationIntegral();
  if (!(integral > 0) || !std::isfinite(integral)) {
    throw InputError(path + ": p(h) is zero everywhere; the file holds no distribution");
  }
  params.p_h.Normalize();
  params.c = params.c * integral;
  try {
    return std::make_unique<DBrdf>(std::move(params));
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
}

nlohmann::json ReadDBrdfFileInfo(const std::string& path) { return ReadContents(path).info; }

}  // namespace zbrdf
