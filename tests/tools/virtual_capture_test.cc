// Captures and re-processing through the zbrdf binary (zbrdf capture and zbrdf process on the
// virtual rig, tools/virtual_capture.h): the cases of issue 15 as a user meets them. A session
// that is what its session.json and journal say; a journal that survives a torn line; outputs
// replaced whole; one writer at a time; options checked before anything is written; errors that
// name the file and the next step. The sessions are the fast thesis rig's, order 1, one exposure,
// simulated once (tests/tools/simulated_sessions.h) and copied.
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tiffio.h>
#include <tiffio.hxx>

#include "acquisition/frame_file.h"
#include "acquisition/session.h"
#include "tests/tools/simulated_sessions.h"
#include "tests/tools/tools_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;
using testing::ReadFile;
using testing::RunZbrdf;
using testing::TempDir;
using testing::WriteFile;

// A processed session of lambert:0.5 (8 frames), shared with the crash harness.
std::string SourceSession() {
  testing::SessionOptions o;
  o.exposures = 1;
  o.shortest_exposure_us = 40000;
  o.tag = "-crash";
  return testing::SimulatedSession("lambert:0.5", 1, o);
}

// A copy of the source session's frames, journal and session.json.
std::string CopySession(const TempDir& tmp, const std::string& name) {
  const std::string source = SourceSession(), dir = tmp.File(name);
  fs::create_directories(dir);
  fs::copy(source + "/frames", dir + "/frames", fs::copy_options::recursive);
  for (const char* f : {kSessionFile, kJournalFile}) fs::copy_file(source + "/" + f, dir + "/" + f);
  return dir;
}

std::string CaptureArgs(const std::string& out) {
  return "capture --rig " + testing::ThesisRigPath() +
         " --preset fast --order 1 --exposures 1 --shortest-exposure-us 40000 --no-hdr-images "
         "--out " +
         out;
}

