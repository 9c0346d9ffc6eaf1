#include "tools/brdf_eval.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>

#include "basis/error.h"
#include "basis/parallel.h"

namespace zbrdf {
namespace {

constexpr int64_t kLinesPerTask = 8192;
constexpr int64_t kPairsPerTask = 4096;

bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Parses one line; returns an error message (empty when fine). *has_pair is false for blank and
// comment-only lines.
std::string ParseLine(std::string_view line, DirectionPair* pair, bool* has_pair) {
  const size_t hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  const char* p = line.data();
  const char* end = p + line.size();
  double values[4];
  int count = 0;
  while (p < end && IsBlank(*p)) ++p;
  *has_pair = p < end;
  if (!*has_pair) return "";
  while (p < end) {
    if (count == 4) {
      return "expected 4 numbers (theta_i phi_i theta_o phi_o, radians), got more: '" +
             std::string(line) + "'";
    }
    double value;
    const char* start = p;
    const auto result = std::from_chars(p, end, value);
    if (result.ec != std::errc() ||
        (result.ptr < end && !IsBlank(*result.ptr) && *result.ptr != ',')) {
      const char* token_end = start;
      while (token_end < end && !IsBlank(*token_end) && *token_end != ',') ++token_end;
      const std::string token(start, token_end);
      return token.empty() ? "an empty field (two separators in a row)"
                           : std::string("'") + token + "' is not a number";
    }
    if (!std::isfinite(value)) {
      std::string message = "'";
      message.append(start, result.ptr);
      return message + "' is not a finite number";
    }
    values[count++] = value;
    p = result.ptr;
    while (p < end && IsBlank(*p)) ++p;
    if (p < end && *p == ',') {
      ++p;
      while (p < end && IsBlank(*p)) ++p;
      if (p == end) return "a trailing comma";
    }
  }
  if (count != 4) {
    return "expected 4 numbers (theta_i phi_i theta_o phi_o, radians), got " +
           std::to_string(count);
  }
  *pair = {values[0], values[1], values[2], values[3]};
  return "";
}

// Appends %.17g of v (or "nan"/"inf" as printf writes them).
void AppendNumber(double v, std::string* out) {
  char buffer[32];
  const auto result =
      std::to_chars(buffer, buffer + sizeof(buffer), v, std::chars_format::general, 17);
  out->append(buffer, result.ptr);
}

}  // namespace

std::vector<DirectionPair> ParseDirectionPairs(std::string_view text, const std::string& source) {
  // Line starts, then lines parsed in parallel chunks; the first error by line number wins.
  std::vector<size_t> starts = {0};
  for (const char* p = text.data();
       (p = static_cast<const char*>(std::memchr(p, '\n', text.data() + text.size() - p)));) {
    ++p;
    starts.push_back(static_cast<size_t>(p - text.data()));
  }
  const int64_t lines = static_cast<int64_t>(starts.size());
  const int64_t tasks = (lines + kLinesPerTask - 1) / kLinesPerTask;
  std::vector<std::vector<DirectionPair>> chunks(tasks);
  std::mutex mutex;
  int64_t error_line = -1;
  std::string error_message;
  ParallelFor(tasks, 1, [&](int64_t begin, int64_t end) {
    for (int64_t task = begin; task < end; ++task) {
      const int64_t first = task * kLinesPerTask, last = std::min(lines, first + kLinesPerTask);
      auto& chunk = chunks[task];
      chunk.reserve(last - first);
      for (int64_t line = first; line < last; ++line) {
        const size_t a = starts[line];
        const size_t b = line + 1 < lines ? starts[line + 1] - 1 : text.size();
        DirectionPair pair;
        bool has_pair = false;
        const std::string message = ParseLine(text.substr(a, b - a), &pair, &has_pair);
        if (!message.empty()) {
          std::lock_guard<std::mutex> lock(mutex);
          if (error_line < 0 || line < error_line) {
            error_line = line;
            error_message = message;
          }
          return;
        }
        if (has_pair) chunk.push_back(pair);
      }
    }
  });
  if (error_line >= 0) {
    throw InputError(source + " line " + std::to_string(error_line + 1) + ": " + error_message +
                     "; nothing was written");
  }
  std::vector<DirectionPair> pairs;
  size_t total = 0;
  for (const auto& chunk : chunks) total += chunk.size();
  pairs.reserve(total);
  for (const auto& chunk : chunks) pairs.insert(pairs.end(), chunk.begin(), chunk.end());
  return pairs;
}

void EvaluateDirections(const Brdf& brdf, std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                        std::span<Rgb> f) {
  ZBRDF_ASSERT(w_i.size() == w_o.size() && w_i.size() == f.size(),
               "EvaluateDirections: w_i, w_o and f differ in size");
  const int64_t n = static_cast<int64_t>(f.size());
  ParallelFor((n + kPairsPerTask - 1) / kPairsPerTask, 1, [&](int64_t begin, int64_t end) {
    for (int64_t task = begin; task < end; ++task) {
      const int64_t first = task * kPairsPerTask, last = std::min(n, first + kPairsPerTask);
      const size_t count = static_cast<size_t>(last - first);
      brdf.EvalBatch(w_i.subspan(first, count), w_o.subspan(first, count), f.subspan(first, count));
      for (int64_t k = first; k < last; ++k) {
        if (w_i[k].z <= 0 || w_o[k].z <= 0) f[k] = Rgb();
      }
    }
  });
}

std::vector<Rgb> EvaluatePairs(const Brdf& brdf, std::span<const DirectionPair> pairs) {
  const int64_t n = static_cast<int64_t>(pairs.size());
  std::vector<Vec3> w_i(pairs.size()), w_o(pairs.size());
  ParallelFor(n, kPairsPerTask, [&](int64_t begin, int64_t end) {
    for (int64_t k = begin; k < end; ++k) {
      w_i[k] = SphericalDirection(pairs[k].theta_i, pairs[k].phi_i);
      w_o[k] = SphericalDirection(pairs[k].theta_o, pairs[k].phi_o);
    }
  });
  std::vector<Rgb> f(pairs.size());
  EvaluateDirections(brdf, w_i, w_o, f);
  return f;
}

std::string FormatEvaluations(std::span<const DirectionPair> pairs, std::span<const Rgb> f,
                              EvalFormat format, const std::string& input,
                              const std::string& spec) {
  ZBRDF_ASSERT(pairs.size() == f.size(), "FormatEvaluations: pairs and values differ in size");
  const bool json = format == EvalFormat::kJson;
  const int64_t n = static_cast<int64_t>(pairs.size());
  const int64_t tasks = (n + kPairsPerTask - 1) / kPairsPerTask;
  std::vector<std::string> chunks(tasks);
  ParallelFor(tasks, 1, [&](int64_t begin, int64_t end) {
    for (int64_t task = begin; task < end; ++task) {
      const int64_t first = task * kPairsPerTask, last = std::min(n, first + kPairsPerTask);
      std::string& out = chunks[task];
      out.reserve((last - first) * 170);
      for (int64_t k = first; k < last; ++k) {
        const DirectionPair& p = pairs[k];
        const double values[7] = {p.theta_i, p.phi_i, p.theta_o, p.phi_o, f[k].r, f[k].g, f[k].b};
        if (json) out += k == 0 ? "    [" : ",\n    [";
        for (int c = 0; c < 7; ++c) {
          if (c > 0) out += ',';
          if (json && !std::isfinite(values[c])) {
            out += "null";
          } else {
            AppendNumber(values[c], &out);
          }
        }
        out += json ? "]" : "\n";
      }
    }
  });
  std::string text;
  size_t size = 0;
  for (const auto& chunk : chunks) size += chunk.size();
  text.reserve(size + 512);
  if (json) {
    text +=
        "{\n  \"input\": " + nlohmann::json(input).dump() +
        ",\n  \"brdf\": " + nlohmann::json(spec).dump() +
        ",\n  \"units\": \"1/sr\",\n  \"quantity\": \"f_r without cosine, linear RGB\","
        "\n  \"columns\": [\"theta_i\", \"phi_i\", \"theta_o\", \"phi_o\", \"r\", \"g\", \"b\"],"
        "\n  \"rows\": [\n";
  } else {
    text += "theta_i,phi_i,theta_o,phi_o,r,g,b\n";
  }
  for (const auto& chunk : chunks) text += chunk;
  if (json) text += "\n  ]\n}\n";
  return text;
}

}  // namespace zbrdf
