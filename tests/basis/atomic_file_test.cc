#include "basis/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "basis/error.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

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

// The fault seam (tests/tools/crash_test.cc drives it at scale): each plan is undone by the
// fixture's TearDown, so that no fault leaks into another test.
class AtomicFileFaultTest : public AtomicFileTest {
 protected:
  void TearDown() override {
    SetWriteFaultPlan({});
    AtomicFileTest::TearDown();
  }
  // Names in dir_ other than `keep`.
  std::vector<std::string> Others(const std::string& keep) const {
    std::vector<std::string> out;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      if (entry.path().filename() != keep) out.push_back(entry.path().filename().string());
    }
    return out;
  }
};

// Disk full while writing: the error names the final file (not the temporary), the bytes it
// needed and the space free, and the next step; the previous file is untouched and no temporary
// is left (issue 15: "disk-full errors name the temp file and no next step").
TEST_F(AtomicFileFaultTest, DiskFullLeavesThePreviousFileAndNamesTheFinalOne) {
  const std::string path = dir_ + "/zonal.exr";
  WriteFileAtomically(path, "the good file");
  SetWriteFaultPlan({WriteFault::kNoSpace, 1, 0.2, ""});
  const std::string bytes(2100000, 'x');
  try {
    WriteFileAtomically(path, bytes);
    FAIL() << "expected FileWriteError";
  } catch (const FileWriteError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.path(), path);
    EXPECT_EQ(e.error_number(), ENOSPC);
    EXPECT_TRUE(e.out_of_space());
    EXPECT_EQ(e.bytes_needed(), bytes.size());
    EXPECT_EQ(what.rfind("disk full writing " + path + " (needs about 2.1 MB, ", 0), 0u) << what;
    EXPECT_NE(what.find(" free): free space and run the command again"), std::string::npos) << what;
    EXPECT_EQ(what.find(".tmp"), std::string::npos) << "names the temporary file: " << what;
    const FileWriteError resume = e.WithNextStep("continue with the same command plus --resume");
    EXPECT_NE(std::string(resume.what())
                  .find("free space and continue with the same command "
                        "plus --resume"),
              std::string::npos)
        << resume.what();
  }
  EXPECT_EQ(Slurp(path), "the good file");
  EXPECT_TRUE(Others("zonal.exr").empty());
}

TEST_F(AtomicFileFaultTest, IoErrorAtFsyncIsReportedAndNothingIsReplaced) {
  const std::string path = dir_ + "/frame.tiff";
  WriteFileAtomically(path, "old");
  SetWriteFaultPlan({WriteFault::kIoError, 1, 1.0, ""});
  try {
    WriteFileAtomically(path, "new bytes");
    FAIL() << "expected FileWriteError";
  } catch (const FileWriteError& e) {
    EXPECT_EQ(e.error_number(), EIO);
    EXPECT_FALSE(e.out_of_space());
    EXPECT_NE(std::string(e.what()).find("I/O error writing " + path), std::string::npos);
  }
  EXPECT_EQ(Slurp(path), "old");
  EXPECT_TRUE(Others("frame.tiff").empty());
}

// write() may move fewer bytes than asked; the helper goes on until all are written.
TEST_F(AtomicFileFaultTest, ShortWritesStillGiveTheWholeFile) {
  const std::string path = dir_ + "/f.bin";
  std::string bytes;
  for (int i = 0; i < 100000; ++i) bytes += static_cast<char>(i * 7 + 3);
  SetWriteFaultPlan({WriteFault::kShortWrites, 1, 0.5, ""});
  WriteFileAtomically(path, bytes);
  EXPECT_EQ(Slurp(path), bytes);
  SetWriteFaultPlan({WriteFault::kShortWrites, 1, 0.5, ""});
  AppendToFile(path, "tail");
  EXPECT_EQ(Slurp(path), bytes + "tail");
}

// Operations are counted from 1, across both writers; path_contains counts only matching paths.
TEST_F(AtomicFileFaultTest, TheFaultHitsThePlannedOperationOnly) {
  SetWriteFaultPlan({WriteFault::kNoSpace, 2, 0.0, "b.txt"});
  const int64_t before = WriteOperationCount();
  WriteFileAtomically(dir_ + "/b.txt", "1");  // first b.txt: fine
  WriteFileAtomically(dir_ + "/a.txt", "2");  // not counted by the plan
  EXPECT_THROW(WriteFileAtomically(dir_ + "/b.txt", "3"), FileWriteError);
  WriteFileAtomically(dir_ + "/b.txt", "4");  // only the planned one fails
  EXPECT_EQ(WriteOperationCount() - before, 4);
  EXPECT_EQ(Slurp(dir_ + "/b.txt"), "4");
  EXPECT_EQ(ParseWriteFault(WriteFaultName(WriteFault::kShortWrites)), WriteFault::kShortWrites);
  EXPECT_THROW(ParseWriteFault("flood"), InputError);
}

