// zbrdf eval: f_r of any material or fit at direction pairs from a file or stdin.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "brdf/material_spec.h"
#include "tools/brdf_eval.h"
#include "tools/brdf_input.h"
#include "tools/cli/command.h"

namespace zbrdf::cli {
namespace {

std::string ReadAll(const std::string& path) {
  if (path == "-") {
    return std::string(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
  }
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw InputError("--pairs " + path +
                     " is a folder; give a file of direction pairs (or - for "
                     "standard input)");
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError("--pairs " + path + ": cannot open it; check the path");
  std::ostringstream buffer;
  buffer << file.rdbuf();
  if (file.bad()) throw InputError("--pairs " + path + ": cannot read it; check the file");
  return buffer.str();
}

int RunEval(const std::vector<std::string>& args) {
  CommandLine cl("eval",
                 "Evaluates f_r of any material, fit or file at direction pairs, for scripts and\n"
                 "cross-checks with other tools. Reads one pair per line: theta_i phi_i theta_o "
                 "phi_o\nin radians in the sample frame (normal +z, phi from +x; w_i toward the "
                 "light, w_o\ntoward the viewer), separated by spaces, tabs or a comma; '#' starts "
                 "a comment.\nWrites per pair the four angles and f_r R G B in 1/sr (not "
                 "multiplied by any cosine),\nevery number with full double precision (%.17g). A "
                 "pair below the horizon gives 0.\nA malformed line, or an input without any "
                 "pair, is an error (naming the line),\nand then nothing is written.");
  cl.Positional("INPUT", "session folder, file or material spec (see below)")
      .Option("pairs", "FILE", "direction pairs, or - for standard input", "-")
      .Option("out", "FILE", "where to write, or - for standard output", "-")
      .Option("format", "F", "csv or json (default: json if --out ends in .json, else csv)")
      .Epilog(
          "Examples:\n"
          "  echo '0.3 0 0.3 3.14159265' | zbrdf eval merl:blue-acrylic\n"
          "  zbrdf eval results/blue-acrylic --pairs pairs.txt --out f.csv\n"
          "  zbrdf eval ggx:alpha=0.2 --pairs pairs.txt --format json\n\n"
          "CSV: a header line theta_i,phi_i,theta_o,phi_o,r,g,b then one line per pair. JSON:\n"
          "{\"input\", \"brdf\", \"units\": \"1/sr\", \"columns\", \"rows\": [[7 numbers], "
          "...]}.\ndocs/eval.md has the details.\n\n" +
          BrdfInputHelp() + "\n" + MaterialSpecHelp());
  if (!cl.Parse(args)) return 0;
  const std::string out = cl.Get("out");
  std::string format = cl.Has("format") ? cl.Get("format") : "";
  if (format.empty()) {
    format = std::filesystem::path(out).extension() == ".json" ? "json" : "csv";
  }
  if (format != "csv" && format != "json") {
    throw InputError("--format must be csv or json (got '" + format + "')");
  }
  const BrdfInput input = ResolveBrdfInput(cl.Positional(0));
  const std::string pairs_path = cl.Get("pairs");
  const std::string text = ReadAll(pairs_path);
  const std::string source = pairs_path == "-" ? "standard input" : pairs_path;
  const std::vector<DirectionPair> pairs = ParseDirectionPairs(text, source);
  if (pairs.empty()) {
    throw InputError(source +
                     " holds no direction pairs (one 'theta_i phi_i theta_o phi_o' per "
                     "line); nothing was written");
  }
  const std::vector<Rgb> f = EvaluatePairs(*input.brdf, pairs);
  const std::string result =
      FormatEvaluations(pairs, f, format == "json" ? EvalFormat::kJson : EvalFormat::kCsv,
                        cl.Positional(0), input.brdf->Spec());
  if (out == "-") {
    std::fwrite(result.data(), 1, result.size(), stdout);
    std::fflush(stdout);
  } else {
    WriteFileAtomically(out, result);
  }
  return 0;
}

const CommandRegistration kEvalCommand(
    {"eval", "evaluate f_r of a material, fit or file at given directions", RunEval});

}  // namespace
}  // namespace zbrdf::cli
