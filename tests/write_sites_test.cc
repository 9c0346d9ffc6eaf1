// Every file zbrdf writes goes through basis/atomic_file.h (issue 15; docs/session-folder.md,
// "Crashes, full disks and concurrent runs"): written to a temporary name, synced, renamed, so a
// kill or a full disk never leaves a truncated file. This test reads the sources of every library
// folder of docs/design.md section 5, and of fuzz/ and bench/, and fails on a file write anywhere
// else, naming file:line:
//
//   std::ofstream / std::fstream, fopen / freopen, cv::imwrite, cv::FileStorage, TIFFOpen,
//   OpenEXR output files opened on a path (Imf::OutputFile, MultiPartOutputFile, RgbaOutputFile,
//   TiledOutputFile constructed from a .c_str() or a literal), and open(2) / write(2) / pwrite(2)
//   / creat(2) / std::filesystem::copy.
//
// Writers that encode into memory and hand the bytes to the helper pass: OpenEXR on an
// Imf::StdOSStream, libtiff on TIFFStreamOpen, cv::imencode. kAllowed lists, with the reason, the
// only write sites that are not "project outputs". The test also prints the helper's call sites,
// the inventory of everything that writes, and checks that the writers of the session folder and
// the exports are among them (so that a broken scan cannot pass by finding nothing).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;

// The scanned tree: the sources, or ZBRDF_WRITE_SITES_ROOT (to scan another checkout).
std::string SourceRoot() {
  const char* root = std::getenv("ZBRDF_WRITE_SITES_ROOT");
  return root != nullptr ? root : ZBRDF_SOURCE_DIR;
}

const std::vector<std::string> kFolders = {"basis",    "brdf",     "drivers",     "rig",
                                           "fitting",  "simulate", "acquisition", "calibration",
                                           "pictures", "tools",    "fuzz",        "bench"};

// Write sites that do not go through the helper, each with why. Keys are "file: pattern name".
const std::map<std::string, std::string> kAllowed = {
    // The helper itself.
    {"basis/atomic_file.cc: open(2) for writing", "the helper"},
    {"basis/atomic_file.cc: write(2)", "the helper"},
    // The writer lock's file is rewritten in place: flock(2) locks an inode, so replacing the
    // file by a rename would hand the next writer a different, unlocked file. It holds only the
    // holder's PID and command line, for the next writer's message.
    {"acquisition/session.cc: open(2) for writing", "session.lock, the writer lock"},
    {"acquisition/session.cc: pwrite(2)", "session.lock, the writer lock"},
    // libFuzzer tooling writes the inputs it was asked to reproduce; not a zbrdf output.
    {"fuzz/fuzz_util.h: fopen", "fuzzer tooling"},
};

struct Pattern {
  std::string name;
  std::regex regex;
};

const std::vector<Pattern>& Patterns() {
  static const std::vector<Pattern> patterns = {
      {"std::ofstream", std::regex(R"(\bofstream\b)")},
      {"std::fstream", std::regex(R"(\bstd::fstream\b|\bfstream\s+\w+\s*\()")},
      {"fopen", std::regex(R"(\bf(re)?open\s*\()")},
      {"cv::imwrite", std::regex(R"(\bimwrite\s*\()")},
      {"cv::FileStorage", std::regex(R"(\bFileStorage\b)")},
      {"TIFFOpen", std::regex(R"(\bTIFFOpen\s*\()")},
      {"OpenEXR file opened on a path",
       std::regex(
           R"(\b(MultiPart|Rgba|Tiled|DeepScanLine|DeepTiled)?OutputFile\s+\w+\s*\(\s*[^,)]*)"
           R"((c_str\s*\(|"))")},
      {"open(2) for writing",
       std::regex(R"(\bopen\s*\([^;]*\b(O_WRONLY|O_RDWR|O_CREAT|O_APPEND|O_TRUNC)\b)")},
      {"write(2)", std::regex(R"((::|\s|^)write\s*\(\s*\w+\s*,)")},
      {"pwrite(2)", std::regex(R"(\bpwrite\s*\()")},
      {"creat(2)", std::regex(R"(\bcreat\s*\()")},
      {"std::filesystem::copy", std::regex(R"(\b(copy_file|filesystem::copy|fs::copy)\s*\()")},
  };
  return patterns;
}

// The file's text with // comments and string literals' contents blanked (lines kept), so that
// a comment or a message mentioning std::ofstream is not a write site.
std::vector<std::string> CodeLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  bool in_block_comment = false;
  for (std::string line; std::getline(in, line);) {
    std::string code;
    bool in_string = false;
    for (size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (in_block_comment) {
        if (c == '*' && i + 1 < line.size() && line[i + 1] == '/') {
          in_block_comment = false;
          ++i;
        }
        continue;
      }
      if (in_string) {
        if (c == '\\') {
          ++i;
        } else if (c == '"') {
          in_string = false;
          code += '"';
        }
        continue;
      }
      if (c == '/' && i + 1 < line.size() && line[i + 1] == '/') break;
      if (c == '/' && i + 1 < line.size() && line[i + 1] == '*') {
        in_block_comment = true;
        ++i;
        continue;
      }
      if (c == '"' && !(i > 0 && line[i - 1] == '\'')) in_string = true;
      code += c;
    }
    lines.push_back(code);
  }
  return lines;
}

struct Scan {
  std::vector<std::string> violations;      // "file:line: pattern"
  std::set<std::string> allowed_used;       // kAllowed keys that matched
  std::map<std::string, int> helper_calls;  // file -> calls of the helper's writers
  int files = 0;
};

