#include "basis/atomic_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "basis/error.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = (fs::temp_directory_path() / ("zbrdf-atomic-file-" + std::to_string(::getpid())))
               .string();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string dir_;
};

TEST_F(AtomicFileTest, WritesAndReplacesTheWholeFileAndLeavesNoTemporary) {
  const std::string path = dir_ + "/f.bin";
  const std::string first("first\0with a NUL", 16);
  WriteFileAtomically(path, first);
  EXPECT_EQ(Slurp(path), first);
  WriteFileAtomically(path, "second, longer than the first");
  EXPECT_EQ(Slurp(path), "second, longer than the first");
  WriteFileAtomically(path, "");
  EXPECT_TRUE(fs::exists(path));
  EXPECT_EQ(fs::file_size(path), 0u);
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir_)) ++entries;
  EXPECT_EQ(entries, 1) << "the temporary file must be renamed, not left behind";
}

TEST_F(AtomicFileTest, AMissingFolderIsAnInputErrorNamingTheFile) {
  const std::string path = dir_ + "/no-such-folder/f.json";
  try {
    WriteFileAtomically(path, "{}");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir_ + "/no-such-folder"));
}

}  // namespace
}  // namespace zbrdf
