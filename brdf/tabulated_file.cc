#include "brdf/tabulated_file.h"

#include <sstream>
#include <vector>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "brdf/exr_writer.h"
#include "brdf/exr_header.h"

namespace zbrdf {
namespace {

constexpr char kTabulatedFormat[] = "zbrdf-tabulated-v1";
constexpr char kTabulatedModel[] =
    "isotropic f_r in 1/sr at nodes of (theta_h, theta_d, phi_d) (Rusinkiewicz 1998, MERL's "
    "rotation convention): theta_h = (pi/2) (ih/(nh-1))^2, theta_d = (pi/2) id/(nd-1), phi_d = "
    "(pi/2) ip/(np-1), phi_d folded into [0, pi/2] by reciprocity and bilateral symmetry; "
    "trilinear in (sqrt(theta_h), theta_d, phi_d); pixel (ip, ih*nd + id)";
constexpr const char* kSigma[3] = {"sigma.R", "sigma.G", "sigma.B"};

struct TabulatedContents {
  std::unique_ptr<HalfDiffGrid> grid;
  std::vector<Rgb> values, sigma;
  nlohmann::json info = nlohmann::json::object();
};

TabulatedContents Read(const std::string& path, bool pixels) {
  const std::string what = "tabulated BRDF file " + path;
  CheckExrHeaderSizes(path, what);
  TabulatedContents out;
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& h = file.header();
    const auto* format = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.format");
    if (!format || format->value() != kTabulatedFormat) {
      throw InputError(path + " is not a zbrdf tabulated BRDF file (zbrdf.format is not " +
                       std::string(kTabulatedFormat) + ")");
    }
    const auto* grid = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.grid");
    if (!grid) throw InputError(what + ": header attribute zbrdf.grid is missing");
    std::istringstream dims(grid->value());
    int nh = 0, nd = 0, np = 0;
    if (!(dims >> nh >> nd >> np)) throw InputError(what + ": zbrdf.grid must hold three counts");
    try {
      out.grid = std::make_unique<HalfDiffGrid>(nh, nd, np);
    } catch (const InputError& e) {  // its message does not name the file
      throw InputError(what + ": " + e.what());
    }
    if (const auto* info = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.info")) {
      out.info = nlohmann::json::parse(info->value(), nullptr, false);
      if (out.info.is_discarded()) throw InputError(what + ": zbrdf.info is not valid JSON");
    }
    if (!pixels) return out;
    const Imath::Box2i window = h.dataWindow();
    RequireWindowAtOrigin(window.min.x, window.min.y, window.max.x, window.max.y, what, "table");
    const int width = window.max.x + 1, height = window.max.y + 1;
    if (width != np || height != nh * nd) {
      throw InputError(what + ": the image is " + std::to_string(width) + " x " +
                       std::to_string(height) + ", the grid " + out.grid->ToString() +
                       " needs " + std::to_string(np) + " x " + std::to_string(nh * nd));
    }
    const bool has_sigma = h.channels().findChannel(kSigma[0]) != nullptr;
    const size_t count = static_cast<size_t>(width) * height;
    std::vector<std::vector<float>> planes(has_sigma ? 6 : 3, std::vector<float>(count));
    Imf::FrameBuffer fb;
    for (size_t p = 0; p < planes.size(); ++p) {
      const char* name = p < 3 ? kRgbChannelNames[p] : kSigma[p - 3];
      if (!h.channels().findChannel(name)) throw InputError(what + ": channel " + name + " is missing");
      fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes[p].data()),
                                 sizeof(float), sizeof(float) * width));
    }
    file.setFrameBuffer(fb);
    file.readPixels(0, height - 1);
    out.values.resize(count);
    if (has_sigma) out.sigma.resize(count);
    for (size_t n = 0; n < count; ++n) {
      out.values[n] = {planes[0][n], planes[1][n], planes[2][n]};
      if (has_sigma) out.sigma[n] = {planes[3][n], planes[4][n], planes[5][n]};
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read " + what + ": " + e.what());
  }
  return out;
}

}  // namespace

void WriteTabulatedFile(const std::string& path, const TabulatedBrdf& brdf,
                        const nlohmann::json& info) {
  const HalfDiffGrid& grid = brdf.grid();
  const int width = grid.phi_d_nodes(), height = grid.theta_h_nodes() * grid.theta_d_nodes();
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  header.insert("zbrdf.format", Imf::StringAttribute(kTabulatedFormat));
  header.insert("zbrdf.grid", Imf::StringAttribute(std::to_string(grid.theta_h_nodes()) + " " +
                                                   std::to_string(grid.theta_d_nodes()) + " " +
                                                   std::to_string(grid.phi_d_nodes())));
  header.insert("zbrdf.model", Imf::StringAttribute(kTabulatedModel));
  header.insert("zbrdf.info", Imf::StringAttribute(info.dump()));
  const bool has_sigma = !brdf.sigma().empty();
  std::vector<std::vector<float>> planes(has_sigma ? 6 : 3, std::vector<float>(grid.size()));
  for (int n = 0; n < grid.size(); ++n) {
    for (int c = 0; c < 3; ++c) {
      planes[c][n] = static_cast<float>(brdf.values()[n][c]);
      if (has_sigma) planes[3 + c][n] = static_cast<float>(brdf.sigma()[n][c]);
    }
  }
  Imf::FrameBuffer fb;
  for (size_t p = 0; p < planes.size(); ++p) {
    const char* name = p < 3 ? kRgbChannelNames[p] : kSigma[p - 3];
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes[p].data()),
                               sizeof(float), sizeof(float) * width));
  }
  WriteScanlineExr(path, header, fb, height, "tabulated BRDF file");
}

std::unique_ptr<TabulatedBrdf> ReadTabulatedFile(const std::string& path, const std::string& spec) {
  TabulatedContents c = Read(path, true);
  try {
    return std::make_unique<TabulatedBrdf>(*c.grid, std::move(c.values), std::move(c.sigma),
                                           spec.empty() ? "file:" + path : spec);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
}

nlohmann::json ReadTabulatedFileInfo(const std::string& path) { return Read(path, false).info; }

}  // namespace zbrdf
