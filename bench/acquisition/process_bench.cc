// Processing speed: a full-resolution, order-4 session (150 frames of the thesis camera) from
// frames on disk to zonal.exr, with and without the per-lobe HDR images; and its parts (frame
// decode, exposure merge). Target (issue 4): <= 5 s on 2 cores, HDR images included.
//
// The session is simulated once (about a minute) and kept in the cache folder
// (<cache>/bench/session-...); later runs reuse it.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>

#include "acquisition/capture_job.h"
#include "acquisition/frame_file.h"
#include "acquisition/hdr.h"
#include "acquisition/session.h"
#include "basis/data_path.h"
#include "basis/hash.h"
#include "brdf/material_spec.h"
#include "simulate/virtual_rig.h"

namespace zbrdf {
namespace {

struct BenchSession {
  Rig rig = LoadRig(DataPath("rig/rigs/thesis.yaml"));
  std::string dir;
  std::unique_ptr<RigCalibration> calibration;

  BenchSession() {
    char leaf[64];
    std::snprintf(leaf, sizeof(leaf), "/bench/session-%016llx-order4",
                  static_cast<unsigned long long>(RigHash(rig)));
    dir = DefaultCacheDir() + leaf;
    const OpticalSystem optics(rig);
    calibration = std::make_unique<RigCalibration>(
        NominalCalibration(rig, LoadOrBuildRigMaps(optics, DefaultCacheDir())));
    if (std::filesystem::exists(SessionPath(dir, kZonalFile))) return;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(std::filesystem::path(dir).parent_path());
    std::fprintf(stderr, "simulating the benchmark session into %s (once, about a minute)\n",
                 dir.c_str());
    VirtualRig::Options o;
    VirtualRig virtual_rig(rig, MakeBrdf("merl:blue-acrylic"), o);
    CaptureJobOptions job;
    job.out_dir = dir;
    job.order = 4;
    RunCaptureJob(virtual_rig.rig(), *calibration, virtual_rig.camera(), virtual_rig.projector(),
                  virtual_rig.clock(), job);
  }
};

const BenchSession& Session() {
  static const BenchSession session;
  return session;
}

// Issue 4's number: frames on disk -> zonal.exr. Arg: 1 writes the 50 HDR images too.
void BM_ProcessSession(benchmark::State& state) {
  const BenchSession& s = Session();
  ProcessingOptions options;
  options.write_hdr_images = state.range(0) != 0;
  for (auto _ : state) {
    const ProcessResult r = ProcessSession(s.dir, *s.calibration, options, "");
    benchmark::DoNotOptimize(r.zonal.tensor[0].data());
    state.counters["read_s"] = r.read_seconds;
    state.counters["hdr_s"] = r.processing.hdr_seconds;
    state.counters["zonal_s"] = r.processing.zonal_seconds;
    state.counters["images_s"] = r.processing.image_seconds;
  }
  state.counters["frames"] = 150;
}
BENCHMARK(BM_ProcessSession)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(3);

std::vector<Frame> FirstLobeFrames() {
  const BenchSession& s = Session();
  const SessionFolder folder = SessionFolder::Open(s.dir);
  const std::vector<JournalEntry> journal = folder.ReadJournal();
  std::vector<Frame> frames;
  for (int i = 3; i < 6; ++i) frames.push_back(folder.ReadFrame(journal[i]));  // Z0,0+
  return frames;
}

void BM_FrameEncode(benchmark::State& state) {
  const Frame frame = FirstLobeFrames()[2];
  size_t bytes = 0;
  for (auto _ : state) bytes = EncodeFrameFile(frame).size();
  state.counters["MB"] = bytes * 1e-6;
}
BENCHMARK(BM_FrameEncode)->Unit(benchmark::kMillisecond);

void BM_FrameDecode(benchmark::State& state) {
  const Frame frame = FirstLobeFrames()[2];
  const std::string bytes = EncodeFrameFile(frame);
  for (auto _ : state) {
    benchmark::DoNotOptimize(DecodeFrameFile(bytes, frame.width, frame.height, "bench").data());
  }
}
BENCHMARK(BM_FrameDecode)->Unit(benchmark::kMillisecond);

// What a frame's checksums cost on the frame writer's thread: the samples' (ImageDescription)
// and the file's (the journal line). Argument 0: FNV-1a 64 (frames written before XXH3),
// 1: XXH3 64.
void BM_FrameChecksum(benchmark::State& state) {
  const Frame frame = FirstLobeFrames()[2];
  const std::string bytes = EncodeFrameFile(frame);
  const bool xxh3 = state.range(0) == 1;
  for (auto _ : state) {
    benchmark::DoNotOptimize(xxh3 ? FrameSamplesChecksum(frame.data)
                                  : FrameSamplesFnv1a64(frame.data));
    benchmark::DoNotOptimize(xxh3 ? Xxh3_64(bytes) : Fnv1a64(bytes));
  }
  state.SetBytesProcessed(state.iterations() *
                          static_cast<int64_t>(frame.data.size() * 2 + bytes.size()));
}
BENCHMARK(BM_FrameChecksum)->ArgName("xxh3")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// One lobe's 3-exposure bracket at 1360 x 1024.
void BM_MergeExposures(benchmark::State& state) {
  const std::vector<Frame> frames = FirstLobeFrames();
  for (auto _ : state) {
    const HdrImage hdr = MergeExposures(frames, *Session().calibration, "bench");
    benchmark::DoNotOptimize(hdr.rate.data());
  }
}
BENCHMARK(BM_MergeExposures)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace zbrdf
