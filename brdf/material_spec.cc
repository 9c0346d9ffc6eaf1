#include "brdf/material_spec.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <optional>
#include <utility>

#include "basis/error.h"
#include "basis/strings.h"
#include "brdf/ashikhmin_shirley.h"
#include "brdf/blinn_phong.h"
#include "brdf/brdf_file.h"
#include "brdf/tabulated_file.h"
#include "brdf/dbrdf.h"
#include "brdf/ggx.h"
#include "brdf/lambertian.h"
#include "brdf/merl_table.h"
#include "brdf/mirror.h"
#include "brdf/model_parameters.h"
#include "brdf/nbrdf.h"
#include "brdf/retro.h"
#include "brdf/rgl_bsdf.h"
#include "brdf/ward.h"

namespace zbrdf {
namespace {

struct ModelInfo {
  const char* name;
  std::vector<const char*> keys;  // canonical spelling, in help order
  const char* positional_key;     // the key of values given before any key=, or nullptr
  const char* help;
};

const std::vector<ModelInfo>& Models() {
  static const std::vector<ModelInfo> models = {
      {"lambert", {"albedo"}, "albedo", "lambert:albedo=A  (or lambert:A)  f = A/pi"},
      {"blinn-phong",
       {"kd", "ks", "n"},
       nullptr,
       "blinn-phong:kd=0,ks=KS,n=N  normalized Blinn-Phong"},
      {"ward",
       {"rho_d", "rho_s", "alpha", "alpha_x", "alpha_y"},
       nullptr,
       "ward:rho_d=0,rho_s=RS,alpha_x=AX,alpha_y=AY  (alpha=A for both)  Ward 1992"},
      {"as",
       {"rd", "rs", "nu", "nv"},
       nullptr,
       "as:rd=0,rs=RS,nu=NU,nv=NV  Ashikhmin-Shirley 2000"},
      {"ggx",
       {"alpha", "alpha_x", "alpha_y", "F0", "kd"},
       nullptr,
       "ggx:alpha=A,F0=0.04,kd=0  (or alpha_x=..,alpha_y=..)  GGX microfacet + Lambert"},
      {"dbrdf",
       {"c", "F0", "kd", "theta_samples", "phi_samples", "p"},
       nullptr,
       "dbrdf:c=1,F0=0.04,kd=0,theta_samples=N,phi_samples=1,p=P0,P1,..  D-BRDF, p(h) tabulated"},
      {"mirror", {"R"}, "R", "mirror:R=R  (or mirror:R)  perfect mirror"},
      {"retro",
       {"kd", "kr", "n"},
       nullptr,
       "retro:kd=0,kr=KR,n=N  retro-reflective cosine lobe about w_o + Lambert"},
      {"merl", {}, nullptr, "merl:NAME  bundled measured material (network), names below"},
      {"rgl", {}, nullptr,
       "rgl:NAME  bundled material of the RGL database (another device; data/materials/rgl)"},
      {"file", {}, nullptr,
       "file:PATH.binary  MERL table;  .json  network;  .bsdf  RGL file;  .exr  tabulated fit"},
      {"target", {}, nullptr,
       "target:white|graycard|mirror  calibration targets: 95% white, 18% gray, mirror R 0.92"},
  };
  return models;
}

std::string Trim(const std::string& text) {
  const auto begin = text.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  const auto end = text.find_last_not_of(" \t");
  return text.substr(begin, end - begin + 1);
}

std::string JoinModelNames() {
  std::string names;
  for (const ModelInfo& model : Models()) {
    names += (names.empty() ? "" : ", ") + std::string(model.name);
  }
  return names;
}

// The parameters of an analytic model's spec, checked against the model's keys as they are read.
class Parameters {
 public:
  Parameters(const std::string& spec, const ModelInfo& model, const std::string& text)
      : spec_(spec), model_(model) {
    size_t start = 0;
    while (start <= text.size()) {
      const size_t comma = std::min(text.find(',', start), text.size());
      AddToken(Trim(text.substr(start, comma - start)));
      start = comma + 1;
    }
  }

  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError("material '" + spec_ + "': " + what);
  }

