// The libraries compile in unity batches (cmake/ZbrdfLibrary.cmake): eight sources of a folder
// are one translation unit, in an order that shifts whenever a file is added. So no two sources
// of a folder may declare the same file-local name: in the anonymous namespace (helpers,
// constants, types) or through a using-declaration or alias at namespace scope. Two such
// definitions are a compile error in one batch and not in another; two overloads of one name
// with different parameters compile and may call the other file's helper. And no source may put
// a `using namespace` directive at namespace scope, since it reaches the sources after it. Held
// here on the sources, independently of how today's batches fall.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;

const std::string kSourceDir = ZBRDF_SOURCE_DIR;

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool IsIdentifierChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// A file-local declaration: its name, where it is, and whether it may legally be repeated with the
// same text (a using-declaration, an alias or a namespace alias naming the same thing).
struct LocalName {
  std::string name;
  std::string where;  // "folder/file.cc:line"
  std::string text;   // the declaration's line, trimmed
  bool repeatable = false;
};

// The names a column-0 line of an anonymous namespace declares: the first identifier that is
// followed, outside brackets, by ( = { [ ; or , and the first one after each top-level comma
// (`const Scalar kGrid(1), kText(2);`). Keywords, `operator` and `__attribute__((...))` are
// skipped.
std::vector<std::string> DeclaredNames(const std::string& line) {
  static const std::set<std::string> kSkip = {"operator", "const",        "constexpr", "static",
                                              "inline",   "return",       "noexcept",  "override",
                                              "final",    "__attribute__"};
  std::vector<std::string> names;
  int depth = 0;
  bool want = true;  // looking for the next declarator's name
  std::string last;  // the identifier just read at depth 0
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (line.compare(i, 2, "//") == 0) break;
    if (c == '"') {  // skip a string literal
      for (++i; i < line.size() && line[i] != '"'; ++i) {
        if (line[i] == '\\') ++i;
      }
      last.clear();
      continue;
    }
    if (IsIdentifierChar(c)) {
      size_t j = i;
      while (j < line.size() && IsIdentifierChar(line[j])) ++j;
      if (depth == 0) last = line.substr(i, j - i);
      i = j - 1;
      continue;
    }
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    if (depth == 0 && want && !last.empty() && !std::isdigit(static_cast<unsigned char>(last[0])) &&
        !kSkip.count(last) &&
        (c == '(' || c == '=' || c == '{' || c == '[' || c == ';' || c == ',')) {
      names.push_back(last);
      want = false;
    }
    if (c == '(' || c == '{' || c == '[' || c == '<') ++depth;
    if ((c == ')' || c == '}' || c == ']' || c == '>') && depth > 0) --depth;
    if (depth == 0 && c == ',') want = true;
    if (c == ':' && i + 1 < line.size() && line[i + 1] == ':') ++i;  // a qualified name goes on
    last.clear();
  }
  return names;
}

std::string Trimmed(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t");
  const size_t e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

struct FileScan {
  std::vector<LocalName> names;
  std::vector<std::string> violations;  // `using namespace` at namespace scope
};

// The file-local names of one source (`label` names it in messages). Declarations start at column
// 0 (the project's format); an anonymous namespace opens with `namespace {` and closes with
// `}  // namespace` on lines of their own.
FileScan ScanSource(const std::string& label, const std::string& text) {
  FileScan scan;
  std::istringstream in(text);
  std::string line;
  bool anonymous = false;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string where = label + ":" + std::to_string(number);
    const std::string trimmed = Trimmed(line);
    if (line.rfind("namespace {", 0) == 0) {
      anonymous = true;
      continue;
    }
    if (anonymous && line.rfind("}", 0) == 0 && trimmed.find("// namespace") != std::string::npos &&
        Trimmed(trimmed.substr(trimmed.find("// namespace") + 12)).empty()) {
      anonymous = false;
      continue;
    }
    if (line.empty() || !(IsIdentifierChar(line[0]) || line[0] == '[')) continue;
    if (line.rfind("using namespace ", 0) == 0) {
      scan.violations.push_back(where + ": `" + trimmed +
                                "` at namespace scope reaches every "
                                "source after it in a unity batch; qualify the names, or put it "
                                "inside a function");
      continue;
    }
    // Using-declarations, aliases and namespace aliases at namespace scope are file-local too.
    if (line.rfind("using ", 0) == 0 ||
        (line.rfind("namespace ", 0) == 0 && line.find('=') != std::string::npos)) {
      std::string rest = line.substr(line.find(' ') + 1);
      const size_t end = rest.find_first_of("=;");
      std::string name = Trimmed(rest.substr(0, end));
      if (const size_t colons = name.rfind("::"); colons != std::string::npos) {
        name = name.substr(colons + 2);
      }
      if (!name.empty()) scan.names.push_back({name, where, trimmed, true});
      continue;
    }
    if (!anonymous || line.rfind("template", 0) == 0 || line.rfind("namespace", 0) == 0) continue;
    for (const char* key : {"struct ", "class ", "enum class ", "enum ", "union "}) {
      if (line.rfind(key, 0) == 0) {
        std::string rest = line.substr(std::string(key).size());
        size_t n = 0;
        while (n < rest.size() && IsIdentifierChar(rest[n])) ++n;
        if (n > 0) scan.names.push_back({rest.substr(0, n), where, trimmed, false});
        line.clear();
        break;
      }
    }
    if (line.empty()) continue;
    for (const std::string& name : DeclaredNames(line)) {
      scan.names.push_back({name, where, trimmed, false});
    }
  }
  return scan;
}