Scan ScanSources(const std::string& root) {
  Scan scan;
  const std::regex helper(R"(\b(WriteFileAtomically|AppendToFile|WritePng)\s*\()");
  for (const std::string& folder : kFolders) {
    if (!fs::exists(fs::path(root) / folder)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(fs::path(root) / folder)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".cc" && ext != ".h")) continue;
      ++scan.files;
      const std::string file = fs::relative(entry.path(), root).string();
      const std::vector<std::string> lines = CodeLines(entry.path().string());
      const std::regex open_call(R"(\bopen\s*\()");
      for (size_t n = 0; n < lines.size(); ++n) {
        // An open(2) call's flags may be on the next lines: its statement, up to the ';'.
        std::string statement = lines[n];
        for (size_t k = 1; k <= 2 && n + k < lines.size(); ++k) statement += " " + lines[n + k];
        statement = statement.substr(0, statement.find(';') + 1);
        for (const Pattern& p : Patterns()) {
          const bool open_pattern = p.name == "open(2) for writing";
          const bool hit = open_pattern ? std::regex_search(lines[n], open_call) &&
                                              std::regex_search(statement, p.regex)
                                        : std::regex_search(lines[n], p.regex);
          if (!hit) continue;
          const std::string key = file + ": " + p.name;
          if (kAllowed.count(key)) {
            scan.allowed_used.insert(key);
          } else {
            scan.violations.push_back(file + ":" + std::to_string(n + 1) + ": " + p.name +
                                      " outside basis/atomic_file.h: `" + lines[n] + "`");
          }
        }
        if (std::regex_search(lines[n], helper)) ++scan.helper_calls[file];
      }
    }
  }
  return scan;
}

TEST(WriteSites, EveryFileIsWrittenThroughTheAtomicFileHelper) {
  const Scan scan = ScanSources(SourceRoot());
  ASSERT_GT(scan.files, 200) << "the sources were not found under " << SourceRoot();
  std::string list;
  for (const std::string& v : scan.violations) list += "  " + v + "\n";
  EXPECT_TRUE(scan.violations.empty())
      << "files written without basis/atomic_file.h (write into memory and call "
         "WriteFileAtomically, or add to kAllowed with the reason):\n"
      << list;
  // Every allow-list entry is still needed.
  for (const auto& [key, why] : kAllowed) {
    EXPECT_TRUE(scan.allowed_used.count(key)) << "kAllowed entry no longer matches: " << key;
  }
  // The inventory, and the writers that must be in it.
  int calls = 0;
  for (const auto& [file, n] : scan.helper_calls) {
    std::printf("  %-40s %d\n", file.c_str(), n);
    calls += n;
  }
  std::printf("%d calls of the helper's writers in %zu files\n", calls, scan.helper_calls.size());
  for (const char* writer : {"acquisition/session.cc",     // session.json, frames, journal lines
                             "acquisition/processing.cc",  // hdr/*.exr
                             "brdf/exr_writer.cc",         // zonal.exr, SH, D-BRDF,
                                                           // tabulated and prior files
                             "brdf/merl_table.cc",         // MERL exports
                             "brdf/tensor_file.cc",        // RGL .bsdf exports
                             "brdf/brdf_explorer.cc",      // BRDF Explorer exports
                             "tools/session_report.cc",    // report.json
                             "tools/brdf_export.cc",       // scene snippets
                             "pictures/image.cc",          // PNG and EXR pictures
                             "calibration/calibration_data.cc", "calibration/float_image.cc"}) {
    EXPECT_TRUE(scan.helper_calls.count(writer)) << writer << " no longer calls the helper";
  }
}

// The scanner itself: what it must find and what it must not.
TEST(WriteSites, TheScannerFindsWritesAndIgnoresCommentsAndMemoryStreams) {
  const std::string root =
      (fs::temp_directory_path() / ("zbrdf-write-sites-" + std::to_string(::getpid()))).string();
  fs::create_directories(root + "/tools");
  std::ofstream(root + "/tools/bad.cc")  // a fixture of the scanner, not a zbrdf output
      << "void A() {\n"
         "  std::ofstream out(path);\n"
         "  cv::imwrite(path, image);\n"
         "  Imf::OutputFile file(path.c_str(), header);\n"
         "  const int fd = ::open(p.c_str(),\n"
         "                        O_WRONLY | O_CREAT, 0644);\n"
         "}\n";
  std::ofstream(root + "/tools/good.cc")
      << "// std::ofstream in a comment; cv::imwrite too\n"
         "void B() {\n"
         "  Imf::StdOSStream stream;\n"
         "  Imf::OutputFile file(stream, header);\n"
         "  throw InputError(\"cannot write: std::ofstream failed\");\n"
         "  std::ifstream in(path);\n"
         "  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);\n"
         "  WriteFileAtomically(path, bytes);\n"
         "}\n";
  const Scan scan = ScanSources(root);
  std::vector<std::string> found;
  for (const std::string& v : scan.violations) found.push_back(v.substr(0, v.find(" outside")));
  const std::vector<std::string> expected = {
      "tools/bad.cc:2: std::ofstream", "tools/bad.cc:3: cv::imwrite",
      "tools/bad.cc:4: OpenEXR file opened on a path", "tools/bad.cc:5: open(2) for writing"};
  EXPECT_EQ(found, expected);
  EXPECT_EQ(scan.helper_calls.at("tools/good.cc"), 1);
  fs::remove_all(root);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
