// A full capture through the real GigE Vision stack (issue "Device drivers", acceptance): the
// virtual rig's frames served by Aravis's fake camera on 127.0.0.1 and grabbed by AravisCamera
// (tools/virtual_capture.h, CameraLink::kGigEFake), compared with the same capture grabbed from
// the virtual camera directly.
//
// Registered on its own (tests/tools/CMakeLists.txt) under RESOURCE_LOCK zbrdf_gige_fake_3956:
// one fake camera at a time can listen on 127.0.0.1:3956.
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "acquisition/session.h"
#include "acquisition/zonal.h"
#include "basis/error.h"
#include "tests/tools/simulated_sessions.h"
#include "tools/virtual_capture.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

constexpr const char* kMaterial = "merl:blue-acrylic";
constexpr int kOrder = 4;

// The same arguments as testing::SimulatedSession (the direct-link reference), over the fake.
VirtualCaptureArgs GigEArgs(const std::string& dir, const GigEFakeOptions& gige) {
  VirtualCaptureArgs args;
  args.rig = ApplyPreset(LoadRig(testing::ThesisRigPath()), Preset::kFast);
  args.preset_name = "fast";
  args.material_spec = kMaterial;
  args.seed = 1;
  args.camera_link = CameraLink::kGigEFake;
  args.gige = gige;
  args.job.out_dir = dir;
  args.job.order = kOrder;
  args.job.exposures = 3;
  args.job.processing.write_hdr_images = false;
  return args;
}

std::string FreshDir(const std::string& name) {
  const std::string dir = testing::TestBuildDir("test-gige") + "/" + name;
  fs::remove_all(dir);
  return dir;
}

std::map<int, std::string> JournalChecksums(const std::string& dir) {
  std::map<int, std::string> out;
  for (const JournalEntry& e : SessionFolder::Open(dir).ReadJournal()) out[e.index] = e.checksum;
  return out;
}

// Relative L2 difference of two sessions' zonal tensors, all channels.
double TensorDifference(const std::string& a_dir, const std::string& b_dir) {
  const ZonalData a = ReadZonalExr(a_dir + "/zonal.exr"), b = ReadZonalExr(b_dir + "/zonal.exr");
  double diff = 0, norm = 0;
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_EQ(a.tensor[ch].rows(), b.tensor[ch].rows());
    EXPECT_EQ(a.tensor[ch].cols(), b.tensor[ch].cols());
    if (a.tensor[ch].size() != b.tensor[ch].size()) return INFINITY;
    diff += (a.tensor[ch] - b.tensor[ch]).squaredNorm();
    norm += a.tensor[ch].squaredNorm();
  }
  return std::sqrt(diff / norm);
}

TEST(GigECapture, MatchesTheVirtualRigSessionThroughLossyGigEVision) {
  const std::string reference = testing::SimulatedSession(kMaterial, kOrder);
  const std::string dir = FreshDir("lossy");
  GigEFakeOptions gige;
  // One packet in 500 lost: about a quarter of the frames lose at least one. The driver asks for
  // resends and captures a frame again when packets stay missing; nothing incomplete is stored.
  gige.lost_packet_ratio = 0.002;
  const VirtualCaptureOutcome outcome = RunVirtualCapture(GigEArgs(dir, gige));
  ASSERT_TRUE(outcome.result.complete);
  // Acceptance: coefficients within 1% of the virtual-rig session's. Frames are keyed on the
  // plan's frame index on both links, so they are in fact identical, bit for bit.
  EXPECT_LT(TensorDifference(reference, dir), 0.01);
  EXPECT_EQ(JournalChecksums(dir), JournalChecksums(reference));
  const nlohmann::json session = SessionFolder::Open(dir).session();
  EXPECT_EQ(session.value("camera_link", std::string()), "gige-fake");
  EXPECT_EQ(session["devices"]["camera"]["id"], "127.0.0.1");
  fs::remove_all(dir);
}

TEST(GigECapture, ACameraThatStopsMidSessionIsReportedAndTheResumeCompletesIt) {
  const std::string reference = testing::SimulatedSession(kMaterial, kOrder);
  const std::string dir = FreshDir("stops");
  GigEFakeOptions stops;
  stops.stop_after_frames = 60;  // metering takes a few; the rest are plan frames
  std::string error;
  try {
    RunVirtualCapture(GigEArgs(dir, stops));
    FAIL() << "the capture should fail when the camera stops answering";
  } catch (const DeviceError& e) {
    error = e.what();
    EXPECT_NE(error.find("127.0.0.1"), std::string::npos) << error;
  }
  // The camera must have stopped mid-capture, not before the session began (say why if not).
  ASSERT_TRUE(fs::exists(dir + "/session.json"))
      << "the capture failed before its session: " << error;
  const size_t journaled = JournalChecksums(dir).size();
  EXPECT_GT(journaled, 30u);
  EXPECT_LT(journaled, 60u);
  // Resumed over a fresh fake camera (a new process would do the same): only what is missing is
  // captured, and the session equals the uninterrupted direct one.
  VirtualCaptureArgs resume = GigEArgs(dir, {});
  resume.job.resume = true;
  const VirtualCaptureOutcome outcome = RunVirtualCapture(resume);
  ASSERT_TRUE(outcome.result.complete);
  EXPECT_EQ(static_cast<size_t>(outcome.result.capture.frames_captured),
            JournalChecksums(reference).size() - journaled);
  EXPECT_EQ(JournalChecksums(dir), JournalChecksums(reference));
  EXPECT_LT(TensorDifference(reference, dir), 0.01);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace zbrdf