  bool Has(const std::string& key) const { return Find(key) != nullptr; }

  double Scalar(const std::string& key, std::optional<double> fallback = std::nullopt) const {
    const std::vector<double>* values = Find(key);
    if (values == nullptr) return Required(key, fallback);
    if (values->size() != 1) {
      Fail(key + " takes one value (got " + std::to_string(values->size()) + ")");
    }
    return values->front();
  }

  int Integer(const std::string& key, std::optional<int> fallback = std::nullopt) const {
    const double value = Scalar(key, fallback ? std::optional<double>(*fallback) : std::nullopt);
    if (value != std::floor(value) || std::abs(value) > 1e9) {
      Fail(key + " must be a whole number (got " + FormatDouble(value) + ")");
    }
    return static_cast<int>(value);
  }

  Rgb Color(const std::string& key, std::optional<double> fallback = std::nullopt) const {
    const std::vector<double>* values = Find(key);
    if (values == nullptr) return Rgb(Required(key, fallback));
    if (values->size() == 1) return Rgb(values->front());
    if (values->size() == 3) return Rgb((*values)[0], (*values)[1], (*values)[2]);
    Fail(key + " takes one value (gray) or three (r,g,b), got " + std::to_string(values->size()));
  }

  std::vector<double> List(const std::string& key) const {
    const std::vector<double>* values = Find(key);
    if (values == nullptr) FailMissing(key);
    return *values;
  }

 private:
  std::string ValidKeys() const {
    std::string keys;
    for (const char* key : model_.keys) keys += (keys.empty() ? "" : ", ") + std::string(key);
    return keys;
  }

  [[noreturn]] void FailMissing(const std::string& key) const {
    Fail("missing parameter " + key + " for " + model_.name + "; " + model_.help);
  }

  double Required(const std::string& key, std::optional<double> fallback) const {
    if (!fallback) FailMissing(key);
    return *fallback;
  }

  const std::vector<double>* Find(const std::string& key) const {
    for (const auto& [name, values] : entries_) {
      if (name == key) return &values;
    }
    return nullptr;
  }

  void AddToken(const std::string& token) {
    if (token.empty()) {
      Fail(std::string("empty value in the parameters of ") + model_.name +
           " (two commas in a row, or a trailing comma?)");
    }
    const size_t equals = token.find('=');
    std::string value_text = token;
    if (equals != std::string::npos) {
      const std::string key = AsciiLower(Trim(token.substr(0, equals)));
      const auto known = std::find_if(model_.keys.begin(), model_.keys.end(),
                                      [&](const char* k) { return AsciiLower(k) == key; });
      if (known == model_.keys.end()) {
        Fail("unknown parameter '" + Trim(token.substr(0, equals)) + "' for " + model_.name +
             "; valid: " + ValidKeys());
      }
      if (Has(*known)) Fail(std::string("parameter ") + *known + " is given twice");
      entries_.emplace_back(*known, std::vector<double>());
      value_text = Trim(token.substr(equals + 1));
      if (value_text.empty()) Fail(std::string("parameter ") + *known + " has no value");
    } else if (entries_.empty()) {
      if (model_.positional_key == nullptr) {
        Fail("'" + token + "' has no parameter name; write KEY=VALUE with KEY one of " +
             ValidKeys());
      }
      entries_.emplace_back(model_.positional_key, std::vector<double>());
    }
    entries_.back().second.push_back(ParseNumber(value_text, entries_.back().first));
  }

  double ParseNumber(const std::string& text, const std::string& key) const {
    double value = 0;
    const char* begin = text.data();
    if (!text.empty() && text[0] == '+') ++begin;
    const auto [end, error] = std::from_chars(begin, text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size()) {
      Fail("'" + text + "' is not a number (in " + key + ")");
    }
    if (!std::isfinite(value)) Fail(key + " must be a finite number (got " + text + ")");
    return value;
  }