// Clashes between the sources of one unity group: the same name declared file-locally in two
// files, unless both are the same repeatable declaration.
std::vector<std::string> Clashes(const std::map<std::string, FileScan>& files) {
  std::map<std::string, std::vector<std::pair<std::string, const LocalName*>>> by_name;
  for (const auto& [file, scan] : files) {
    std::set<std::string> seen;  // a file may overload its own helpers
    for (const LocalName& n : scan.names) {
      if (seen.insert(n.name).second) by_name[n.name].push_back({file, &n});
    }
  }
  std::vector<std::string> clashes;
  for (const auto& [name, uses] : by_name) {
    if (uses.size() < 2) continue;
    // (Named here: clang 14 cannot capture a structured binding in a lambda.)
    const std::string& first_text = uses.front().second->text;
    const bool harmless = std::all_of(uses.begin(), uses.end(), [&](const auto& u) {
      return u.second->repeatable && u.second->text == first_text;
    });
    if (harmless) continue;
    std::string message = name + " is declared file-locally in " + std::to_string(uses.size()) +
                          " sources of one unity batch group:";
    for (const auto& u : uses) message += " " + u.second->where;
    clashes.push_back(message + "; give each its own name, or share one in a header");
  }
  return clashes;
}

// The unity groups of the tree: every folder of .cc files that a library, the CLI's object
// library or the Python module compiles (one or two levels down; tests/ and bench/ are not
// compiled in unity batches of this kind), and the fuzz stage's readers.
std::map<std::string, std::vector<fs::path>> UnityGroups(const std::string& root,
                                                         const std::string& extension = ".cc") {
  static const std::set<std::string> kNotLibraries = {"tests", "fuzz",    "bench", "docs",
                                                      "data",  "scripts", "cmake"};
  std::map<std::string, std::vector<fs::path>> groups;
  for (const auto& top : fs::directory_iterator(root)) {
    const std::string name = top.path().filename().string();
    if (!top.is_directory() || kNotLibraries.count(name) || name[0] == '.' ||
        name.rfind("build", 0) == 0) {
      continue;
    }
    std::vector<fs::path> dirs = {top.path()};
    for (const auto& sub : fs::directory_iterator(top.path())) {
      if (sub.is_directory()) dirs.push_back(sub.path());
    }
    for (const fs::path& dir : dirs) {
      for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.is_regular_file() && entry.path().extension() == extension) {
          groups[fs::relative(dir, root).string()].push_back(entry.path());
        }
      }
    }
  }
  // The fuzz stage compiles the readers' sources of several folders as one library, in unity
  // batches too (fuzz/CMakeLists.txt): those sources are one more group.
  const std::string fuzz = ReadText(fs::path(root) / "fuzz" / "CMakeLists.txt");
  const size_t list = fuzz.find("set(zbrdf_fuzz_sources");
  if (extension == ".cc" && list != std::string::npos) {
    std::istringstream words(fuzz.substr(list + 23, fuzz.find(')', list) - list - 23));
    for (std::string word; words >> word;) groups["fuzz readers"].push_back(fs::path(root) / word);
  }
  return groups;
}

// The names the project's headers declare at column 0 outside anonymous namespaces (functions,
// constants, types of every library's public interface), with where. A file-local name equal to
// one of them overloads or hides it in every unity batch whose sources include that header.
std::map<std::string, std::string> HeaderNames(const std::string& root) {
  std::map<std::string, std::string> names;
  for (const auto& [group, paths] : UnityGroups(root, ".h")) {
    for (const fs::path& path : paths) {
      const std::string label = fs::relative(path, root).string();
      const std::string text = ReadText(path);
      // Scan the header as if it were all one anonymous namespace: same column-0 rules.
      for (const LocalName& n : ScanSource(label, "namespace {\n" + text).names) {
        if (n.repeatable) continue;
        names.emplace(
            n.name,
            label + ":" + std::to_string(std::stoi(n.where.substr(n.where.rfind(':') + 1)) - 1));
      }
    }
  }
  return names;
}

std::string Joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += "  " + l + "\n";
  return s;
}

