// The crash-test harness (issue 15; docs/session-folder.md, "Crashes, full disks and concurrent
// runs"), in the spirit of SQLite's: a capture, a process and an export are each broken at many
// points, then run again as a user would (capture --resume, process again, export again), and the
// results must be byte-identical to an unbroken run's, with nothing lost on the way:
//
//   - faults through the seam of basis/atomic_file.h (the helper every write goes through):
//     SIGKILL after a random share of a file's bytes (or after it is whole and synced, before its
//     rename), ENOSPC after a random share, EIO at fsync, and short writes;
//   - SIGKILL at a random time (timed kills, which land anywhere: rendering, merging, writing).
//
// Operations and shares are drawn from std::mt19937 with fixed seeds. Captures and processing run
// in forked children of a test process that has built the virtual rig once (the rig takes
// seconds to build; a fork costs milliseconds) and never processes anything itself, so that no
// thread pool exists at fork time; a part of the process and export faults run the real command
// line (zbrdf-faults, tests/tools/zbrdf_faults.cc). Between a fault and its rerun, every file the
// faulted run left must be whole: absent, the previous version, or the final one.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acquisition/capture_job.h"
#include "acquisition/session.h"
#include "basis/atomic_file.h"
#include "brdf/sh_file.h"
#include "calibration/calibration_data.h"
#include "rig/direction_maps.h"
#include "tests/acquisition/acquisition_test_util.h"
#include "tests/acquisition/session_fixture.h"
#include "tests/tools/simulated_sessions.h"
#include "tests/tools/tools_test_util.h"
#include "tools/brdf_export.h"
#include "tools/session_report.h"
#include "tools/virtual_capture.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// ---- Running broken children ----

struct Outcome {
  bool killed = false;  // by SIGKILL (the seam's or the harness's)
  int exit_code = -1;   // 0 done, 2 FileWriteError or other InputError, 3 anything else
  std::string error;    // what() of the exception that ended it
  double seconds = 0;
};

// Runs body in a forked child with the fault plan set; kills it after kill_after_s if >= 0.
// The child ends with _exit: nothing of the test process's state runs in it but body.
Outcome RunChild(const std::function<void()>& body, const WriteFaultPlan& plan,
                 double kill_after_s = -1) {
  const std::string error_file =
      (fs::temp_directory_path() / ("zbrdf-crash-error-" + std::to_string(::getpid()))).string();
  fs::remove(error_file);
  const auto start = Clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    SetWriteFaultPlan(plan);
    int code = 0;
    try {
      body();
    } catch (const std::exception& e) {
      code = dynamic_cast<const InputError*>(&e) != nullptr ? 2 : 3;
      std::ofstream(error_file) << e.what();  // the harness's own note, not a project output
    }
    ::_exit(code);
  }
  Outcome out;
  if (kill_after_s >= 0) {
    ::usleep(static_cast<useconds_t>(kill_after_s * 1e6));
    ::kill(pid, SIGKILL);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  out.seconds = Since(start);
  out.killed = WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
  if (WIFEXITED(status)) out.exit_code = WEXITSTATUS(status);
  out.error = testing::ReadFile(error_file);
  fs::remove(error_file);
  return out;
}

// Runs `<build>/<binary> args` with ZBRDF_WRITE_FAULT set (if plan has a fault); stderr to err.
Outcome RunBinary(const std::string& binary, const std::string& args, const WriteFaultPlan& plan,
                  const std::string& err) {
  std::string env;
  if (plan.fault != WriteFault::kNone) {
    env = "ZBRDF_WRITE_FAULT=" + WriteFaultName(plan.fault) + ":" + std::to_string(plan.operation) +
          ":" + std::to_string(plan.fraction) + " ";
  }
  const auto start = Clock::now();
  const std::string command =
      env + std::string(ZBRDF_BINARY_DIR) + "/" + binary + " " + args + " >/dev/null 2>" + err;
  const int status = std::system(command.c_str());
  Outcome out;
  out.seconds = Since(start);
  // system() runs a shell: a command it forked and that was killed exits with 128 + the signal.
  out.killed = (WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) ||
               (WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGKILL);
  if (WIFEXITED(status)) out.exit_code = WEXITSTATUS(status);
  out.error = testing::ReadFile(err);
  return out;
}