  std::string spec_;
  const ModelInfo& model_;
  std::vector<std::pair<std::string, std::vector<double>>> entries_;
};

std::unique_ptr<Brdf> MakeAnalytic(const std::string& spec, const ModelInfo& model,
                                   const std::string& text) {
  const Parameters params(spec, model, text);
  const std::string name = model.name;
  if (name == "lambert") return std::make_unique<LambertianBrdf>(params.Color("albedo"));
  if (name == "blinn-phong") {
    return std::make_unique<BlinnPhongBrdf>(params.Color("kd", 0.0), params.Color("ks"),
                                            params.Scalar("n"));
  }
  // Either alpha, or both alpha_x and alpha_y.
  const auto alphas = [&]() -> std::pair<double, double> {
    if (params.Has("alpha")) {
      if (params.Has("alpha_x") || params.Has("alpha_y")) {
        params.Fail("give either alpha or alpha_x and alpha_y, not both");
      }
      const double alpha = params.Scalar("alpha");
      return {alpha, alpha};
    }
    if (!params.Has("alpha_x") && !params.Has("alpha_y")) {
      params.Fail("missing parameter alpha (or alpha_x and alpha_y) for " + name + "; " +
                  model.help);
    }
    return {params.Scalar("alpha_x"), params.Scalar("alpha_y")};
  };
  if (name == "ward") {
    const Rgb rho_d = params.Color("rho_d", 0.0), rho_s = params.Color("rho_s");
    const auto [ax, ay] = alphas();
    return std::make_unique<WardBrdf>(rho_d, rho_s, ax, ay);
  }
  if (name == "as") {
    return std::make_unique<AshikhminShirleyBrdf>(params.Color("rd", 0.0), params.Color("rs"),
                                                  params.Scalar("nu"), params.Scalar("nv"));
  }
  if (name == "ggx") {
    const auto [ax, ay] = alphas();
    return std::make_unique<GgxBrdf>(ax, ay, params.Color("F0", 0.04), params.Color("kd", 0.0));
  }
  if (name == "mirror") return std::make_unique<MirrorBrdf>(params.Color("R"));
  if (name == "retro") {
    return std::make_unique<RetroBrdf>(params.Color("kd", 0.0), params.Color("kr"),
                                       params.Scalar("n"));
  }
  // dbrdf
  DBrdfParams dbrdf;
  dbrdf.c = params.Color("c", 1.0);
  dbrdf.f0 = params.Scalar("F0", 0.04);
  dbrdf.kd = params.Color("kd", 0.0);
  dbrdf.p_h.theta_samples = params.Integer("theta_samples");
  dbrdf.p_h.phi_samples = params.Integer("phi_samples", 1);
  dbrdf.p_h.p = params.List("p");
  if (const std::string problems = dbrdf.p_h.Problems(); !problems.empty()) {
    params.Fail(problems);
  }
  if (!(std::abs(dbrdf.p_h.NormalizationIntegral() - 1.0) <= 1e-12)) {
    try {
      dbrdf.p_h.Normalize();
    } catch (const NumericalError& e) {
      params.Fail(e.what());
    }
  }
  return std::make_unique<DBrdf>(std::move(dbrdf));
}

std::unique_ptr<Brdf> MakeFromFile(const std::string& spec, const std::string& path) {
  if (path.empty()) {
    throw InputError("material '" + spec +
                     "': file: needs a path, e.g. file:gold.binary or file:gold.json");
  }
  const std::string extension = AsciiLower(std::filesystem::path(path).extension().string());
  if (extension == ".binary") return MerlBrdf::FromFile(path);
  if (extension == ".json") return NbrdfBrdf::FromFile(path);
  if (extension == ".bsdf") return RglBrdf::FromFile(path);
  if (extension == ".exr" && ExrFormatOf(path) == "zbrdf-tabulated-v1") {
    return ReadTabulatedFile(path, "file:" + path);
  }
  throw InputError("material '" + spec + "': cannot tell the format of '" + path +
                   "' from its extension; use .binary (MERL table), .json (network file), .bsdf (RGL "
                   "file) or a tabulated .exr (zbrdf fit --model prior)");
}

}  // namespace

