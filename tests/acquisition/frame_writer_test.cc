#include "acquisition/frame_writer.h"

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "tests/acquisition/acquisition_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;

using testing::SmallFrame;

JournalEntry PlanFields(int index) {
  JournalEntry e;
  e.lobe = "l" + std::to_string(index / 3);
  e.exposure = index % 3;
  e.repeat = 0;
  e.exposure_us_requested = 500.0 * (1 << (index % 3));
  return e;
}

// Every fault plan is undone, so that none leaks into another test.
class FrameWriterTest : public ::testing::Test {
 protected:
  void TearDown() override { SetWriteFaultPlan({}); }
};

// More frames than the queue holds, so that Add blocks and resumes: each file and journal line
// is there, in the order handed over, with the capture's fields and the frame's samples, as
// SessionFolder::WriteFrame and AppendJournal on the capture's own thread left them.
TEST_F(FrameWriterTest, WritesEveryFrameAndLineInOrder) {
  const std::string dir = testing::FreshTempDir("frame-writer-test", "order");
  SessionFolder session = SessionFolder::Create(dir, nlohmann::json::object());
  const int n = 3 * FrameWriter::kMaxQueued + 1;
  std::vector<JournalEntry> entries;
  {
    FrameWriter writer(session);
    for (int i = 0; i < n; ++i) writer.Add(i, SmallFrame(static_cast<uint16_t>(100 * i)), PlanFields(i));
    entries = writer.Drain();
    EXPECT_TRUE(writer.Drain().empty()) << "each entry is returned once";
  }
  ASSERT_EQ(static_cast<int>(entries.size()), n);
  const std::vector<JournalEntry> journal = session.ReadJournal();
  ASSERT_EQ(static_cast<int>(journal.size()), n);
  for (int i = 0; i < n; ++i) {
    SCOPED_TRACE("frame " + std::to_string(i));
    EXPECT_EQ(entries[i].index, i);
    EXPECT_EQ(journal[i].index, i);
    EXPECT_EQ(journal[i].checksum, entries[i].checksum);
    EXPECT_EQ(journal[i].lobe, PlanFields(i).lobe);
    EXPECT_EQ(journal[i].exposure, PlanFields(i).exposure);
    EXPECT_EQ(journal[i].exposure_us_requested, PlanFields(i).exposure_us_requested);
    EXPECT_TRUE(session.FrameIsIntact(journal[i]));
    EXPECT_EQ(session.ReadFrame(journal[i]).data, SmallFrame(static_cast<uint16_t>(100 * i)).data);
  }
}

// A full disk at frame 2's file: frames 0 and 1 stay journaled, nothing after the failure is
// written (the journal ends at the last frame on disk), and the error reaches the capture.
TEST_F(FrameWriterTest, AFailedWriteStopsTheWritesAndIsThrownToTheCapture) {
  const std::string dir = testing::FreshTempDir("frame-writer-test", "failure");
  SessionFolder session = SessionFolder::Create(dir, nlohmann::json::object());
  SetWriteFaultPlan({WriteFault::kNoSpace, 1, 0.5, FrameFileName(2)});
  bool thrown = false;
  {
    FrameWriter writer(session);
    try {
      for (int i = 0; i < 8; ++i) writer.Add(i, SmallFrame(static_cast<uint16_t>(i)), PlanFields(i));
      writer.Drain();
    } catch (const FileWriteError& e) {
      thrown = true;
      EXPECT_NE(std::string(e.what()).find(FrameFileName(2)), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(thrown);
  SetWriteFaultPlan({});
  const std::vector<JournalEntry> journal = session.ReadJournal();
  ASSERT_EQ(journal.size(), 2u);
  EXPECT_EQ(journal[0].index, 0);
  EXPECT_EQ(journal[1].index, 1);
  for (int i = 2; i < 8; ++i) {
    EXPECT_FALSE(fs::exists(dir + "/" + FrameFileName(i))) << FrameFileName(i);
  }
}

// A capture that fails elsewhere (a camera gone) destroys the writer without draining it: what
// was handed over is still written and journaled.
TEST_F(FrameWriterTest, FramesHandedOverAreWrittenWhenTheCaptureFails) {
  const std::string dir = testing::FreshTempDir("frame-writer-test", "unwound");
  SessionFolder session = SessionFolder::Create(dir, nlohmann::json::object());
  try {
    FrameWriter writer(session);
    for (int i = 0; i < 3; ++i) writer.Add(i, SmallFrame(static_cast<uint16_t>(i)), PlanFields(i));
    throw DeviceError("camera gone");
  } catch (const DeviceError&) {
  }
  const std::vector<JournalEntry> journal = session.ReadJournal();
  ASSERT_EQ(journal.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(session.FrameIsIntact(journal[i])) << i;
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
