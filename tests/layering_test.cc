// The layering of docs/design.md section 5, held to the code: every #include "folder/..." of a
// library folder (and of fuzz/) must name the folder itself or one the design's `layers` block
// allows, and Ceres is included only where the design says. The block is read from the document
// itself, so the rule and its documentation cannot drift apart; the README's layout table must
// list the same folders, bottom to top.
#include <gtest/gtest.h>

#include <algorithm>
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

const std::string kSourceDir = ZBRDF_SOURCE_DIR;

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// folder -> the folders it may include, in the order the block lists the folders.
struct Layers {
  std::vector<std::string> order;
  std::map<std::string, std::set<std::string>> allowed;
};

// The ```layers block of docs/design.md: lines "folder: dep dep ..." ("-" for none).
Layers ParseLayers(const std::string& design) {
  Layers layers;
  const size_t begin = design.find("```layers\n");
  if (begin == std::string::npos) return layers;
  const size_t end = design.find("```", begin + 10);
  std::istringstream block(design.substr(begin + 10, end - begin - 10));
  std::string line;
  while (std::getline(block, line)) {
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string folder = line.substr(0, colon);
    std::istringstream deps(line.substr(colon + 1));
    std::set<std::string>& allowed = layers.allowed[folder];
    for (std::string dep; deps >> dep;) {
      if (dep != "-") allowed.insert(dep);
    }
    layers.order.push_back(folder);
  }
  return layers;
}

struct Scan {
  std::vector<std::string> violations;  // "file:line: what"
  int includes_checked = 0;
  int files = 0;
};

// Checks every .h and .cc file under root/<folder> for each folder of `layers`. Includes are
// those of the form #include "a/b.h" whose first component is a folder of the source tree;
// <...> includes are third-party, except Ceres, which only `ceres_users` (folders or files) may
// include.
Scan CheckIncludes(const std::string& root, const Layers& layers,
                   const std::set<std::string>& ceres_users) {
  Scan scan;
  std::set<std::string> tree_folders;
  for (const auto& entry : fs::directory_iterator(root)) {
    if (entry.is_directory()) tree_folders.insert(entry.path().filename().string());
  }
  const std::regex project_include(R"(^\s*#\s*include\s*"([A-Za-z0-9_]+)/([^"]+)\")");
  const std::regex ceres_include(R"(^\s*#\s*include\s*<ceres/)");
  for (const std::string& folder : layers.order) {
    const fs::path dir = fs::path(root) / folder;
    if (!fs::is_directory(dir)) {
      scan.violations.push_back(folder + "/: listed in the layers block but not in the tree");
      continue;
    }
    const std::set<std::string>& allowed = layers.allowed.at(folder);
    std::vector<fs::path> files;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
      const std::string ext = entry.path().extension().string();
      if (entry.is_regular_file() && (ext == ".h" || ext == ".cc")) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& file : files) {
      ++scan.files;
      const std::string relative = fs::relative(file, root).string();
      std::istringstream text(ReadText(file.string()));
      std::string line;
      for (int number = 1; std::getline(text, line); ++number) {
        const std::string where = relative + ":" + std::to_string(number) + ": ";
        std::smatch m;
        if (std::regex_search(line, m, project_include)) {
          const std::string target = m[1];
          if (!tree_folders.count(target)) continue;  // not a folder of this tree
          ++scan.includes_checked;
          if (target == folder || allowed.count(target)) continue;
          std::string may;
          for (const std::string& a : allowed) may += (may.empty() ? "" : ", ") + a;
          scan.violations.push_back(where + "#include \"" + target + "/" + m[2].str() + "\": " +
                                    folder + "/ may include only " +
                                    (may.empty() ? std::string("itself") : may) +
                                    " (docs/design.md section 5)");
        } else if (std::regex_search(line, ceres_include)) {
          ++scan.includes_checked;
          if (ceres_users.count(folder) || ceres_users.count(relative)) continue;
          scan.violations.push_back(where + "Ceres is included only by fitting/ and "
                                    "calibration/geometry.cc (docs/design.md section 5)");
        }
      }
    }
  }
  return scan;
}

const std::set<std::string> kCeresUsers = {"fitting", "calibration/geometry.cc"};

std::string Joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += "  " + l + "\n";
  return s;
}

