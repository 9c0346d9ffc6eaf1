#include "brdf/brdf_prior.h"

#include <cmath>
#include <set>
#include <sstream>

#include <Imath/half.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>

#include "basis/atomic_file.h"
#include "basis/data_path.h"
#include "basis/error.h"
#include "brdf/exr_writer.h"
#include "basis/hash.h"
#include "brdf/exr_header.h"

namespace zbrdf {
namespace {

constexpr char kPriorFormat[] = "zbrdf-prior-v1";
// Largest finite half is 65504; atoms above this are scaled down by a per-atom factor.
constexpr double kHalfCeiling = 60000.0;

}  // namespace

uint64_t BrdfPrior::Hash() const {
  uint64_t h = kFnv1a64Offset;
  const int dims[3] = {grid.theta_h_nodes(), grid.theta_d_nodes(), grid.phi_d_nodes()};
  h = Fnv1a64(dims, sizeof(dims), h);
  for (const std::string& m : materials) h = Fnv1a64(m + '\n', h);
  return Fnv1a64(atoms.data(), sizeof(float) * static_cast<size_t>(atoms.size()), h);
}

int BrdfPrior::MaterialIndex(const std::string& name) const {
  for (size_t k = 0; k < materials.size(); ++k) {
    if (materials[k] == name) return static_cast<int>(k);
  }
  return -1;
}

std::vector<float> PriorAtoms(const PriorSource& s, const HalfDiffGrid& grid) {
  const std::vector<Rgb> table = TabulateBrdf(*s.brdf, grid);
  const size_t n_nodes = static_cast<size_t>(grid.size());
  std::vector<float> atoms(3 * n_nodes);
  Rgb sum;
  for (size_t n = 0; n < n_nodes; ++n) {
    if (!table[n].IsFinite()) {
      throw InputError("prior: material " + s.name + " (" + s.source +
                       ") evaluates to a non-finite value; it cannot enter a prior");
    }
    for (int c = 0; c < 3; ++c) atoms[c * n_nodes + n] = static_cast<float>(std::max(0.0, table[n][c]));
    sum += table[n];
  }
  if (!(sum.Max() > 0)) {
    throw InputError("prior: material " + s.name + " (" + s.source +
                     ") is zero everywhere; it cannot enter a prior");
  }
  return atoms;
}

BrdfPrior AssemblePrior(const HalfDiffGrid& grid, const std::vector<std::string>& names,
                        const std::vector<std::string>& sources,
                        const std::vector<std::vector<float>>& atoms) {
  if (names.empty()) throw InputError("prior: no materials to build it from");
  if (sources.size() != names.size() || atoms.size() != names.size()) {
    throw InputError("prior: names, sources and atoms disagree in count");
  }
  std::set<std::string> seen;
  for (size_t k = 0; k < names.size(); ++k) {
    if (!seen.insert(names[k]).second) {
      throw InputError("prior: material name " + names[k] + " appears twice (" + sources[k] +
                       "); names identify the materials a fit may leave out");
    }
  }
  const size_t n_nodes = static_cast<size_t>(grid.size());
  BrdfPrior prior{grid, names, sources, Eigen::MatrixXf(grid.size(), 3 * names.size()), {}};
  for (size_t k = 0; k < names.size(); ++k) {
    if (atoms[k].size() != 3 * n_nodes) {
      throw InputError("prior: material " + names[k] + " has " + std::to_string(atoms[k].size()) +
                       " atom values, the grid " + grid.ToString() + " needs " +
                       std::to_string(3 * n_nodes));
    }
    for (int c = 0; c < 3; ++c) {
      for (size_t n = 0; n < n_nodes; ++n) prior.atoms(n, 3 * k + c) = atoms[k][c * n_nodes + n];
    }
  }
  prior.info = {{"grid", grid.ToString()},
                {"materials", prior.material_count()},
                {"symmetrized", "mean of phi_d and pi - phi_d; reciprocal by the fold"}};
  return prior;
}

BrdfPrior BuildPrior(const std::vector<PriorSource>& sources, const HalfDiffGrid& grid,
                     const ProgressCallback& progress) {
  if (sources.empty()) throw InputError("prior: no materials to build it from");
  std::set<std::string> names;
  for (const PriorSource& s : sources) {
    if (!names.insert(s.name).second) {
      throw InputError("prior: material name " + s.name + " appears twice (" + s.source +
                       "); names identify the materials a fit may leave out");
    }
  }
  std::vector<std::string> material_names, material_sources;
  std::vector<std::vector<float>> atoms;
  for (size_t k = 0; k < sources.size(); ++k) {
    atoms.push_back(PriorAtoms(sources[k], grid));
    material_names.push_back(sources[k].name);
    material_sources.push_back(sources[k].source);
    Report(progress, {"prior", static_cast<long>(k + 1), static_cast<long>(sources.size()),
                      "materials"});
  }
  return AssemblePrior(grid, material_names, material_sources, atoms);
}

void WritePriorFile(const std::string& path, const BrdfPrior& prior) {
  const int width = prior.grid.size(), height = static_cast<int>(prior.atoms.cols());
  if (prior.atoms.rows() != width || height != 3 * prior.material_count()) {
    throw InputError("cannot write prior " + path + ": atom matrix is " +
                     std::to_string(prior.atoms.rows()) + " x " +
                     std::to_string(prior.atoms.cols()) + ", expected " + std::to_string(width) +
                     " x " + std::to_string(3 * prior.material_count()));
  }
  nlohmann::json atoms = nlohmann::json::array();
  std::vector<half> data(static_cast<size_t>(width) * height);
  for (int a = 0; a < height; ++a) {
    const double max = prior.atoms.col(a).maxCoeff();
    const double scale = max > kHalfCeiling ? max / kHalfCeiling : 1.0;
    for (int n = 0; n < width; ++n) {
      data[static_cast<size_t>(a) * width + n] = half(static_cast<float>(prior.atoms(n, a) / scale));
    }
    atoms.push_back({{"material", prior.materials[a / 3]},
                     {"channel", kRgbChannelNames[a % 3]},
                     {"scale", scale},
                     {"source", prior.sources[a / 3]}});
  }
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  header.insert("zbrdf.format", Imf::StringAttribute(kPriorFormat));
  header.insert("zbrdf.grid", Imf::StringAttribute(std::to_string(prior.grid.theta_h_nodes()) +
                                                   " " + std::to_string(prior.grid.theta_d_nodes()) +
                                                   " " + std::to_string(prior.grid.phi_d_nodes())));
  header.insert("zbrdf.atoms", Imf::StringAttribute(atoms.dump()));
  header.insert("zbrdf.info", Imf::StringAttribute(prior.info.dump()));
  header.channels().insert("f", Imf::Channel(Imf::HALF));
  Imf::FrameBuffer fb;
  fb.insert("f", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(data.data()), sizeof(half),
                            sizeof(half) * width));
  WriteScanlineExr(path, header, fb, height, "prior");
}

