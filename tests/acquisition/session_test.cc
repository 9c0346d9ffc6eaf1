#include "acquisition/session.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/hash.h"
#include "tests/acquisition/acquisition_test_util.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;

std::string TempDir(const std::string& name) { return testing::FreshTempDir("session-test", name); }

using testing::SmallFrame;

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Session, Fnv1aMatchesPublishedVectors) {
  // FNV-1a 64 test vectors (Fowler, Noll, Vo: offset basis and "a", "foobar"): the hash of
  // journal lines, and of frame files in journals written before XXH3.
  EXPECT_EQ(Fnv1a64(""), 0xcbf29ce484222325ull);
  EXPECT_EQ(Fnv1a64("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(Fnv1a64("foobar"), 0x85944171f73967e8ull);
}

TEST(Session, FrameFileChecksumIsXxh3OfTheFile) {
  // XXH3 64 (seed 0) of "" as the xxHash specification gives it, and of "a" and "foobar" as
  // xxHash's own command-line tool prints them (xxhsum -H3 of files holding those bytes).
  const std::string dir = TempDir("xxh3");
  fs::create_directories(dir);
  const std::pair<std::string, std::string> vectors[] = {
      {"", "2d06800538d394c2"}, {"a", "e6c632b61e964e1f"}, {"foobar", "d78fda63144c5c84"}};
  for (const auto& [text, hex] : vectors) {
    WriteFileAtomically(dir + "/f", text);
    EXPECT_EQ(FileChecksum(dir + "/f"), "xxh3-64:" + hex) << '"' << text << '"';
    EXPECT_EQ(FrameFileChecksum(text), "xxh3-64:" + hex);
    EXPECT_TRUE(FrameFileChecksumMatches("xxh3-64:" + hex, text));
  }
  EXPECT_EQ(FileChecksum(dir + "/missing"), "");
  // What journals written before XXH3 record is checked with FNV-1a; anything else never matches.
  EXPECT_TRUE(FrameFileChecksumMatches("fnv1a64:85944171f73967e8", "foobar"));
  EXPECT_FALSE(FrameFileChecksumMatches("fnv1a64:85944171f73967e9", "foobar"));
  EXPECT_FALSE(FrameFileChecksumMatches("xxh3-64:d78fda63144c5c85", "foobar"));
  EXPECT_FALSE(FrameFileChecksumMatches("d78fda63144c5c84", "foobar"));
  EXPECT_FALSE(FrameFileChecksumMatches("", ""));
  fs::remove_all(dir);
}

TEST(Session, FramesJournaledWithFnv1aBeforeXxh3StillRead) {
  // A session written before XXH3: its journal lines record FNV-1a 64 of the frame files.
  const std::string dir = TempDir("fnv-journal");
  SessionFolder s = SessionFolder::Create(dir, nlohmann::json::object());
  JournalEntry e = s.WriteFrame(0, SmallFrame(42));
  char fnv[32];
  std::snprintf(fnv, sizeof(fnv), "fnv1a64:%016llx",
                static_cast<unsigned long long>(Fnv1a64(Slurp(dir + "/" + e.file))));
  e.checksum = fnv;
  s.AppendJournal(e);
  const std::vector<JournalEntry> journal = SessionFolder::Open(dir).ReadJournal();
  ASSERT_EQ(journal.size(), 1u);
  EXPECT_EQ(journal[0].checksum, fnv);
  EXPECT_TRUE(s.FrameIsIntact(journal[0]));
  EXPECT_EQ(s.ReadFrame(journal[0]).data, SmallFrame(42).data);
  // A wrong FNV-1a checksum is damage, as a wrong XXH3 one is.
  JournalEntry wrong = journal[0];
  wrong.checksum.back() = wrong.checksum.back() == '0' ? '1' : '0';
  EXPECT_FALSE(s.FrameIsIntact(wrong));
  EXPECT_THROW(s.ReadFrame(wrong), InputError);
  fs::remove_all(dir);
}

TEST(Session, ExistingSessionIsNeverOverwritten) {
  const std::string dir = TempDir("exists");
  SessionFolder::Create(dir, {{"note", "first"}});
  EXPECT_THROW(SessionFolder::Create(dir, {{"note", "second"}}), InputError);
  EXPECT_EQ(SessionFolder::Open(dir).session().value("note", ""), "first");
  fs::remove_all(dir);
}

TEST(Session, OpenOnlyReadsAndOpenForWritingRestoresTheFolders) {
  const std::string dir = TempDir("read-only");
  SessionFolder::Create(dir, {{"material", "lambert:0.5"}});
  EXPECT_TRUE(SessionFolder::Exists(dir));
  fs::remove_all(dir + "/frames");
  fs::remove_all(dir + "/hdr");
  const auto before = fs::last_write_time(dir + "/session.json");
  const SessionFolder read = SessionFolder::Open(dir);
  EXPECT_EQ(read.material(), "lambert:0.5");
  EXPECT_FALSE(fs::exists(dir + "/frames"));
  EXPECT_FALSE(fs::exists(dir + "/hdr"));
  EXPECT_EQ(fs::last_write_time(dir + "/session.json"), before);
  SessionFolder::OpenForWriting(dir);
  EXPECT_TRUE(fs::is_directory(dir + "/frames"));
  EXPECT_TRUE(fs::is_directory(dir + "/hdr"));
  EXPECT_FALSE(SessionFolder::Exists(dir + "/frames"));
  fs::remove_all(dir);
}

TEST(Session, FileNamesFollowTheDocumentedLayout) {
  // docs/session-folder.md.
  EXPECT_EQ(FrameFileName(42), "frames/f000042.tiff");
  EXPECT_EQ(FitReportFileName("ggx"), "fit-ggx.json");
  EXPECT_EQ(ShFileName("sh-even"), "sh-sh-even.exr");
  EXPECT_EQ(SessionPath("/tmp/s", kZonalFile), "/tmp/s/zonal.exr");
  const std::string dir = TempDir("names");
  SessionFolder s = SessionFolder::Create(dir, nlohmann::json::object());
  const JournalEntry e = s.WriteFrame(7, SmallFrame(100));
  EXPECT_EQ(e.file, FrameFileName(7));
  EXPECT_TRUE(fs::exists(SessionPath(dir, e.file)));
  fs::remove_all(dir);
}

TEST(Session, OpenNamesWhatIsMissingOrDamaged) {
  const std::string dir = TempDir("open");
  EXPECT_THROW(SessionFolder::Open(dir), InputError);
  fs::create_directories(dir);
  std::ofstream(dir + "/session.json") << "{ not json";
  EXPECT_THROW(SessionFolder::Open(dir), InputError);
  fs::remove_all(dir);
}

TEST(Session, FramesRoundTripThroughTheJournal) {
  const std::string dir = TempDir("frames");
  SessionFolder s = SessionFolder::Create(dir, nlohmann::json::object());
  for (int i = 0; i < 3; ++i) {
    JournalEntry e = s.WriteFrame(i, SmallFrame(static_cast<uint16_t>(100 * i)));
    e.lobe = "Z1,0+";
    s.AppendJournal(e);
  }
  const std::vector<JournalEntry> journal = SessionFolder::Open(dir).ReadJournal();
  ASSERT_EQ(journal.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(journal[i].index, i);
    EXPECT_EQ(journal[i].lobe, "Z1,0+");
    EXPECT_TRUE(s.FrameIsIntact(journal[i]));
    EXPECT_EQ(s.ReadFrame(journal[i]).data, SmallFrame(static_cast<uint16_t>(100 * i)).data);
    EXPECT_EQ(FileChecksum(dir + "/" + journal[i].file), journal[i].checksum);
  }
  // No temporary files are left behind by the atomic writes.
  for (const auto& entry : fs::directory_iterator(dir + "/frames")) {
    EXPECT_EQ(entry.path().extension(), ".tiff") << entry.path();
  }
  fs::remove_all(dir);
}

TEST(Session, CorruptOrTruncatedFramesFailTheirChecksum) {
  const std::string dir = TempDir("corrupt");
  SessionFolder s = SessionFolder::Create(dir, nlohmann::json::object());
  JournalEntry e = s.WriteFrame(0, SmallFrame(7));
  s.AppendJournal(e);
  const std::string path = dir + "/" + e.file;
  std::string bytes = Slurp(path);
  bytes[bytes.size() / 2] ^= 0x10;  // one flipped bit
  std::ofstream(path, std::ios::binary) << bytes;
  EXPECT_FALSE(s.FrameIsIntact(e));
  try {
    s.ReadFrame(e);
    FAIL() << "a corrupt frame was read";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(e.file), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("resume"), std::string::npos) << error.what();
  }
  const std::string head = Slurp(path).substr(0, 40);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << head;
  EXPECT_FALSE(s.FrameIsIntact(e));
  fs::remove(path);
  EXPECT_FALSE(s.FrameIsIntact(e));
  EXPECT_THROW(s.ReadFrame(e), InputError);
  fs::remove_all(dir);
}

TEST(Session, JournalSurvivesATornLastLineAndKeepsTheLatestEntry) {
  const std::string dir = TempDir("journal");
  SessionFolder s = SessionFolder::Create(dir, nlohmann::json::object());
  JournalEntry first = s.WriteFrame(0, SmallFrame(1));
  s.AppendJournal(first);
  JournalEntry again = s.WriteFrame(0, SmallFrame(2));  // recaptured frame 0
  s.AppendJournal(again);
  {
    std::ofstream out(dir + "/journal.jsonl", std::ios::app);
    out << R"({"index": 1, "lobe": "Z1,0-", "exposure")";  // a crash mid-line
  }
  const std::vector<JournalEntry> journal = s.ReadJournal();
  ASSERT_EQ(journal.size(), 1u);
  EXPECT_EQ(journal[0].checksum, again.checksum);
  EXPECT_EQ(s.ReadFrame(journal[0]).data, SmallFrame(2).data);
  fs::remove_all(dir);
}

CapturePlan SmallPlan() { return MakePlan({DegToRad(10), DegToRad(50), 1, 2, 2, 500, 1}); }

// Journal entries of SmallPlan's frames, as the runner makes them.
JournalEntry PlannedEntry(SessionFolder& s, const CapturePlan& plan, int index) {
  JournalEntry e = s.WriteFrame(index, SmallFrame(static_cast<uint16_t>(10 * index)));
  const PlannedFrame pf = plan.Frame(index);
  e.lobe = plan.lobes[pf.lobe].Name();
  e.exposure = pf.exposure;
  e.repeat = pf.repeat;
  e.exposure_us_requested = plan.exposures_us[pf.exposure];
  return e;
}

// Issue 15, case 1: a folder holding a journal and frames but no session.json is not a session;
// a new one is refused there (naming what is there and --force-new), which moves it aside.
TEST(Session, AFolderWithoutSessionJsonIsNeverTakenForASession) {
  const std::string dir = TempDir("no-session-json");
  fs::create_directories(dir + "/frames");
  testing::WriteFile(dir + "/journal.jsonl", "{\"index\":0}\n");
  testing::WriteFile(dir + "/frames/f000000.tiff", "a user's own frame");
  try {
    SessionFolder::Create(dir, {{"note", "new"}});
    FAIL() << "a folder with a journal and frames was taken for a new session";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("holds no session.json (found frames/ (1 files), journal.jsonl)"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("--force-new"), std::string::npos) << what;
  }
  EXPECT_EQ(Slurp(dir + "/frames/f000000.tiff"), "a user's own frame");
  EXPECT_EQ(Slurp(dir + "/journal.jsonl"), "{\"index\":0}\n");
  EXPECT_THROW(SessionFolder::OpenForWriting(dir), InputError) << "nothing to resume either";
  // --force-new: moved aside whole, never deleted.
  const std::string aside = MoveSessionFolderAside(dir);
  ASSERT_FALSE(aside.empty());
  EXPECT_EQ(aside.rfind(dir + ".before-", 0), 0u) << aside;
  EXPECT_EQ(Slurp(aside + "/frames/f000000.tiff"), "a user's own frame");
  EXPECT_FALSE(fs::exists(dir));
  SessionFolder s = SessionFolder::Create(dir, {{"note", "new"}});
  EXPECT_TRUE(s.ReadJournal().empty());
  EXPECT_EQ(s.session_id().size(), 16u);
  fs::remove_all(aside);
  fs::remove_all(dir);

  // What a run killed before its session.json leaves is no obstacle.
  fs::create_directories(dir + "/frames");
  fs::create_directories(dir + "/hdr");
  testing::WriteFile(dir + "/session.lock", "pid 1: zbrdf capture\n");
  EXPECT_NO_THROW(CheckNewSessionFolder(dir));
  EXPECT_EQ(MoveSessionFolderAside(dir), "");
  EXPECT_NO_THROW(SessionFolder::Create(dir, nlohmann::json::object()));
  fs::remove_all(dir);
}

// Issue 15, case 2: a line torn by a crash or a full disk is cut away (and kept) before anything
// is appended, so the next line is not glued onto it and lost.
TEST(Session, ATornLastJournalLineIsCutAwayBeforeTheNextIsAppended) {
  const std::string dir = TempDir("torn");
  const CapturePlan plan = SmallPlan();
  std::string fragment;
  {
    SessionFolder s = SessionFolder::Create(dir, {{"plan", plan.ToJson()}});
    for (int i = 0; i < 3; ++i) s.AppendJournal(PlannedEntry(s, plan, i));
    const std::string line = PlannedEntry(s, plan, 3).ToLine();
    fragment = line.substr(0, line.size() / 2);
    std::ofstream(dir + "/journal.jsonl", std::ios::app | std::ios::binary) << fragment;
  }
  EXPECT_TRUE(SessionFolder::Open(dir).ReadJournalLines().torn_tail);
  SessionFolder s = SessionFolder::OpenForWriting(dir);
  EXPECT_EQ(s.repairs().torn_journal_bytes, fragment.size());
  EXPECT_EQ(s.repairs().torn_journal_copy, "journal.jsonl.torn-1");
  EXPECT_EQ(Slurp(dir + "/journal.jsonl.torn-1"), fragment);
  EXPECT_NE(s.repairs().Summary().find("cut a torn last line"), std::string::npos);
  s.AppendJournal(PlannedEntry(s, plan, 3));
  const JournalReading reading = s.ReadJournalLines();
  EXPECT_FALSE(reading.torn_tail);
  EXPECT_TRUE(reading.damaged_lines.empty());
  ASSERT_EQ(reading.entries.size(), 4u);
  EXPECT_EQ(reading.entries[3].index, 3);
  fs::remove_all(dir);
}

// Every journal line carries a check of its own bytes: a damaged line is not trusted (its frame
// is taken again); lines of earlier versions, without the check, are read as before.
TEST(Session, EveryJournalLineCarriesItsOwnCheck) {
  const std::string dir = TempDir("line-check");
  const CapturePlan plan = SmallPlan();
  SessionFolder s = SessionFolder::Create(dir, {{"plan", plan.ToJson()}});
  for (int i = 0; i < 3; ++i) s.AppendJournal(PlannedEntry(s, plan, i));
  std::string journal = Slurp(dir + "/journal.jsonl");
  const size_t second = journal.find('\n') + 1;
  EXPECT_NE(journal.find("\"line_check\":\"fnv1a64:"), std::string::npos);
  // The same JSON with another exposure, as a recomputed journal checksum would not notice.
  const size_t at = journal.find("\"exposure\":1", second);
  ASSERT_NE(at, std::string::npos);
  journal[at + 11] = '0';
  std::ofstream(dir + "/journal.jsonl", std::ios::binary | std::ios::trunc) << journal;
  JournalReading reading = s.ReadJournalLines();
  EXPECT_EQ(reading.damaged_lines, std::vector<int>{2});
  ASSERT_EQ(reading.entries.size(), 2u);
  EXPECT_EQ(reading.entries[1].index, 2);
  // A line of an earlier version: no check, no session id.
  nlohmann::json old = PlannedEntry(s, plan, 1).ToJson();
  old.erase("session_id");
  std::ofstream(dir + "/journal.jsonl", std::ios::app) << old.dump() << "\n";
  reading = s.ReadJournalLines();
  EXPECT_EQ(reading.entries.size(), 3u);
  EXPECT_EQ(reading.entries[1].session_id, "");
  fs::remove_all(dir);
}

TEST(Session, JournalEntriesMustBeOfTheSessionAndItsPlan) {
  const std::string dir = TempDir("mismatch");
  const CapturePlan plan = SmallPlan();  // dark, Z0,0+ and 6 lobes of order 1; 2 exposures
  SessionFolder s = SessionFolder::Create(dir, {{"plan", plan.ToJson()}});
  const std::string id = s.session_id();
  const JournalEntry good = PlannedEntry(s, plan, 3);
  EXPECT_EQ(JournalEntryMismatch(good, plan, id, true), "");
  JournalEntry e = good;
  e.session_id = "0123456789abcdef";
  EXPECT_NE(JournalEntryMismatch(e, plan, id, true).find("belongs to session 0123456789abcdef"),
            std::string::npos);
  EXPECT_EQ(JournalEntryMismatch(e, plan, "", true), "") << "a session of an earlier version";
  e = good;
  e.lobe = "Z1,1-";
  EXPECT_NE(JournalEntryMismatch(e, plan, id, true).find("says lobe Z1,1-"), std::string::npos);
  e = good;
  e.exposure = 0;
  EXPECT_NE(JournalEntryMismatch(e, plan, id, true), "");
  e = good;
  e.index = plan.frame_count();
  EXPECT_NE(JournalEntryMismatch(e, plan, id, true).find("the plan has 16 frames"),
            std::string::npos);
  e = good;
  e.file = FrameFileName(2);
  EXPECT_NE(JournalEntryMismatch(e, plan, id, true), "");
  e = good;  // frame 3 is lobe 1's second exposure
  e.exposure_us_requested *= 1.5;
  EXPECT_NE(JournalEntryMismatch(e, plan, id, true).find("requested"), std::string::npos);
  EXPECT_EQ(JournalEntryMismatch(e, plan, id, false), "") << "decided while capturing";
  fs::remove_all(dir);
}

// A process that holds the session's lock until told to exit; a pipe says when it holds it.
class LockHolder {
 public:
  explicit LockHolder(const std::string& dir) {
    int ready[2], release[2];
    EXPECT_EQ(::pipe(ready), 0);
    EXPECT_EQ(::pipe(release), 0);
    pid_ = ::fork();
    if (pid_ == 0) {
      ::close(ready[0]);
      ::close(release[1]);
      {
        SessionFolder s = SessionFolder::OpenForWriting(dir);
        char c = 1;
        (void)!::write(ready[1], &c, 1);
        (void)!::read(release[0], &c, 1);  // until the parent closes its end
      }
      ::_exit(0);
    }
    ::close(ready[1]);
    ::close(release[0]);
    release_ = release[1];
    char c = 0;
    EXPECT_EQ(::read(ready[0], &c, 1), 1);
    ::close(ready[0]);
  }
  ~LockHolder() { Kill(); }
  pid_t pid() const { return pid_; }
  void Kill() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    ::close(release_);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
  int release_ = -1;
};

// Issue 15, case 3: one writer per session. A second writer fails at once, naming the holder's
// PID; readers do not wait; a writer killed by SIGKILL holds nothing any more.
TEST(Session, OneWriterAtATimeAndReadersNeverWait) {
  const std::string dir = TempDir("lock");
  const CapturePlan plan = SmallPlan();
  {
    SessionFolder s = SessionFolder::Create(dir, {{"plan", plan.ToJson()}});
    s.AppendJournal(PlannedEntry(s, plan, 0));
  }
  LockHolder holder(dir);
  try {
    SessionFolder::OpenForWriting(dir);
    FAIL() << "a second writer was let in";
  } catch (const SessionBusyError& e) {
    EXPECT_EQ(e.holder_pid(), holder.pid());
    const std::string what = e.what();
    EXPECT_NE(what.find("is being written by pid " + std::to_string(holder.pid()) + ": "),
              std::string::npos)
        << what;
  }
  EXPECT_NE(SessionLock::Holder(dir).find("pid " + std::to_string(holder.pid())),
            std::string::npos);
  // Readers: the session and its journal, while the writer holds the lock.
  EXPECT_EQ(SessionFolder::Open(dir).ReadJournal().size(), 1u);
  holder.Kill();
  EXPECT_EQ(SessionLock::Holder(dir), "");
  // Re-entrant within a process: the runner opens a session its command already holds.
  SessionFolder a = SessionFolder::OpenForWriting(dir);
  SessionFolder b = SessionFolder::OpenForWriting(dir);
  EXPECT_EQ(a.lock().get() != nullptr, true);
  fs::remove_all(dir);
}

// Temporary files of killed runs are removed when the session is opened for writing.
TEST(Session, TemporaryFilesOfKilledRunsAreRemovedOnResume) {
  const std::string dir = TempDir("leftovers");
  SessionFolder::Create(dir, nlohmann::json::object());
  const pid_t gone = ::fork();
  if (gone == 0) ::_exit(0);
  ::waitpid(gone, nullptr, 0);
  const std::string suffix = ".tmp" + std::to_string(gone);
  for (const std::string name : {"frames/f000003.tiff", "hdr/dark.exr", "zonal.exr"}) {
    testing::WriteFile(dir + "/" + name + suffix, "half a file");
  }
  const SessionFolder s = SessionFolder::OpenForWriting(dir);
  const std::vector<std::string> expected = {"zonal.exr" + suffix, "frames/f000003.tiff" + suffix,
                                             "hdr/dark.exr" + suffix};
  EXPECT_EQ(s.repairs().temporary_files_removed, expected);
  for (const std::string& name : expected) EXPECT_FALSE(fs::exists(dir + "/" + name)) << name;
  fs::remove_all(dir);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