// A full disk while a journal line is appended leaves no partial line: the file is cut back.
TEST_F(AtomicFileFaultTest, AFailedAppendIsCutBackToThePreviousLength) {
  const std::string path = dir_ + "/journal.jsonl";
  AppendToFile(path, "{\"index\":0}\n");
  SetWriteFaultPlan({WriteFault::kNoSpace, 1, 0.5, ""});
  try {
    AppendToFile(path, "{\"index\":1,\"lobe\":\"dark\"}\n");
    FAIL() << "expected FileWriteError";
  } catch (const FileWriteError& e) {
    EXPECT_NE(std::string(e.what()).find("disk full writing " + path), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(Slurp(path), "{\"index\":0}\n");
  TruncateFile(path, 3);
  EXPECT_EQ(Slurp(path), "{\"i");
}

// A process killed mid-write (SIGKILL, as the seam does it) leaves the previous file and its
// temporary; the temporary is recognized, kept while its process runs, and removed after.
TEST_F(AtomicFileFaultTest, AKilledWriterLeavesOnlyATemporaryThatIsCleanedUp) {
  const std::string path = dir_ + "/zonal.exr";
  WriteFileAtomically(path, "good");
  for (const double fraction : {0.0, 0.5, 1.0}) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      SetWriteFaultPlan({WriteFault::kKill, 1, fraction, ""});
      WriteFileAtomically(path, std::string(1000, 'n'));
      ::_exit(0);  // not reached
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << fraction;
    EXPECT_EQ(Slurp(path), "good") << fraction;
    const std::string leftover = "zonal.exr.tmp" + std::to_string(child);
    EXPECT_EQ(Others("zonal.exr"), std::vector<std::string>{leftover}) << fraction;
    EXPECT_TRUE(IsTemporaryFileName(leftover));
    EXPECT_EQ(fs::file_size(dir_ + "/" + leftover), static_cast<uintmax_t>(1000 * fraction));
    EXPECT_EQ(RemoveStaleTemporaryFiles(dir_), std::vector<std::string>{leftover});
    EXPECT_TRUE(Others("zonal.exr").empty());
  }
  // A running process's (here our own) temporary is kept, and so are other names.
  WriteFileAtomically(TemporaryFileName(path), "in flight");
  WriteFileAtomically(dir_ + "/notes.tmp", "a user's file");
  WriteFileAtomically(dir_ + "/x.tmp1", "pid 1 runs");
  EXPECT_TRUE(RemoveStaleTemporaryFiles(dir_).empty());
  EXPECT_FALSE(IsTemporaryFileName("notes.tmp"));
  EXPECT_FALSE(IsTemporaryFileName(".tmp123"));
}

TEST(AtomicFile, FormatsBytesInDecimalUnits) {
  EXPECT_EQ(FormatBytes(512), "512 bytes");
  EXPECT_EQ(FormatBytes(2100), "2.1 kB");
  EXPECT_EQ(FormatBytes(2100000), "2.1 MB");
  EXPECT_EQ(FormatBytes(1300000000), "1.3 GB");
}

// Permission errors say so and name the folder to fix (root may write anywhere: skipped then).
TEST_F(AtomicFileTest, PermissionDeniedNamesTheFolder) {
  const FileWriteError denied("out/m.bsdf", EACCES, 10, 0);
  EXPECT_STREQ(denied.what(),
               "permission denied writing out/m.bsdf: make out writable for you, "
               "or write elsewhere, and run the command again");
  // The operating system's refusal. Root writes to read-only folders, so as root the write is
  // tried from a child process that has given up root for the unprivileged user 65534 (nobody).
  const std::string sub = dir_ + "/locked";
  fs::create_directories(sub);
  fs::permissions(dir_, fs::perms::owner_all | fs::perms::others_exec);
  fs::permissions(sub, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::others_read |
                           fs::perms::others_exec);
  const std::string expected =
      "permission denied writing " + sub + "/f: make " + sub + " writable";
  // Exit codes of the child: 0 the expected error, 1 another message, 2 no error, 3 another
  // exception, 4 could not drop root.
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) ::_exit(4);
    try {
      WriteFileAtomically(sub + "/f", "x");
    } catch (const FileWriteError& e) {
      ::_exit(std::string(e.what()).find(expected) != std::string::npos ? 0 : 1);
    } catch (...) {
      ::_exit(3);
    }
    ::_exit(2);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "0: the error '" << expected
                                    << "...', 1: another message, 2: no error, 3: another "
                                       "exception, 4: could not drop root";
  EXPECT_FALSE(fs::exists(sub + "/f"));
  fs::permissions(sub, fs::perms::owner_all);
}

TEST_F(AtomicFileTest, CacheEntriesHaveOneWriterAndReadersSeeAWholeFile) {
  // Eight threads write the same entry at once, each with its own 1 MB payload: the entry ends as
  // exactly one of them (never a mixture), and no temporary or claim file is left.
  const std::string path = dir_ + "/entry.bin";
  std::vector<std::string> payloads;
  for (int i = 0; i < 8; ++i) payloads.push_back(std::string(1 << 20, static_cast<char>('a' + i)));
  std::atomic<int> written{0};
  std::vector<std::thread> writers;
  for (int i = 0; i < 8; ++i) {
    writers.emplace_back([&, i] {
      const std::string_view part(payloads[i]);
      written += WriteCacheFile(path, {part.substr(0, 1000), part.substr(1000)});
    });
  }
  for (auto& t : writers) t.join();
  EXPECT_GE(written.load(), 1);
  const std::string entry = Slurp(path);
  ASSERT_EQ(entry.size(), size_t{1} << 20);
  EXPECT_EQ(entry, std::string(entry.size(), entry[0])) << "a mixture of writers";
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);

  // A writer holding the entry keeps others out; a claim left by a writer that died (older than
  // 10 minutes) is taken over.
  WriteFileAtomically(path + ".writing", "");
  EXPECT_FALSE(WriteCacheFile(path, {"other"}));
  EXPECT_EQ(Slurp(path), entry);
  fs::last_write_time(path + ".writing", fs::file_time_type::clock::now() - std::chrono::minutes(11));
  EXPECT_TRUE(WriteCacheFile(path, {"other"}));
  EXPECT_EQ(Slurp(path), "other");
  EXPECT_FALSE(fs::exists(path + ".writing"));
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
