#include "brdf/brdf_explorer.h"

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "brdf/ashikhmin_shirley.h"
#include "brdf/blinn_phong.h"
#include "brdf/dbrdf.h"
#include "brdf/ggx.h"
#include "brdf/lambertian.h"
#include "brdf/material_spec.h"
#include "brdf/nbrdf.h"
#include "brdf/ward.h"

namespace zbrdf {
namespace {

// A GLSL float literal with float precision (9 significant digits); always has a '.' or an
// exponent so that GLSL reads it as a float, not an int.
std::string GlslFloat(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", value);
  std::string s = text;
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string ExplorerNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", value);
  return text;
}

std::string ColorParameter(const std::string& name, const Rgb& c) {
  return "color " + name + " " + ExplorerNumber(c.r) + " " + ExplorerNumber(c.g) + " " +
         ExplorerNumber(c.b) + "\n";
}

std::string FloatParameter(const std::string& name, double min, double max, double value) {
  return "float " + name + " " + ExplorerNumber(min) + " " + ExplorerNumber(std::max(max, value)) +
         " " + ExplorerNumber(value) + "\n";
}

std::string FloatArray(const std::string& name, const std::vector<double>& values) {
  std::string s = "const float " + name + "[" + std::to_string(values.size()) + "] = float[" +
                  std::to_string(values.size()) + "](";
  for (size_t i = 0; i < values.size(); ++i) {
    s += (i % 8 == 0 ? "\n    " : " ") + GlslFloat(values[i]) + (i + 1 < values.size() ? "," : "");
  }
  return s + ");\n";
}

// The local-frame prologue of every shader: directions in (X, Y, N) and the horizon test.
constexpr const char* kLocalFrame =
    "    vec3 l = vec3(dot(L, X), dot(L, Y), dot(L, N));\n"
    "    vec3 v = vec3(dot(V, X), dot(V, Y), dot(V, N));\n"
    "    if (l.z <= 0.0 || v.z <= 0.0) return vec3(0.0);\n";

constexpr const char* kPrelude =
    "const float PI = 3.14159265358979323846;\n\n"
    "vec3 SchlickFresnel(vec3 f0, float cos_theta)\n{\n"
    "    float m = 1.0 - clamp(cos_theta, 0.0, 1.0);\n"
    "    return f0 + (vec3(1.0) - f0) * (m * m * m * m * m);\n}\n\n";

struct Shader {
  std::string model, parameters, body;
};

Shader LambertShader(const LambertianBrdf& m) {
  return {"lambert", ColorParameter("albedo", m.albedo()),
          "vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )\n{\n" + std::string(kLocalFrame) +
              "    return albedo / PI;\n}\n"};
}

Shader BlinnPhongShader(const BlinnPhongBrdf& m) {
  return {"blinn-phong",
          ColorParameter("kd", m.kd()) + ColorParameter("ks", m.ks()) +
              FloatParameter("n", 0, 10000, m.exponent()),
          "vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )\n{\n" + std::string(kLocalFrame) +
              "    vec3 h = normalize(l + v);\n"
              "    float lobe = (n + 8.0) / (8.0 * PI) * pow(h.z, n);\n"
              "    return kd / PI + ks * lobe;\n}\n"};
}

Shader WardShader(const WardBrdf& m) {
  return {"ward",
          ColorParameter("rho_d", m.rho_d()) + ColorParameter("rho_s", m.rho_s()) +
              FloatParameter("alpha_x", 0.001, 1, m.alpha_x()) +
              FloatParameter("alpha_y", 0.001, 1, m.alpha_y()),
          "vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )\n{\n" + std::string(kLocalFrame) +
              "    vec3 h = l + v;\n"
              "    float sx = h.x / alpha_x, sy = h.y / alpha_y;\n"
              "    float lobe = exp(-(sx * sx + sy * sy) / (h.z * h.z)) /\n"
              "                 (4.0 * PI * alpha_x * alpha_y * sqrt(l.z * v.z));\n"
              "    return rho_d / PI + rho_s * lobe;\n}\n"};
}

Shader AshikhminShirleyShader(const AshikhminShirleyBrdf& m) {
  return {
      "as",
      ColorParameter("rd", m.rd()) + ColorParameter("rs", m.rs()) +
          FloatParameter("nu", 0, 10000, m.nu()) + FloatParameter("nv", 0, 10000, m.nv()),
      "float DiffuseFactor(float c)\n{\n    float m = 1.0 - 0.5 * c;\n"
      "    return 1.0 - m * m * m * m * m;\n}\n\n"
      "vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )\n{\n" +
          std::string(kLocalFrame) +
          "    vec3 h = normalize(l + v);\n"
          "    float sin2 = h.x * h.x + h.y * h.y;\n"
          "    float e = sin2 > 0.0 ? (nu * h.x * h.x + nv * h.y * h.y) / sin2 : nu;\n"
          "    float p_h = sqrt((nu + 1.0) * (nv + 1.0)) / (2.0 * PI) * pow(h.z, e);\n"
          "    float cos_kh = dot(l, h);\n"
          "    vec3 specular = SchlickFresnel(rs, cos_kh) * p_h / (4.0 * cos_kh * max(l.z, v.z));\n"
          "    vec3 diffuse = rd * (vec3(1.0) - rs) * (28.0 / (23.0 * PI)) *\n"
          "                   DiffuseFactor(l.z) * DiffuseFactor(v.z);\n"
          "    return specular + diffuse;\n}\n"};
}

Shader GgxShader(const GgxBrdf& m) {
  return {"ggx",
          FloatParameter("alpha_x", 0.001, 1, m.alpha_x()) +
              FloatParameter("alpha_y", 0.001, 1, m.alpha_y()) + ColorParameter("F0", m.f0()) +
              ColorParameter("kd", m.kd()),
          "float Lambda(vec3 w)\n{\n    float tx = alpha_x * w.x, ty = alpha_y * w.y;\n"
          "    return 0.5 * (sqrt(1.0 + (tx * tx + ty * ty) / (w.z * w.z)) - 1.0);\n}\n\n"
          "vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )\n{\n" +
              std::string(kLocalFrame) +
              "    vec3 h = normalize(l + v);\n"
              "    float sx = h.x / alpha_x, sy = h.y / alpha_y;\n"
              "    float q = sx * sx + sy * sy + h.z * h.z;\n"
              "    float D = 1.0 / (PI * alpha_x * alpha_y * q * q);\n"
              "    float G2 = 1.0 / (1.0 + Lambda(l) + Lambda(v));\n"
              "    return kd / PI + SchlickFresnel(F0, dot(v, h)) * (D * G2 / (4.0 * l.z * "
              "v.z));\n}\n"};
}

Shader DBrdfShader(const DBrdf& m) {
  const HalfVectorTable& t = m.table();
  std::string body =
      "const int THETA_SAMPLES = " + std::to_string(t.theta_samples) + ";\n" +
      "const int PHI_SAMPLES = " + std::to_string(t.phi_samples) + ";\n" +
      FloatArray("P_TABLE", t.p) +
      "\nfloat P(int j, int k) { return P_TABLE[j * PHI_SAMPLES + k]; }\n\n"
      "// p(h) interpolated linearly in theta_h and periodically in phi_h.\n"
      "float PEval(float theta_h, float phi_h)\n{\n"
      "    float u = clamp(theta_h, 0.0, 0.5 * PI) / (0.5 * PI / float(THETA_SAMPLES - 1));\n"
      "    int j = min(int(u), THETA_SAMPLES - 2);\n"
      "    float t = u - float(j);\n"
      "    if (PHI_SAMPLES == 1) return mix(P(j, 0), P(j + 1, 0), t);\n"
      "    float w = mod(phi_h, 2.0 * PI) / (2.0 * PI / float(PHI_SAMPLES));\n"
      "    int k0 = min(int(w), PHI_SAMPLES - 1);\n"
      "    int k1 = (k0 + 1) % PHI_SAMPLES;\n"
      "    float s = clamp(w - float(k0), 0.0, 1.0);\n"
      "    return mix(mix(P(j, k0), P(j, k1), s), mix(P(j + 1, k0), P(j + 1, k1), s), t);\n"
      "}\n\n"
      "vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )\n{\n" +
      std::string(kLocalFrame) +
      "    vec3 h = normalize(l + v);\n"
      "    float p = PEval(acos(clamp(h.z, -1.0, 1.0)), atan(h.y, h.x));\n"
      "    float F = SchlickFresnel(vec3(F0), dot(l, h)).x;\n"
      "    return c * (p * F / (l.z + v.z - l.z * v.z)) + kd / PI;\n}\n";
  return {"dbrdf",
          ColorParameter("c", m.c()) + FloatParameter("F0", 0, 1, m.f0()) +
              ColorParameter("kd", m.kd()),
          body};
}

Shader NetworkShader(const NbrdfBrdf& m) {
  const NbrdfNetwork& net = m.network();
  std::string arrays;
  for (int k = 0; k < 3; ++k) {
    const auto& layer = net.layers[k];
    arrays += FloatArray(std::string("W") += std::to_string(k + 1), layer.weights);
    arrays += FloatArray(std::string("B") += std::to_string(k + 1), layer.bias);
  }
  const std::string h1 = std::to_string(net.layers[0].out), h2 = std::to_string(net.layers[1].out);
  std::string body = "// Sztrajman et al. 2021 network of ";
  body += net.material;
  body +=
      " (MERL, Matusik et al. 2003): weights row-major in x out.\n"
      "const int H1 = " +
      h1 + ";\nconst int H2 = " + h2 + ";\n" + arrays +
      "\nvec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )\n{\n" + std::string(kLocalFrame) +
      "    vec3 h = normalize(l + v);\n"
      "    float sin_h = length(h.xy), cos_h = h.z;\n"
      "    float cp = sin_h > 0.0 ? h.x / sin_h : 1.0, sp = sin_h > 0.0 ? h.y / sin_h : 0.0;\n"
      "    float tx = l.x * cp + l.y * sp, ty = l.y * cp - l.x * sp;\n"
      "    float x[6] = float[6](sin_h, 0.0, cos_h, tx * cos_h - l.z * sin_h, ty,\n"
      "                          tx * sin_h + l.z * cos_h);\n"
      "    float a1[" +
      h1 +
      "];\n"
      "    for (int j = 0; j < H1; ++j) {\n"
      "        float s = B1[j];\n"
      "        for (int i = 0; i < 6; ++i) s += x[i] * W1[i * H1 + j];\n"
      "        a1[j] = max(s, 0.0);\n"
      "    }\n"
      "    float a2[" +
      h2 +
      "];\n"
      "    for (int j = 0; j < H2; ++j) {\n"
      "        float s = B2[j];\n"
      "        for (int i = 0; i < H1; ++i) s += a1[i] * W2[i * H2 + j];\n"
      "        a2[j] = max(s, 0.0);\n"
      "    }\n"
      "    vec3 y = vec3(B3[0], B3[1], B3[2]);\n"
      "    for (int i = 0; i < H2; ++i) {\n"
      "        y += a2[i] * vec3(W3[i * 3], W3[i * 3 + 1], W3[i * 3 + 2]);\n"
      "    }\n"
      "    return max(exp(y) - vec3(1.0), vec3(0.0));\n}\n";
  return {"nbrdf", "", body};
}

Shader ShaderFor(const Brdf& brdf) {
  if (const auto* m = dynamic_cast<const LambertianBrdf*>(&brdf)) return LambertShader(*m);
  if (const auto* m = dynamic_cast<const BlinnPhongBrdf*>(&brdf)) return BlinnPhongShader(*m);
  if (const auto* m = dynamic_cast<const WardBrdf*>(&brdf)) return WardShader(*m);
  if (const auto* m = dynamic_cast<const AshikhminShirleyBrdf*>(&brdf)) {
    return AshikhminShirleyShader(*m);
  }
  if (const auto* m = dynamic_cast<const GgxBrdf*>(&brdf)) return GgxShader(*m);
  if (const auto* m = dynamic_cast<const DBrdf*>(&brdf)) return DBrdfShader(*m);
  if (const auto* m = dynamic_cast<const NbrdfBrdf*>(&brdf)) return NetworkShader(*m);
  throw InputError("brdf-explorer export: " + brdf.Spec() +
                   " has no analytic GLSL form here (supported: lambert, blinn-phong, ward, as, "
                   "ggx, dbrdf and the measured networks). BRDF Explorer opens MERL tables "
                   "directly: use --format merl");
}

// ---- reading ----

struct ParsedFile {
  std::string model;
  std::map<std::string, std::vector<double>> parameters;  // defaults: 1 (float) or 3 (color)
  std::map<std::string, std::vector<double>> arrays;
  std::map<std::string, int> ints;
};

[[noreturn]] void Malformed(const std::string& path, const std::string& what) {
  throw InputError("BRDF Explorer file " + path + ": " + what);
}

std::vector<double> ParseNumbers(const std::string& text, const std::string& path,
                                 const std::string& what) {
  std::vector<double> values;
  std::string token;
  std::istringstream in(text);
  while (std::getline(in, token, ',')) {
    const size_t begin = token.find_first_not_of(" \t\n\r");
    if (begin == std::string::npos) continue;
    try {
      size_t used = 0;
      values.push_back(std::stod(token.substr(begin), &used));
    } catch (const std::exception&) {
      Malformed(path, what + ": '" + token + "' is not a number");
    }
  }
  return values;
}

ParsedFile ParseFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("BRDF Explorer file " + path + ": cannot open it; check the path");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  ParsedFile parsed;
  std::istringstream lines(text);
  std::string line;
  bool in_parameters = false;
  while (std::getline(lines, line)) {
    if (line.rfind("# zbrdf-model:", 0) == 0) {
      std::istringstream(line.substr(14)) >> parsed.model;
    } else if (line.rfind("::begin parameters", 0) == 0) {
      in_parameters = true;
    } else if (line.rfind("::end parameters", 0) == 0) {
      in_parameters = false;
    } else if (in_parameters) {
      std::istringstream fields(line);
      std::string type, name;
      if (!(fields >> type >> name) || type[0] == '#') continue;
      std::vector<double> values;
      double v;
      while (fields >> v) values.push_back(v);
      if (type == "color" && values.size() == 3) {
        parsed.parameters[name] = values;
      } else if (type == "float" && values.size() == 3) {
        parsed.parameters[name] = {values[2]};
      } else if (type == "bool" && values.size() == 1) {
        parsed.parameters[name] = values;
      } else {
        Malformed(path, "parameter line '" + line + "' is malformed");
      }
    } else if (line.rfind("const int ", 0) == 0) {
      std::istringstream fields(line.substr(10));
      std::string name, equals;
      int value;
      if (fields >> name >> equals >> value) parsed.ints[name] = value;
    }
  }
  // const float NAME[N] = float[N]( ... );
  for (size_t pos = text.find("const float "); pos != std::string::npos;
       pos = text.find("const float ", pos + 1)) {
    const size_t bracket = text.find('[', pos), open = text.find('(', pos),
                 close = text.find(')', pos);
    const size_t equals = text.find('=', pos);
    if (bracket == std::string::npos || open == std::string::npos || close == std::string::npos ||
        equals == std::string::npos || bracket > equals) {
      continue;  // a scalar constant such as PI
    }
    const std::string name = text.substr(pos + 12, bracket - pos - 12);
    const int declared = std::atoi(text.c_str() + bracket + 1);
    std::vector<double> values =
        ParseNumbers(text.substr(open + 1, close - open - 1), path, "array " + name);
    if (static_cast<int>(values.size()) != declared) {
      Malformed(path, "array " + name + " declares " + std::to_string(declared) +
                          " values but has " + std::to_string(values.size()));
    }
    parsed.arrays[name] = std::move(values);
  }
  if (parsed.model.empty()) {
    Malformed(path,
              "no '# zbrdf-model:' line; only files written by zbrdf export can be read back "
              "(other BRDF Explorer shaders are GLSL programs, not data)");
  }
  return parsed;
}

const std::vector<double>& Get(const ParsedFile& f,
                               const std::map<std::string, std::vector<double>>& m,
                               const std::string& name, const std::string& path) {
  auto it = m.find(name);
  if (it == m.end())
    Malformed(path, "the " + f.model + " model needs '" + name + "', which is missing");
  return it->second;
}

Rgb ColorOf(const ParsedFile& f, const std::string& name, const std::string& path) {
  const auto& v = Get(f, f.parameters, name, path);
  if (v.size() != 3) Malformed(path, "'" + name + "' must be a color");
  return {v[0], v[1], v[2]};
}

double FloatOf(const ParsedFile& f, const std::string& name, const std::string& path) {
  const auto& v = Get(f, f.parameters, name, path);
  if (v.size() != 1) Malformed(path, "'" + name + "' must be a float");
  return v[0];
}

std::string Col(const Rgb& c) {
  return ExplorerNumber(c.r) + "," + ExplorerNumber(c.g) + "," + ExplorerNumber(c.b);
}

}  // namespace