// A fault of the seam, drawn with rng: kind, operation in [1, operations], share of the bytes.
WriteFaultPlan DrawFault(std::mt19937& rng, int64_t operations, int case_number) {
  static const WriteFault kinds[] = {WriteFault::kKill, WriteFault::kKill, WriteFault::kNoSpace,
                                     WriteFault::kIoError, WriteFault::kShortWrites};
  WriteFaultPlan plan;
  plan.fault = kinds[case_number % 5];
  plan.operation = std::uniform_int_distribution<int64_t>(1, operations)(rng);
  // Kills: a share of the bytes, or (one in four) all of them, synced, before the rename.
  plan.fraction = std::uniform_real_distribution<double>(0, 1)(rng);
  if (plan.fault == WriteFault::kKill && case_number % 4 == 1) plan.fraction = 1.0;
  return plan;
}

std::string Describe(const WriteFaultPlan& plan, double kill_after_s) {
  if (kill_after_s >= 0) return "SIGKILL after " + std::to_string(kill_after_s) + " s";
  return WriteFaultName(plan.fault) + " at write operation " + std::to_string(plan.operation) +
         " after " + std::to_string(plan.fraction) + " of its bytes";
}

// ---- Comparing folders ----

// Every regular file under dir by relative path, with its bytes; `skip` names are left out.
std::map<std::string, std::string> Files(const std::string& dir,
                                         const std::set<std::string>& skip) {
  std::map<std::string, std::string> out;
  if (!fs::exists(dir)) return out;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    const std::string name = fs::relative(entry.path(), dir).string();
    if (skip.count(name) || name.rfind(std::string(kJournalFile) + ".torn-", 0) == 0) continue;
    out[name] = testing::ReadFile(entry.path().string());
  }
  return out;
}

// Files a run leaves that depend on the run (timings, PIDs) or record its repairs.
const std::set<std::string> kRunDependent = {kJournalFile, kReportFile, kLockFile};

// The journal's trusted entries without what depends on the run (wall time, the session clock's
// timestamps, the camera's frame counter), one line per frame.
std::vector<std::string> JournalContent(const std::string& dir) {
  std::vector<std::string> out;
  for (JournalEntry e : SessionFolder::Open(dir).ReadJournal()) {
    e.wall_time.clear();
    e.timestamp_us = 0;
    e.frame_id = 0;
    out.push_back(e.ToJson().dump());
  }
  return out;
}

// No temporary file anywhere under dir.
std::vector<std::string> Temporaries(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (IsTemporaryFileName(entry.path().filename().string())) {
      out.push_back(fs::relative(entry.path(), dir).string());
    }
  }
  return out;
}

// Whether every file of `now` is whole: equal to the same file in `before` or in `after`.
// Returns the names that are neither (a truncated or mixed file).
std::vector<std::string> TornFiles(const std::map<std::string, std::string>& now,
                                   const std::map<std::string, std::string>& before,
                                   const std::map<std::string, std::string>& after) {
  std::vector<std::string> torn;
  for (const auto& [name, bytes] : now) {
    const auto b = before.find(name), a = after.find(name);
    const bool whole =
        (b != before.end() && b->second == bytes) || (a != after.end() && a->second == bytes);
    if (!whole && !IsTemporaryFileName(fs::path(name).filename().string())) torn.push_back(name);
  }
  return torn;
}

// The error a write fault ends a command with names the final file and the next step.
void ExpectUsefulWriteError(const Outcome& o, const std::string& where, const std::string& what) {
  EXPECT_EQ(o.exit_code, 2) << what;
  EXPECT_NE(o.error.find(where), std::string::npos) << what << ": " << o.error;
  EXPECT_EQ(o.error.find(".tmp"), std::string::npos) << what << ": names a temporary: " << o.error;
  EXPECT_TRUE(o.error.find("--resume") != std::string::npos ||
              o.error.find("again") != std::string::npos)
      << what << ": no next step: " << o.error;
}