BrdfPrior ReadPriorFile(const std::string& path) {
  const std::string what = "prior file " + path;
  CheckExrHeaderSizes(path, what);
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& h = file.header();
    auto text = [&](const char* name) {
      const auto* a = h.findTypedAttribute<Imf::StringAttribute>(name);
      if (!a) throw InputError(what + ": header attribute " + name + " is missing");
      return a->value();
    };
    if (const auto* f = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.format");
        !f || f->value() != kPriorFormat) {
      throw InputError(path + " is not a zbrdf prior (zbrdf.format is not " +
                       std::string(kPriorFormat) + "); `zbrdf prior build` writes one");
    }
    std::istringstream dims(text("zbrdf.grid"));
    int nh = 0, nd = 0, np = 0;
    if (!(dims >> nh >> nd >> np)) {
      throw InputError(what + ": zbrdf.grid must hold three node counts");
    }
    const HalfDiffGrid grid = [&] {
      try {
        return HalfDiffGrid(nh, nd, np);
      } catch (const InputError& e) {  // its message does not name the file
        throw InputError(what + ": " + e.what());
      }
    }();
    const nlohmann::json atoms = nlohmann::json::parse(text("zbrdf.atoms"), nullptr, false);
    if (!atoms.is_array() || atoms.empty() || atoms.size() % 3 != 0) {
      throw InputError(what + ": zbrdf.atoms must be a JSON list of 3 atoms per material");
    }
    const Imath::Box2i window = h.dataWindow();
    RequireWindowAtOrigin(window.min.x, window.min.y, window.max.x, window.max.y, what, "atoms");
    const int width = window.max.x + 1, height = window.max.y + 1;
    if (width != grid.size() || height != static_cast<int>(atoms.size())) {
      throw InputError(what + ": the image is " + std::to_string(width) + " x " +
                       std::to_string(height) + ", the header describes " +
                       std::to_string(grid.size()) + " x " + std::to_string(atoms.size()));
    }
    if (!h.channels().findChannel("f")) throw InputError(what + ": channel f is missing");
    BrdfPrior prior{grid, {}, {}, Eigen::MatrixXf(width, height), nlohmann::json::object()};
    if (const auto* info = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.info")) {
      prior.info = nlohmann::json::parse(info->value(), nullptr, false);
      if (prior.info.is_discarded()) throw InputError(what + ": zbrdf.info is not valid JSON");
    }
    std::vector<half> data(static_cast<size_t>(width) * height);
    Imf::FrameBuffer fb;
    fb.insert("f", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(data.data()), sizeof(half),
                              sizeof(half) * width));
    file.setFrameBuffer(fb);
    file.readPixels(0, height - 1);
    for (int a = 0; a < height; ++a) {
      const nlohmann::json& atom = atoms[a];
      if (!atom.is_object() || !atom.contains("material") || !atom["material"].is_string() ||
          !atom.contains("scale") || !atom["scale"].is_number()) {
        throw InputError(what + ": atom " + std::to_string(a) +
                         " lacks a material name or a numeric scale");
      }
      const double scale = atom["scale"].get<double>();
      if (!(scale > 0) || !std::isfinite(scale)) {
        throw InputError(what + ": atom " + std::to_string(a) + " has scale " +
                         std::to_string(scale) + "; it must be finite and > 0");
      }
      if (a % 3 == 0) {
        prior.materials.push_back(atom["material"].get<std::string>());
        prior.sources.push_back(atom.value("source", std::string()));
      } else if (atom["material"].get<std::string>() != prior.materials.back()) {
        throw InputError(what + ": atoms " + std::to_string(a - a % 3) + "-" +
                         std::to_string(a - a % 3 + 2) + " must be one material's R, G, B");
      }
      for (int n = 0; n < width; ++n) {
        const float v = static_cast<float>(data[static_cast<size_t>(a) * width + n]) * scale;
        if (!std::isfinite(v) || v < 0) {
          throw InputError(what + ": atom " + std::to_string(a) + " (" +
                           prior.materials.back() + ") has value " + std::to_string(v) +
                           " at node " + std::to_string(n) + "; values must be finite and >= 0");
        }
        prior.atoms(n, a) = v;
      }
    }
    return prior;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read " + what + ": " + e.what());
  }
}

std::string DefaultPriorPath() { return DataPath("data/priors/merl100.exr"); }

}  // namespace zbrdf