TEST(Layering, EveryIncludeOfEveryLibraryFolderFollowsTheDesign) {
  const Layers layers = ParseLayers(ReadText(kSourceDir + "/docs/design.md"));
  ASSERT_GE(layers.order.size(), 10u) << "no ```layers block in docs/design.md section 5";
  const Scan scan = CheckIncludes(kSourceDir, layers, kCeresUsers);
  EXPECT_TRUE(scan.violations.empty()) << scan.violations.size()
                                       << " includes break the layering:\n"
                                       << Joined(scan.violations);
  // A scan that finds nothing proves nothing (272 files and 874 includes when this was written).
  EXPECT_GT(scan.files, 200);
  EXPECT_GT(scan.includes_checked, 600);
  std::printf("layering: %d includes in %d files of %zu folders checked\n", scan.includes_checked,
              scan.files, layers.order.size());
  ::testing::Test::RecordProperty("includes_checked", scan.includes_checked);
  ::testing::Test::RecordProperty("files", scan.files);
}

TEST(Layering, TheBlockListsEveryLibraryAndOnlyLowerFolders) {
  const Layers layers = ParseLayers(ReadText(kSourceDir + "/docs/design.md"));
  // Every folder that builds a library (zbrdf_library in its CMakeLists.txt) has a line.
  for (const auto& entry : fs::directory_iterator(kSourceDir)) {
    const fs::path cmake = entry.path() / "CMakeLists.txt";
    if (!entry.is_directory() || !fs::exists(cmake)) continue;
    if (ReadText(cmake.string()).find("zbrdf_library(") == std::string::npos) continue;
    const std::string folder = entry.path().filename().string();
    EXPECT_TRUE(layers.allowed.count(folder)) << folder << "/ builds a library but has no line in "
                                              << "the layers block of docs/design.md";
  }
  // Bottom to top: a folder may include only folders listed above it, so the layers form no
  // cycle and the block reads as the build order.
  std::set<std::string> below;
  for (const std::string& folder : layers.order) {
    for (const std::string& dep : layers.allowed.at(folder)) {
      EXPECT_TRUE(below.count(dep)) << folder << " may include " << dep
                                    << ", which the block lists after it";
    }
    below.insert(folder);
  }
}

TEST(Layering, TheReadmeLayoutTableListsTheLibrariesInTheSameOrder) {
  const Layers layers = ParseLayers(ReadText(kSourceDir + "/docs/design.md"));
  const std::string readme = ReadText(kSourceDir + "/README.md");
  size_t previous = 0;
  std::string previous_folder = "(start)";
  for (const std::string& folder : layers.order) {
    if (folder == "fuzz") continue;  // not a library
    const size_t at = readme.find("| `" + folder + "/` |");
    ASSERT_NE(at, std::string::npos) << folder << "/ is missing from README.md's layout table";
    EXPECT_GT(at, previous) << folder << "/ comes before " << previous_folder
                            << "/ in README.md's layout table";
    previous = at;
    previous_folder = folder;
  }
}

// The checker itself, on a tree with known faults: it must name the file and the line.
TEST(Layering, AForbiddenIncludeIsNamedByFileAndLine) {
  const fs::path root = fs::temp_directory_path() / "zbrdf-layering-test";
  fs::remove_all(root);
  fs::create_directories(root / "low");
  fs::create_directories(root / "high" / "sub");
  std::ofstream(root / "low" / "a.h") << "#pragma once\n";
  std::ofstream(root / "low" / "b.cc") << "// the low layer\n#include <vector>\n"
                                       << "#include \"low/a.h\"\n#include \"high/c.h\"\n";
  std::ofstream(root / "high" / "c.h") << "#pragma once\n#include \"low/a.h\"\n";
  std::ofstream(root / "high" / "sub" / "d.cc") << "#include <ceres/ceres.h>\n"
                                                << "#include \"elsewhere/x.h\"\n";
  Layers layers;
  layers.order = {"low", "high"};
  layers.allowed = {{"low", {}}, {"high", {"low"}}};
  const Scan scan = CheckIncludes(root.string(), layers, {"low"});
  const std::vector<std::string> expected = {
      "low/b.cc:4: #include \"high/c.h\": low/ may include only itself (docs/design.md section "
      "5)",
      "high/sub/d.cc:1: Ceres is included only by fitting/ and calibration/geometry.cc "
      "(docs/design.md section 5)"};
  EXPECT_EQ(scan.violations, expected);
  EXPECT_EQ(scan.includes_checked, 4);  // low/a.h twice, high/c.h, ceres; elsewhere/ is not ours
  fs::remove_all(root);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
