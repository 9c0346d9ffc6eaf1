#include "acquisition/session.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "tests/acquisition/acquisition_test_util.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

std::string TempDir(const std::string& name) { return testing::FreshTempDir("session-test", name); }

Frame SmallFrame(uint16_t base) {
  Frame f;
  f.width = 16;
  f.height = 8;
  f.layout = PixelLayout::kBayerRGGB;
  f.bit_depth = 12;
  f.exposure_us = 500;
  for (int i = 0; i < 16 * 8; ++i) f.data.push_back(static_cast<uint16_t>(base + i));
  return f;
}

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Session, Fnv1aChecksumMatchesPublishedVectors) {
  // FNV-1a 64 test vectors (Fowler, Noll, Vo: offset basis and "a", "foobar").
  const std::string dir = TempDir("fnv");
  fs::create_directories(dir);
  const std::pair<std::string, std::string> vectors[] = {{"", "cbf29ce484222325"},
                                                         {"a", "af63dc4c8601ec8c"},
                                                         {"foobar", "85944171f73967e8"}};
  for (const auto& [text, hex] : vectors) {
    WriteFileAtomically(dir + "/f", text);
    EXPECT_EQ(FileChecksum(dir + "/f"), "fnv1a64:" + hex) << '"' << text << '"';
  }
  EXPECT_EQ(FileChecksum(dir + "/missing"), "");
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

}  // namespace
}  // namespace zbrdf