// A fresh scratch folder for a harness: on /dev/shm (tmpfs) where there is one, since syncing
// each file to a disk (about 12 ms a file here) would be most of the harness's time, and what it
// tests is what a fault leaves, not the disk's speed; else under the temp directory.
std::string ScratchDir(const std::string& name) {
  std::error_code error;
  const bool shm = fs::is_directory("/dev/shm", error) && ::access("/dev/shm", W_OK) == 0;
  const std::string dir = (fs::path(shm ? "/dev/shm" : fs::temp_directory_path()) /
                           ("zbrdf-crash-" + std::to_string(::getpid()) + "-" + name))
                              .string();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

int Cases(int base) {
  // ZBRDF_CRASH_SCALE multiplies the case counts (a longer local run); the test command uses 1.
  const char* scale = std::getenv("ZBRDF_CRASH_SCALE");
  return scale != nullptr ? std::max(1, static_cast<int>(base * std::atof(scale))) : base;
}

// ---- Capture ----

// Lambert 50%, order 1, one exposure: 8 patterns and frames, 8 HDR images; the fast thesis rig.
CaptureJobOptions CaptureJob(const std::string& dir, bool resume) {
  CaptureJobOptions job;
  job.out_dir = dir;
  job.resume = resume;
  job.order = 1;
  job.exposures = 1;
  job.shortest_exposure_us = 40000;
  job.pattern_cache_dir = testing::TestCacheDir();
  return job;
}

TEST(CrashHarness, CapturesKilledOrStarvedAnywhereResumeToIdenticalSessions) {
  const auto start = Clock::now();
  testing::SimulatedRig setup("lambertian:0.5");  // built once; every child inherits it
  const std::string root = ScratchDir("capture");
  const std::string dir = root + "/s", reference = root + "/reference";
  const auto capture = [&](bool resume) {
    return [&setup, &dir, resume] {
      CaptureJobResult r = setup.Run(CaptureJob(dir, resume));
      if (!r.complete) throw std::runtime_error("incomplete");
      WriteSessionReport(dir, CaptureJobReport(r, r.capture.device_time_s));
    };
  };
  // Two clean runs: the first fills the pattern cache, the second counts the write operations
  // of a capture as the faulted ones make them; both must give the same session.
  int64_t operations = 0;
  double clean_s = 0;
  for (int run = 0; run < 2; ++run) {
    fs::remove_all(dir);
    const std::string count_file = root + "/count";
    const Outcome o = RunChild(
        [&] {
          const int64_t inherited = WriteOperationCount();  // the test process's own, if any
          capture(false)();
          std::ofstream(count_file) << WriteOperationCount() - inherited;  // the harness's note
        },
        {});
    ASSERT_EQ(o.exit_code, 0) << o.error;
    operations = std::atoll(testing::ReadFile(count_file).c_str());
    clean_s = o.seconds;
    if (run == 0) fs::rename(dir, reference);
  }
  ASSERT_GE(operations, 26) << "session.json, 8 frames and lines, 8 HDR images, zonal, report";
  ASSERT_EQ(Files(dir, kRunDependent), Files(reference, kRunDependent));
  ASSERT_EQ(JournalContent(dir), JournalContent(reference));
  const std::map<std::string, std::string> expected = Files(reference, kRunDependent);

  std::mt19937 rng(15);
  const int cases = Cases(49);
  int resumed = 0, torn_lines = 0, temporaries = 0;
  for (int c = 0; c < cases; ++c) {
    fs::remove_all(dir);
    WriteFaultPlan plan = DrawFault(rng, operations, c);
    double kill_after_s = -1;
    if (c % 7 == 6) {  // a timed kill, anywhere in the run
      plan = {};
      kill_after_s = std::uniform_real_distribution<double>(0, clean_s)(rng);
    }
    const std::string what = "case " + std::to_string(c) + ": " + Describe(plan, kill_after_s);
    const Outcome broken = RunChild(capture(false), plan, kill_after_s);
    if (plan.fault == WriteFault::kKill) {
      EXPECT_TRUE(broken.killed) << what;
    }
    if (plan.fault == WriteFault::kShortWrites) {
      EXPECT_EQ(broken.exit_code, 0) << what;
    }
    if (plan.fault == WriteFault::kNoSpace || plan.fault == WriteFault::kIoError) {
      ExpectUsefulWriteError(broken, dir + "/", what);
    }
    // Nothing half-written: each file is absent or the final one.
    if (fs::exists(dir)) {
      EXPECT_EQ(TornFiles(Files(dir, kRunDependent), {}, expected), std::vector<std::string>())
          << what;
      temporaries += !Temporaries(dir).empty();
      torn_lines +=
          SessionFolder::Exists(dir) && SessionFolder::Open(dir).ReadJournalLines().torn_tail;
    }
    // The user's next step: resume, or start again if the run died before session.json.
    if (!(broken.exit_code == 0 && !broken.killed)) {
      ++resumed;
      const Outcome again = RunChild(capture(SessionFolder::Exists(dir)), {});
      ASSERT_EQ(again.exit_code, 0) << what << ": the rerun failed: " << again.error;
    }
    EXPECT_EQ(Files(dir, kRunDependent), expected) << what;
    EXPECT_EQ(JournalContent(dir), JournalContent(reference)) << what;
    const JournalReading journal = SessionFolder::Open(dir).ReadJournalLines();
    EXPECT_TRUE(journal.damaged_lines.empty() && !journal.torn_tail) << what;
    EXPECT_EQ(Temporaries(dir), std::vector<std::string>()) << what;
    EXPECT_TRUE(fs::exists(dir + "/" + kReportFile)) << what;
  }
  // The harness reached the repairs: journals torn by a kill, temporaries of killed runs.
  if (cases >= 49) {
    EXPECT_GT(torn_lines, 0);
    EXPECT_GT(temporaries, 0);
  }
  std::printf(
      "capture: %d faults (%d resumed; %d left a torn journal line, %d temporary files), "
      "%lld write operations per run, %.1f s\n",
      cases, resumed, torn_lines, temporaries, static_cast<long long>(operations), Since(start));
  fs::remove_all(root);
}

// ---- Process ----

// A processed session's report as `zbrdf process` writes it (tools/cli/process.cc).
void ProcessAndReport(const std::string& dir, const RigCalibration& calibration,
                      const ProcessingOptions& options) {
  const ProcessResult r = ProcessSession(dir, calibration, options, testing::TestCacheDir());
  nlohmann::json report = {
      {"processing", {{"saturated_pixel_lobes", r.processing.saturated_pixels}}}};
  WriteSessionReport(dir, report);
}

TEST(CrashHarness, ProcessingKilledOrStarvedAnywhereLeavesThePreviousFilesAndRedoesThem) {
  const auto start = Clock::now();
  // A captured session (frames, journal, session.json), simulated once in a child and cached.
  std::string source;
  {
    const std::string note = testing::TestBuildDir("test-sessions") + "/crash-source.txt";
    const Outcome made = RunChild(
        [&] {
          testing::SessionOptions o;
          o.exposures = 1;
          o.shortest_exposure_us = 40000;
          o.tag = "-crash";
          std::ofstream(note) << testing::SimulatedSession("lambert:0.5", 1, o);
        },
        {});
    ASSERT_EQ(made.exit_code, 0) << made.error;
    source = testing::ReadFile(note);
  }
  const std::string root = ScratchDir("process");
  const std::string dir = root + "/s";
  fs::create_directories(dir + "/frames");
  for (const char* name : {kSessionFile, kJournalFile})
    fs::copy_file(source + "/" + name, dir + "/" + name);
  fs::copy(source + "/frames", dir + "/frames");
  const RigCalibration calibration =
      LoadRigCalibration(SessionRig(dir), "", testing::TestCacheDir(), nullptr);
  ProcessingOptions options;  // 1 x 2 deg grid, HDR images on
  ProcessingOptions coarse;
  coarse.theta_step_deg = 2;
  coarse.phi_step_deg = 4;
  const std::set<std::string> kSkip = {kLockFile};
  // The files before (a coarser zonal.exr, its report) and after (the default grid).
  ASSERT_EQ(RunChild([&] { ProcessAndReport(dir, calibration, coarse); }, {}).exit_code, 0);
  const std::map<std::string, std::string> before = Files(dir, kSkip);
  const std::string count_file = root + "/count";
  const Outcome clean = RunChild(
      [&] {
        const int64_t inherited = WriteOperationCount();
        ProcessAndReport(dir, calibration, options);
        std::ofstream(count_file) << WriteOperationCount() - inherited;
      },
      {});
  ASSERT_EQ(clean.exit_code, 0) << clean.error;
  const int64_t operations = std::atoll(testing::ReadFile(count_file).c_str());
  ASSERT_EQ(operations, 10) << "8 HDR images, zonal.exr, report.json";
  const std::map<std::string, std::string> after = Files(dir, kSkip);
  ASSERT_NE(before.at(kZonalFile), after.at(kZonalFile));

  std::mt19937 rng(16);
  const int forked = Cases(40), binary = Cases(8);
  for (int c = 0; c < forked + binary; ++c) {
    // Back to the earlier state: the coarse zonal.exr and report.
    for (const auto& [name, bytes] : before) WriteFileAtomically(dir + "/" + name, bytes);
    WriteFaultPlan plan = DrawFault(rng, operations, c);
    double kill_after_s = -1;
    const bool real_binary = c >= forked;
    if (!real_binary && c % 7 == 6) {
      plan = {};
      kill_after_s = std::uniform_real_distribution<double>(0, clean.seconds)(rng);
    }
    const std::string what = std::string(real_binary ? "zbrdf-faults process, " : "") + "case " +
                             std::to_string(c) + ": " + Describe(plan, kill_after_s);
    const Outcome broken =
        real_binary
            ? RunBinary("zbrdf-faults", "process " + dir, plan, root + "/err.txt")
            : RunChild([&] { ProcessAndReport(dir, calibration, options); }, plan, kill_after_s);
    if (plan.fault == WriteFault::kKill) {
      EXPECT_TRUE(broken.killed) << what << broken.error;
    }
    if (plan.fault == WriteFault::kShortWrites) {
      EXPECT_EQ(broken.exit_code, 0) << what;
    }
    if (plan.fault == WriteFault::kNoSpace || plan.fault == WriteFault::kIoError) {
      ExpectUsefulWriteError(broken, dir + "/", what);
    }
    // Every file is the earlier or the new one, never a truncated or mixed one. (The command
    // line's report.json has timings: it must be whole JSON.)
    std::map<std::string, std::string> left = Files(dir, kSkip);
    if (real_binary) {
      EXPECT_FALSE(nlohmann::json::parse(left[kReportFile], nullptr, false).is_discarded()) << what;
      left.erase(kReportFile);
    }
    EXPECT_EQ(TornFiles(left, before, after), std::vector<std::string>()) << what;
    const Outcome again = real_binary
                              ? RunBinary("zbrdf", "process " + dir, {}, root + "/err.txt")
                              : RunChild([&] { ProcessAndReport(dir, calibration, options); }, {});
    ASSERT_EQ(again.exit_code, 0) << what << ": the rerun failed: " << again.error;
    std::map<std::string, std::string> now = Files(dir, kSkip);
    if (real_binary) {  // the CLI's report.json has timings
      now.erase(kReportFile);
      EXPECT_TRUE(fs::exists(dir + "/" + kReportFile));
    }
    std::map<std::string, std::string> expected = after;
    if (real_binary) expected.erase(kReportFile);
    EXPECT_EQ(now, expected) << what;
    EXPECT_EQ(Temporaries(dir), std::vector<std::string>()) << what;
  }
  std::printf(
      "process: %d faults (%d through zbrdf-faults), %lld write operations per run, "
      "%.1f s\n",
      forked + binary, binary, static_cast<long long>(operations), Since(start));
  fs::remove_all(root);
}

// ---- Export ----

struct ExportCase {
  std::string input, format, out;
  std::string options;  // flags of `zbrdf export`
};

TEST(CrashHarness, ExportsKilledOrStarvedAnywhereLeaveWholeFilesAndRedoThem) {
  const auto start = Clock::now();
  const std::string root = ScratchDir("export");
  fs::create_directories(root + "/out");
  WriteShFile(root + "/sh.exr", testing::MakeShData(0.5));  // OpenEXR without a thread pool
  WriteShFile(root + "/sh-earlier.exr", testing::MakeShData(0.3));
  // Each export is made twice: from an earlier input (the files there before) and from the input
  // (the files after); faults hit the second.
  const std::string rgl = " --rgl-theta 4 --rgl-phi 5 --rgl-samples 8";
  const std::vector<ExportCase> exports = {
      {"ggx:alpha=0.2,F0=0.04,kd=0.2", "rgl", "m.bsdf", rgl},
      {"dbrdf:c=0.3,F0=0.5,kd=0.05,theta_samples=4,p=4,2,1,0.5", "dbrdf", "d.exr", ""},
      {"ward:rho_d=0.3,rho_s=0.1,alpha=0.2", "brdf-explorer", "w.brdf", ""},
      {root + "/sh.exr", "sh", "s.exr", ""},
  };
  const std::vector<std::string> earlier = {
      "ggx:alpha=0.3,F0=0.04,kd=0.2", "dbrdf:c=0.3,F0=0.5,kd=0.05,theta_samples=4,p=4,3,2,1",
      "ward:rho_d=0.3,rho_s=0.1,alpha=0.3", root + "/sh-earlier.exr"};
  const auto run_export = [&](const std::string& input, const ExportCase& e) {
    return [&, input] {
      ExportOptions options;
      options.format = ParseExportFormat(e.format);
      options.out = root + "/out/" + e.out;
      options.rgl.theta_nodes = 4;
      options.rgl.phi_nodes = 5;
      options.rgl.sample_resolution = 8;  // as the flags of ExportCase::options
      ExportBrdf(ResolveBrdfInput(input), options);
    };
  };
  std::vector<std::map<std::string, std::string>> before, after;
  std::vector<int64_t> operations;
  for (size_t k = 0; k < exports.size(); ++k) {
    fs::remove_all(root + "/out");
    fs::create_directories(root + "/out");
    ASSERT_EQ(RunChild(run_export(earlier[k], exports[k]), {}).exit_code, 0);
    before.push_back(Files(root + "/out", {}));
    const std::string count_file = root + "/count";
    const Outcome o = RunChild(
        [&] {
          const int64_t inherited = WriteOperationCount();
          run_export(exports[k].input, exports[k])();
          std::ofstream(count_file) << WriteOperationCount() - inherited;
        },
        {});
    ASSERT_EQ(o.exit_code, 0) << o.error;
    operations.push_back(std::atoll(testing::ReadFile(count_file).c_str()));
    after.push_back(Files(root + "/out", {}));
  }
  std::mt19937 rng(17);
  const int forked = Cases(110), binary = Cases(10);
  for (int c = 0; c < forked + binary; ++c) {
    const size_t k = static_cast<size_t>(c) % exports.size();
    const ExportCase& e = exports[k];
    fs::remove_all(root + "/out");
    fs::create_directories(root + "/out");
    for (const auto& [name, bytes] : before[k]) WriteFileAtomically(root + "/out/" + name, bytes);
    const WriteFaultPlan plan = DrawFault(rng, operations[k], c / static_cast<int>(exports.size()));
    const bool real_binary = c >= forked;
    const std::string what = std::string(real_binary ? "zbrdf-faults " : "") + "export " +
                             e.format + ", case " + std::to_string(c) + ": " + Describe(plan, -1);
    const std::string args = "export " + e.input + " --format " + e.format + " --out " + root +
                             "/out/" + e.out + e.options;
    const Outcome broken = real_binary ? RunBinary("zbrdf-faults", args, plan, root + "/err.txt")
                                       : RunChild(run_export(e.input, e), plan);
    if (plan.fault == WriteFault::kKill) {
      EXPECT_TRUE(broken.killed) << what << broken.error;
    }
    if (plan.fault == WriteFault::kShortWrites) {
      EXPECT_EQ(broken.exit_code, 0) << what;
    }
    if (plan.fault == WriteFault::kNoSpace || plan.fault == WriteFault::kIoError) {
      ExpectUsefulWriteError(broken, root + "/out/", what);
    }
    EXPECT_EQ(TornFiles(Files(root + "/out", {}), before[k], after[k]), std::vector<std::string>())
        << what;
    const Outcome again = real_binary ? RunBinary("zbrdf", args, {}, root + "/err.txt")
                                      : RunChild(run_export(e.input, e), {});
    ASSERT_EQ(again.exit_code, 0) << what << ": the rerun failed: " << again.error;
    // The rerun replaces every file; a killed run's temporaries stay until removed.
    std::map<std::string, std::string> now = Files(root + "/out", {});
    for (auto it = now.begin(); it != now.end();) {
      it = IsTemporaryFileName(fs::path(it->first).filename().string()) ? now.erase(it) : ++it;
    }
    EXPECT_EQ(now, after[k]) << what;
  }
  std::printf("export: %d faults (%d through zbrdf-faults), %.1f s\n", forked + binary, binary,
              Since(start));
  fs::remove_all(root);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