double SecondsOf(const std::function<void()>& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Runs zbrdf with a file size limit (RLIMIT_FSIZE): writes past it fail with EFBIG, as on a
// full disk, through any writer. Returns the exit status; stderr goes to err.
int RunZbrdfWithFileSizeLimit(const std::vector<std::string>& args, rlim_t limit_bytes,
                              const std::string& err) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const rlimit limit = {limit_bytes, limit_bytes};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    ::signal(SIGXFSZ, SIG_IGN);                           // EFBIG instead of the signal
    if (!freopen(err.c_str(), "w", stderr)) ::_exit(99);  // the test's own capture of stderr
    if (!freopen("/dev/null", "w", stdout)) ::_exit(99);
    std::vector<char*> argv;
    const std::string binary = testing::ZbrdfBinary();
    argv.push_back(const_cast<char*>(binary.c_str()));
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(binary.c_str(), argv.data());
    ::_exit(98);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Issue 15, case 1: "a lambert:0.5 capture into a folder left by a blue-acrylic session reported
// frames_captured 0, frames_reused 150, exit 0". Now refused, naming what is there; --force-new
// moves it aside; a disk filling during the new capture names the frame and --resume.
TEST(VirtualCapture, AFolderWithoutSessionJsonIsRefusedAndForceNewMovesItAside) {
  TempDir tmp("virtual-capture-orphan");
  const std::string dir = CopySession(tmp, "s");
  fs::remove(dir + "/session.json");
  const std::string journal = ReadFile(dir + "/journal.jsonl");
  const std::string args = CaptureArgs(dir) + " --material ggx:alpha=0.3 --json";
  double seconds = 0;
  int code = 0;
  seconds = SecondsOf([&] { code = RunZbrdf(args, tmp.File("out.json"), tmp.File("err.txt")); });
  EXPECT_EQ(code, 2) << ReadFile(tmp.File("out.json"));
  const std::string err = ReadFile(tmp.File("err.txt"));
  EXPECT_NE(err.find("holds no session.json (found frames/ (8 files), journal.jsonl)"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("--force-new"), std::string::npos) << err;
  EXPECT_LT(seconds, 5.0) << "refused before the virtual rig is built";
  EXPECT_EQ(ReadFile(dir + "/journal.jsonl"), journal);

  // --force-new, and the disk fills at the third frame: the error names it and --resume.
  const std::string faulted = "ZBRDF_WRITE_FAULT=nospace:3:0.5:frames/ " +
                              std::string(ZBRDF_BINARY_DIR) + "/zbrdf-faults " + args +
                              " --force-new >/dev/null 2>" + tmp.File("err.txt");
  EXPECT_EQ(WEXITSTATUS(std::system(faulted.c_str())), 2);
  const std::string full = ReadFile(tmp.File("err.txt"));
  EXPECT_NE(full.find("disk full writing " + dir + "/frames/f000002.tiff (needs about "),
            std::string::npos)
      << full;
  EXPECT_NE(full.find("free): free space and continue with the same command plus --resume"),
            std::string::npos)
      << full;
  bool moved = false;
  for (const auto& entry : fs::directory_iterator(tmp.path())) {
    if (entry.path().filename().string().rfind("s.before-", 0) == 0) {
      moved = ReadFile(entry.path().string() + "/journal.jsonl") == journal;
    }
  }
  EXPECT_TRUE(moved) << "the old folder is kept whole beside the new one";
  ASSERT_EQ(RunZbrdf(args + " --resume", tmp.File("out.json"), tmp.File("err.txt")), 0)
      << ReadFile(tmp.File("err.txt"));
  const nlohmann::json report = nlohmann::json::parse(ReadFile(tmp.File("out.json")));
  EXPECT_EQ(report["frames_reused"], 2);
  EXPECT_EQ(report["frames_captured"], 6);
  EXPECT_EQ(SessionFolder::Open(dir).material(), "ggx:alpha=0.3,F0=0.04,kd=0");
}

// Issue 15, case 2: "--resume appends its next line onto the fragment, that frame drops out of
// the journal, resume reports complete: true with exit 0, and zbrdf process then fails".
TEST(VirtualCapture, ATornJournalLineIsRepairedOnResumeAndProcessFindsEveryFrame) {
  TempDir tmp("virtual-capture-torn");
  const std::string dir = CopySession(tmp, "s");
  std::string journal = ReadFile(dir + "/journal.jsonl");
  size_t cut = 0;
  for (int line = 0; line < 5; ++line) cut = journal.find('\n', cut) + 1;
  const std::string fragment = journal.substr(cut, (journal.find('\n', cut) - cut) / 2);
  WriteFile(dir + "/journal.jsonl", journal.substr(0, cut) + fragment);
  ASSERT_EQ(RunZbrdf(CaptureArgs(dir) + " --resume", tmp.File("out.txt"), tmp.File("err.txt")), 0)
      << ReadFile(tmp.File("err.txt"));
  EXPECT_NE(ReadFile(tmp.File("out.txt")).find("repaired: cut a torn last line from the journal"),
            std::string::npos)
      << ReadFile(tmp.File("out.txt"));
  EXPECT_EQ(ReadFile(dir + "/journal.jsonl.torn-1"), fragment);
  EXPECT_EQ(SessionFolder::Open(dir).ReadJournal().size(), 8u);
  EXPECT_EQ(RunZbrdf("process " + dir + " --no-hdr-images", "/dev/null", tmp.File("err.txt")), 0)
      << ReadFile(tmp.File("err.txt"));
}

// A process that holds a session's writer lock until killed (as a running capture would).
pid_t HoldLock(const std::string& dir) {
  int ready[2];
  EXPECT_EQ(::pipe(ready), 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(ready[0]);
    const SessionFolder s = SessionFolder::OpenForWriting(dir);
    char c = 1;
    (void)!::write(ready[1], &c, 1);
    while (true) ::pause();
  }
  ::close(ready[1]);
  char c = 0;
  EXPECT_EQ(::read(ready[0], &c, 1), 1);
  ::close(ready[0]);
  return pid;
}

// Issue 15, case 3: "two process runs at once gave an unreadable zonal.exr once and a silently
// mixed one once in 14 tries; two capture --resume at once both exit 0". One writer at a time:
// the second exits at once naming the first's PID; readers do not wait.
TEST(VirtualCapture, ASecondWriterIsRefusedNamingTheFirstAndReadersDoNotWait) {
  TempDir tmp("virtual-capture-lock");
  const std::string dir = CopySession(tmp, "s");
  ASSERT_EQ(RunZbrdf("process " + dir + " --no-hdr-images", "/dev/null", tmp.File("err.txt")), 0);
  const std::string zonal = ReadFile(dir + "/zonal.exr");  // zonal.exr records its session's path
  const pid_t holder = HoldLock(dir);
  const std::string pid = "pid " + std::to_string(holder) + ": ";
  double seconds = 0;
  int code = 0;
  seconds = SecondsOf([&] { code = RunZbrdf("process " + dir, "/dev/null", tmp.File("err.txt")); });
  EXPECT_EQ(code, 2);
  std::string err = ReadFile(tmp.File("err.txt"));
  EXPECT_NE(err.find("session " + dir + " is being written by " + pid), std::string::npos) << err;
  EXPECT_NE(err.find("one process writes a session at a time"), std::string::npos) << err;
  EXPECT_LT(seconds, 5.0);
  seconds = SecondsOf(
      [&] { code = RunZbrdf(CaptureArgs(dir) + " --resume", "/dev/null", tmp.File("err.txt")); });
  EXPECT_EQ(code, 2);
  err = ReadFile(tmp.File("err.txt"));
  EXPECT_NE(err.find("is being written by " + pid), std::string::npos) << err;
  EXPECT_LT(seconds, 5.0) << "refused before the virtual rig is built";
  EXPECT_TRUE(ReadFile(dir + "/zonal.exr") == zonal) << "nothing written";
  // A reader (zbrdf convert reads zonal.exr) does not wait for the writer.
  EXPECT_EQ(RunZbrdf("convert " + dir + " --to sh", "/dev/null", tmp.File("err.txt")), 0)
      << ReadFile(tmp.File("err.txt"));
  ::kill(holder, SIGKILL);  // the kernel releases a killed writer's lock
  ::waitpid(holder, nullptr, 0);
  EXPECT_EQ(RunZbrdf("process " + dir + " --no-hdr-images", "/dev/null", tmp.File("err.txt")), 0)
      << ReadFile(tmp.File("err.txt"));
  EXPECT_TRUE(ReadFile(dir + "/zonal.exr") == zonal);

  // Two at once, for real: each exits 0 or is refused; zonal.exr is always the whole result.
  for (int attempt = 0; attempt < 3; ++attempt) {
    const std::string a = tmp.File("a.txt"), b = tmp.File("b.txt");
    const std::string process = testing::ZbrdfBinary() + " process " + dir + " --no-hdr-images";
    const std::string both = "(" + process + " 2>" + a + " >/dev/null; echo $? >>" + a + ") & (" +
                             process + " 2>" + b + " >/dev/null; echo $? >>" + b + ") & wait";
    ASSERT_EQ(std::system(both.c_str()), 0);
    int succeeded = 0;
    for (const std::string& f : {a, b}) {
      const std::string text = ReadFile(f);  // stderr (progress, errors), then the status
      const std::string status = text.substr(text.rfind('\n', text.size() - 2) + 1);
      const bool ok = status == "0\n";
      const bool refused =
          status == "2\n" && text.find("is being written by ") != std::string::npos;
      EXPECT_TRUE(ok || refused) << text;
      succeeded += ok;
    }
    EXPECT_GE(succeeded, 1);
    EXPECT_TRUE(ReadFile(dir + "/zonal.exr") == zonal) << "whole, and the same result";
  }
}

// Issue 15, case 3: "a kill during zbrdf process leaves a truncated zonal.exr where a good one
// was", and "an HDR image was silently cut to a fifth of its size when the disk filled". A file
// size limit fails the writes as a full disk does: the earlier files stay whole, and the error
// names the final file (not a temporary) and what to do.
TEST(VirtualCapture, AFullDiskDuringProcessLeavesThePreviousFilesWhole) {
  TempDir tmp("virtual-capture-full");
  const std::string dir = CopySession(tmp, "s");
  ASSERT_EQ(RunZbrdf("process " + dir, "/dev/null", tmp.File("err.txt")), 0);
  const std::string zonal = ReadFile(dir + "/zonal.exr");
  const std::string hdr = ReadFile(dir + "/hdr/Z1_0pos.exr");
  ASSERT_GT(zonal.size(), 400000u);
  ASSERT_GT(hdr.size(), 50000u);
  // zonal.exr of a 0.5 x 1 deg grid is larger than the limit; the HDR images are not.
  EXPECT_EQ(
      RunZbrdfWithFileSizeLimit({"process", dir, "--grid", "0.5,1"}, 300000, tmp.File("err.txt")),
      2);
  std::string err = ReadFile(tmp.File("err.txt"));
  EXPECT_NE(err.find("file size limit reached writing " + dir + "/zonal.exr (needs about "),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("and run zbrdf process " + dir + " again (the previous zonal.exr"),
            std::string::npos)
      << err;
  EXPECT_TRUE(ReadFile(dir + "/zonal.exr") == zonal) << "the previous zonal.exr, whole";
  // The HDR images now: each is whole, old or new (here the same bytes).
  EXPECT_EQ(RunZbrdfWithFileSizeLimit({"process", dir}, 30000, tmp.File("err.txt")), 2);
  err = ReadFile(tmp.File("err.txt"));
  EXPECT_NE(err.find("file size limit reached writing " + dir + "/hdr/"), std::string::npos) << err;
  EXPECT_TRUE(ReadFile(dir + "/hdr/Z1_0pos.exr") == hdr) << "the previous HDR image, whole";
  EXPECT_TRUE(ReadFile(dir + "/zonal.exr") == zonal);
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
  }
}

// Issue 15, smaller cases: options and session files are checked before anything is written, and
// errors name the file.
TEST(VirtualCapture, BadOptionsAndDamagedPlansAreNamedBeforeAnythingIsWritten) {
  TempDir tmp("virtual-capture-options");
  // --grid 0,0: refused before the folder exists (and before the rig is built), so the plain
  // rerun is not refused for a folder it left.
  const std::string out = tmp.File("new");
  double seconds = SecondsOf([&] {
    EXPECT_EQ(RunZbrdf(CaptureArgs(out) + " --material lambert:0.5 --grid 0,0", "/dev/null",
                       tmp.File("err.txt")),
              2);
  });
  EXPECT_NE(ReadFile(tmp.File("err.txt")).find("processing.theta_step_deg must be in (0, 10]"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_LT(seconds, 5.0);
  // zbrdf process --grid 0,0 writes nothing either (not even frames/, hdr/ or the lock).
  const std::string dir = CopySession(tmp, "s");
  fs::remove_all(dir + "/hdr");
  EXPECT_EQ(RunZbrdf("process " + dir + " --grid 0,0", "/dev/null", tmp.File("err.txt")), 2);
  EXPECT_FALSE(fs::exists(dir + "/hdr"));
  EXPECT_FALSE(fs::exists(dir + "/session.lock"));
  // A plan field missing from session.json: the file and the field, not a library's text.
  nlohmann::json session = nlohmann::json::parse(ReadFile(dir + "/session.json"));
  session["plan"].erase("order");
  WriteFile(dir + "/session.json", session.dump(2));
  EXPECT_EQ(RunZbrdf("process " + dir, "/dev/null", tmp.File("err.txt")), 2);
  const std::string err = ReadFile(tmp.File("err.txt"));
  EXPECT_NE(err.find(dir + "/session.json plan field 'order' is missing"), std::string::npos)
      << err;
  EXPECT_EQ(err.find("json.exception"), std::string::npos) << err;
  // zbrdf eval: a folder where a file belongs is named, not "basic_filebuf::underflow error";
  // an input without pairs is an error, not an empty table.
  fs::create_directories(tmp.File("gold.binary"));
  EXPECT_EQ(RunZbrdf("eval file:" + tmp.File("gold.binary") + " --pairs /dev/null", "/dev/null",
                     tmp.File("err.txt")),
            2);
  std::string eval = ReadFile(tmp.File("err.txt"));
  EXPECT_NE(eval.find(tmp.File("gold.binary")), std::string::npos) << eval;
  EXPECT_EQ(eval.find("underflow"), std::string::npos) << eval;
  EXPECT_EQ(
      RunZbrdf("eval lambert:0.5 --pairs " + tmp.path(), tmp.File("out.csv"), tmp.File("err.txt")),
      2);
  eval = ReadFile(tmp.File("err.txt"));
  EXPECT_NE(eval.find("--pairs " + tmp.path() + " is a folder"), std::string::npos) << eval;
  EXPECT_EQ(ReadFile(tmp.File("out.csv")), "");
  WriteFile(tmp.File("empty.txt"), "# only a comment\n");
  EXPECT_EQ(RunZbrdf("eval lambert:0.5 --pairs " + tmp.File("empty.txt"), "/dev/null",
                     tmp.File("err.txt")),
            2);
  EXPECT_NE(ReadFile(tmp.File("err.txt")).find("holds no direction pairs"), std::string::npos);
}

// --samples-per-pixel sets the light transport's sample count (the report says which), the
// direction maps, which do not depend on it, are shared between sample counts in the cache, a
// session is resumed only at its own count, and an absurd count is refused before anything is
// written.
TEST(VirtualCapture, SamplesPerPixelSetsTheTransportAndSharesTheMaps) {
  TempDir tmp("virtual-capture-samples");
  const std::string cache = tmp.File("cache");
  const char* previous = std::getenv("ZBRDF_CACHE_DIR");
  const std::string saved = previous != nullptr ? previous : "";
  ::setenv("ZBRDF_CACHE_DIR", cache.c_str(), 1);
  auto count = [&](const std::string& folder, const std::string& prefix) {
    int n = 0;
    if (!fs::exists(folder)) return 0;
    for (const auto& entry : fs::directory_iterator(folder)) {
      n += entry.path().filename().string().rfind(prefix, 0) == 0;
    }
    return n;
  };
  const std::string simulate =
      "simulate --rig " + testing::ThesisRigPath() +
      " --preset fast --material ggx:alpha=0.3 --order 1 --exposures 1 --shortest-exposure-us "
      "40000 --no-hdr-images --truth-samples 256 --json";
  for (const int samples : {32, 64}) {
    const std::string out = tmp.File("s" + std::to_string(samples));
    ASSERT_EQ(
        RunZbrdf(simulate + " --samples-per-pixel " + std::to_string(samples) + " --out " + out,
                 tmp.File("report.json"), tmp.File("err.txt")),
        0)
        << ReadFile(tmp.File("err.txt"));
    const auto report = nlohmann::json::parse(ReadFile(tmp.File("report.json")));
    EXPECT_EQ(report.value("samples_per_pixel", 0), samples);
    EXPECT_EQ(count(cache, "maps-"), 1);
    EXPECT_EQ(count(cache + "/transport", "transport-"), samples == 32 ? 1 : 2);
  }
  // A session resumed at another count is refused, naming the flag.
  EXPECT_EQ(RunZbrdf(simulate + " --samples-per-pixel 64 --resume --out " + tmp.File("s32"),
                     "/dev/null", tmp.File("err.txt")),
            2);
  EXPECT_NE(ReadFile(tmp.File("err.txt")).find("--samples-per-pixel"), std::string::npos)
      << ReadFile(tmp.File("err.txt"));
  const std::string refused = tmp.File("refused");
  EXPECT_EQ(RunZbrdf(simulate + " --samples-per-pixel 0 --out " + refused, "/dev/null",
                     tmp.File("err.txt")),
            2);
  EXPECT_NE(ReadFile(tmp.File("err.txt")).find("--samples-per-pixel"), std::string::npos)
      << ReadFile(tmp.File("err.txt"));
  EXPECT_FALSE(fs::exists(refused));
  if (previous != nullptr) {
    ::setenv("ZBRDF_CACHE_DIR", saved.c_str(), 1);
  } else {
    ::unsetenv("ZBRDF_CACHE_DIR");
  }
}

// The frame's samples with one changed, in a TIFF carrying the original's ImageDescription (and
// so its checksum): damage that decodes cleanly.
std::string DamageKeepingTheDescription(const std::string& bytes, int width, int height) {
  std::istringstream in(bytes);
  TIFF* original = TIFFStreamOpen("frame", static_cast<std::istream*>(&in));
  char* text = nullptr;
  TIFFGetField(original, TIFFTAG_IMAGEDESCRIPTION, &text);
  const std::string description = text;
  TIFFClose(original);
  std::vector<uint16_t> samples = DecodeFrameFile(bytes, width, height, "frame");
  samples[samples.size() / 2] ^= 0x10;
  std::ostringstream out;
  TIFF* tiff = TIFFStreamOpen("frame", &out);
  TIFFSetField(tiff, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(width));
  TIFFSetField(tiff, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(height));
  TIFFSetField(tiff, TIFFTAG_BITSPERSAMPLE, 16);
  TIFFSetField(tiff, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(tiff, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tiff, TIFFTAG_COMPRESSION, COMPRESSION_ZSTD);
  TIFFSetField(tiff, TIFFTAG_ROWSPERSTRIP, height);
  TIFFSetField(tiff, TIFFTAG_IMAGEDESCRIPTION, description.c_str());
  TIFFWriteEncodedStrip(tiff, 0, samples.data(), static_cast<tmsize_t>(samples.size() * 2));
  TIFFClose(tiff);
  return out.str();
}

// Issue 15: "a bit flip inside a frame whose journal checksum is recomputed passes silently (the
// frame's own data carry no check)".
TEST(VirtualCapture, AFrameDamagedBehindItsJournalsBackIsFoundByItsOwnChecksum) {
  TempDir tmp("virtual-capture-flip");
  const std::string dir = CopySession(tmp, "s");
  std::string journal;
  for (JournalEntry e : SessionFolder::Open(dir).ReadJournal()) {
    if (e.index == 4) {
      const std::string path = dir + "/" + e.file;
      WriteFile(path, DamageKeepingTheDescription(ReadFile(path), e.width, e.height));
      e.checksum = FileChecksum(path);  // the journal agrees with the damaged file
    }
    journal += e.ToLine();
  }
  WriteFile(dir + "/journal.jsonl", journal);
  EXPECT_EQ(RunZbrdf("process " + dir, "/dev/null", tmp.File("err.txt")), 2);
  const std::string err = ReadFile(tmp.File("err.txt"));
  EXPECT_NE(err.find("frame " + dir +
                     "/frames/f000004.tiff is damaged: its samples do not match "
                     "the checksum the file records"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("--resume"), std::string::npos) << err;
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