std::string BrdfExplorerSource(const Brdf& brdf) {
  const Shader shader = ShaderFor(brdf);
  return "analytic\n\n# zbrdf export of " + brdf.Spec().substr(0, 200) +
         "\n# zbrdf-model: " + shader.model +
         "\n# BRDF() returns f_r in 1/sr without the cosine; L toward the light, V toward the "
         "viewer.\n\n::begin parameters\n" +
         shader.parameters + "::end parameters\n\n::begin shader\n\n" + kPrelude + shader.body +
         "\n::end shader\n";
}

void WriteBrdfExplorerFile(const std::string& path, const Brdf& brdf) {
  WriteFileAtomically(path, BrdfExplorerSource(brdf));
}

std::unique_ptr<Brdf> ReadBrdfExplorerFile(const std::string& path) {
  const ParsedFile f = ParseFile(path);
  const std::string& model = f.model;
  if (model == "lambert") return MakeBrdf("lambert:albedo=" + Col(ColorOf(f, "albedo", path)));
  if (model == "blinn-phong") {
    return MakeBrdf("blinn-phong:kd=" + Col(ColorOf(f, "kd", path)) + ",ks=" +
                    Col(ColorOf(f, "ks", path)) + ",n=" + ExplorerNumber(FloatOf(f, "n", path)));
  }
  if (model == "ward") {
    return MakeBrdf("ward:rho_d=" + Col(ColorOf(f, "rho_d", path)) +
                    ",rho_s=" + Col(ColorOf(f, "rho_s", path)) +
                    ",alpha_x=" + ExplorerNumber(FloatOf(f, "alpha_x", path)) +
                    ",alpha_y=" + ExplorerNumber(FloatOf(f, "alpha_y", path)));
  }
  if (model == "as") {
    return MakeBrdf("as:rd=" + Col(ColorOf(f, "rd", path)) + ",rs=" + Col(ColorOf(f, "rs", path)) +
                    ",nu=" + ExplorerNumber(FloatOf(f, "nu", path)) +
                    ",nv=" + ExplorerNumber(FloatOf(f, "nv", path)));
  }
  if (model == "ggx") {
    return MakeBrdf("ggx:alpha_x=" + ExplorerNumber(FloatOf(f, "alpha_x", path)) +
                    ",alpha_y=" + ExplorerNumber(FloatOf(f, "alpha_y", path)) +
                    ",F0=" + Col(ColorOf(f, "F0", path)) + ",kd=" + Col(ColorOf(f, "kd", path)));
  }
  if (model == "dbrdf") {
    auto theta = f.ints.find("THETA_SAMPLES"), phi = f.ints.find("PHI_SAMPLES");
    if (theta == f.ints.end() || phi == f.ints.end()) {
      Malformed(path, "the dbrdf model needs THETA_SAMPLES and PHI_SAMPLES");
    }
    DBrdfParams params;
    params.p_h.theta_samples = theta->second;
    params.p_h.phi_samples = phi->second;
    params.p_h.p = Get(f, f.arrays, "P_TABLE", path);
    if (const std::string problems = params.p_h.Problems(); !problems.empty()) {
      Malformed(path, problems);
    }
    // The table was rounded to float: renormalize and keep the product c p(h) unchanged.
    const double integral = params.p_h.NormalizationIntegral();
    params.p_h.Normalize();
    params.c = ColorOf(f, "c", path) * integral;
    params.f0 = FloatOf(f, "F0", path);
    params.kd = ColorOf(f, "kd", path);
    return std::make_unique<DBrdf>(std::move(params));
  }
  if (model == "nbrdf") {
    NbrdfNetwork network;
    network.material = "from " + path;
    const int h1 = f.ints.count("H1") ? f.ints.at("H1") : 0;
    const int h2 = f.ints.count("H2") ? f.ints.at("H2") : 0;
    const int sizes[4] = {6, h1, h2, 3};
    for (int k = 0; k < 3; ++k) {
      auto& layer = network.layers[k];
      layer.in = sizes[k];
      layer.out = sizes[k + 1];
      layer.weights = Get(f, f.arrays, std::string("W") += std::to_string(k + 1), path);
      layer.bias = Get(f, f.arrays, std::string("B") += std::to_string(k + 1), path);
      if (layer.in < 1 || layer.out < 1 ||
          layer.weights.size() != static_cast<size_t>(layer.in) * layer.out ||
          layer.bias.size() != static_cast<size_t>(layer.out)) {
        Malformed(path, "network layer " + std::to_string(k + 1) + " has inconsistent sizes");
      }
    }
    return std::make_unique<NbrdfBrdf>(std::move(network), "file:" + path);
  }
  Malformed(path, "unknown zbrdf-model '" + model + "'");
}

}  // namespace zbrdf