TEST(UnityNames, NoTwoSourcesOfALibraryShareAFileLocalName) {
  const auto groups = UnityGroups(kSourceDir);
  const auto header_names = HeaderNames(kSourceDir);
  std::vector<std::string> problems;
  size_t names = 0, files = 0;
  for (const auto& [group, paths] : groups) {
    std::map<std::string, FileScan> scans;
    for (const fs::path& path : paths) {
      const std::string label = fs::relative(path, kSourceDir).string();
      scans[label] = ScanSource(label, ReadText(path));
      names += scans[label].names.size();
      ++files;
      for (const std::string& v : scans[label].violations) problems.push_back(v);
    }
    for (const std::string& c : Clashes(scans)) problems.push_back(c);
    for (const auto& [file, scan] : scans) {
      for (const LocalName& n : scan.names) {
        // A using-declaration names the header's entity itself; an alias or helper does not.
        if (n.repeatable && n.text.find('=') == std::string::npos) continue;
        if (auto h = header_names.find(n.name); h != header_names.end()) {
          problems.push_back(n.where + ": " + n.name + " is file-local here and declared in " +
                             h->second +
                             "; in a unity batch with a source that includes that "
                             "header the two clash or overload: rename the file-local one");
        }
      }
    }
  }
  EXPECT_TRUE(problems.empty()) << problems.size() << " unity-build hazards:\n" << Joined(problems);
  // A scan that finds nothing proves nothing (944 names in 225 sources of 13 groups when
  // this was written).
  EXPECT_GE(groups.size(), 13u);
  EXPECT_GT(files, 200u);
  EXPECT_GT(names, 700u);
  std::printf("unity names: %zu file-local names in %zu sources of %zu groups\n", names, files,
              groups.size());
}

// The scanner itself, on sources with known hazards.
TEST(UnityNames, TheScannerFindsHelpersConstantsTypesAndAliases) {
  const FileScan scan = ScanSource("a.cc",
                                   "#include \"x.h\"\n"
                                   "namespace zbrdf {\n"
                                   "namespace {\n"
                                   "\n"
                                   "namespace fs = std::filesystem;\n"
                                   "constexpr char kFormat[] = \"zbrdf-x-v1\";\n"
                                   "const cv::Scalar kGrid(215, 215, 215), kText(40, 40, 40);\n"
                                   "[[noreturn]] void Fail(const std::string& what) {\n"
                                   "  throw Error(what);  // indented: not a declaration\n"
                                   "}\n"
                                   "std::vector<std::pair<int, int>> Pairs(int n);\n"
                                   "struct Contents {\n"
                                   "  int size;\n"
                                   "};\n"
                                   "enum class Mode { kA, kB };\n"
                                   "template <typename T>\n"
                                   "T Twice(T x) { return x + x; }\n"
                                   "bool operator<(const Contents& a, const Contents& b);\n"
                                   "__attribute__((target(\"avx2\"))) double SumAvx2(int n);\n"
                                   "\n"
                                   "}  // namespace\n"
                                   "\n"
                                   "using plot::Text;\n"
                                   "double Public(double x) { return x; }\n"
                                   "}  // namespace zbrdf\n");
  std::vector<std::string> names;
  for (const LocalName& n : scan.names) names.push_back(n.name);
  const std::vector<std::string> expected = {"fs",    "kFormat", "kGrid",    "kText",
                                             "Fail",  "Pairs",   "Contents", "Mode",
                                             "Twice", "SumAvx2", "Text"};
  EXPECT_EQ(names, expected);
  EXPECT_TRUE(scan.violations.empty());
  EXPECT_EQ(scan.names.back().where, "a.cc:23");
}

TEST(UnityNames, ClashesAreNamedAndRepeatedAliasesAreNot) {
  std::map<std::string, FileScan> files;
  files["a.cc"] = ScanSource("a.cc",
                             "namespace {\n"
                             "namespace fs = std::filesystem;\n"
                             "double Since(Clock::time_point t) { return 0; }\n"
                             "using plot::Text;\n"
                             "}  // namespace\n");
  files["b.cc"] = ScanSource("b.cc",
                             "namespace {\n"
                             "namespace fs = std::filesystem;\n"
                             "double Since(int t) { return 1; }\n"
                             "}  // namespace\n"
                             "using other::Text;\n"
                             "using namespace plot;\n");
  const std::vector<std::string> clashes = Clashes(files);
  ASSERT_EQ(clashes.size(), 2u) << Joined(clashes);
  EXPECT_NE(clashes[0].find("Since"), std::string::npos);
  EXPECT_NE(clashes[0].find("a.cc:3"), std::string::npos);
  EXPECT_NE(clashes[0].find("b.cc:3"), std::string::npos);
  EXPECT_NE(clashes[1].find("Text"), std::string::npos);  // two different using-declarations
  ASSERT_EQ(files["b.cc"].violations.size(), 1u);
  EXPECT_NE(files["b.cc"].violations[0].find("b.cc:6"), std::string::npos);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