std::unique_ptr<Brdf> MakeBrdf(const std::string& spec) {
  const size_t colon = spec.find(':');
  if (colon == std::string::npos) {
    throw InputError("material '" + spec +
                     "': expected MODEL:PARAMETERS, e.g. lambert:0.18 or merl:blue-acrylic; "
                     "models: " +
                     JoinModelNames());
  }
  std::string model_name = AsciiLower(Trim(spec.substr(0, colon)));
  if (model_name == "lambertian") model_name = "lambert";
  if (model_name == "ashikhmin-shirley") model_name = "as";
  const std::string rest = Trim(spec.substr(colon + 1));
  const auto model = std::find_if(Models().begin(), Models().end(),
                                  [&](const ModelInfo& m) { return model_name == m.name; });
  if (model == Models().end()) {
    throw InputError("material '" + spec + "': unknown model '" + Trim(spec.substr(0, colon)) +
                     "'; valid: " + JoinModelNames());
  }
  try {
    if (model_name == "merl") {
      if (rest.empty()) {
        throw InputError("merl: needs a material name, e.g. merl:blue-acrylic");
      }
      return NbrdfBrdf::FromName(rest);
    }
    if (model_name == "rgl") {
      if (rest.empty()) throw InputError("rgl: needs a material name, e.g. rgl:cardboard");
      return NbrdfBrdf::FromName(rest, "rgl");
    }
    if (model_name == "file") return MakeFromFile(spec, rest);
    if (model_name == "target") {
      const std::string target = AsciiLower(rest);
      if (target == "white") return std::make_unique<LambertianBrdf>(Rgb(kWhiteTargetAlbedo));
      if (target == "graycard" || target == "gray-card") {
        return std::make_unique<LambertianBrdf>(Rgb(kGrayCardAlbedo));
      }
      if (target == "mirror") return std::make_unique<MirrorBrdf>(Rgb(kTargetMirrorReflectance));
      throw InputError("unknown calibration target '" + rest + "'; valid: white, graycard, mirror");
    }
    return MakeAnalytic(spec, *model, rest);
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.rfind("material '", 0) == 0) throw;
    throw InputError("material '" + spec + "': " + what);
  }
}

std::vector<std::string> MaterialModelNames() {
  std::vector<std::string> names;
  for (const ModelInfo& model : Models()) names.push_back(model.name);
  return names;
}

std::string MaterialShortName(const std::string& spec) {
  const size_t colon = spec.find(':');
  if (colon == std::string::npos) return spec;
  const std::string model = AsciiLower(spec.substr(0, colon));
  if (model == "merl" || model == "rgl") return spec.substr(colon + 1);
  if (model == "file") return std::filesystem::path(spec.substr(colon + 1)).stem().string();
  return model;
}

std::string MaterialSpecHelp() {
  std::string help =
      "Material specs, MODEL:PARAMETERS (colours are one value or r,g,b; upper-case names are\n"
      "required values, numbers are defaults):\n";
  for (const ModelInfo& model : Models()) help += "  " + std::string(model.help) + "\n";
  help +=
      "Bundled measured materials, merl:NAME (the MERL database, Matusik et al. 2003, as\n"
      "networks by Sztrajman et al. 2021):\n";
  std::string line;
  for (const std::string& name : BundledMaterialNames()) {
    if (!line.empty() && line.size() + name.size() + 3 > 100) {
      help += "  " + line + "\n";
      line.clear();
    }
    if (!line.empty()) line += ' ';
    line += name;
  }
  if (!line.empty()) help += "  " + line + "\n";
  return help;
}

}  // namespace zbrdf
