// From a session's frames to zonal coefficients: HDR merge per lobe, lobe subtraction,
// calibration, resampling onto the exitant grid, projection in w_r.
//
// ZonalProcessor takes the lobes in plan order (the dark pattern first), each as soon as its
// exposures are in; with Start() it works on a background thread while the capture goes on.
// Memory stays at a few images: a positive lobe waits only for its negative partner, and at
// most kMaxQueuedImages HDR images wait for their writer thread (demosaicing and lossless PIZ
// compression cost as much as the merge itself, so they run beside it).
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "acquisition/hdr.h"
#include "acquisition/patterns.h"
#include "acquisition/plan.h"
#include "acquisition/rig_calibration.h"
#include "acquisition/zonal.h"
#include "drivers/camera.h"

namespace zbrdf {

struct ProcessingOptions {
  double theta_step_deg = 1.0, phi_step_deg = 2.0;  // exitant grid
  bool write_hdr_images = true;                     // hdr/<lobe>.exr under hdr_folder
  std::string hdr_folder;
  HdrOptions hdr;
  // If set, called (on the processing thread) with each basis function's per-pixel values
  // z_k(pixel), before resampling and the channel scale, and which pixels are valid: the
  // gray-card calibration derives the camera's flat field from them.
  std::function<void(int k, const std::vector<float>& value, const std::vector<uint8_t>& valid)>
      pixel_values;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

// The zone, order and exitant grid of the ZonalData that processing a capture of `plan` fills
// (no values yet): what the true coefficients need before the capture has ended.
ZonalData ZonalLayout(const CapturePlan& plan, const ProcessingOptions& options);

struct ProcessingStats {
  double hdr_seconds = 0;    // merging exposures
  double image_seconds = 0;  // demosaicing and writing HDR images (on their own thread)
  double zonal_seconds = 0;  // lobe subtraction, resampling, exitant projection
  int saturated_pixels = 0;  // pixel-lobes with every exposure saturated
  int filled_cells = 0;      // grid cells filled by interpolation (first function, any channel)
};

class ZonalProcessor {
 public:
  ZonalProcessor(const CapturePlan& plan, const std::vector<LobePatternInfo>& patterns,
                 const RigCalibration& calibration, const ProcessingOptions& options);
  ~ZonalProcessor();

  // Processes lobes on a background thread from now on (AddLobe only queues them).
  void Start();
  // The frames (all exposures and repeats) of plan lobe `lobe`; lobes must come in plan order.
  // No frames: the lobe was not captured because the material is isotropic (adaptive capture,
  // docs/adaptive.md); its function is synthesized instead: a skipped negative lobe of Z_lm
  // (m > 0) after a measured positive one gives z_lm = 2 x the cos(m phi) part of the positive
  // lobe's response per theta row; skipped lobes of Z_l,-m (m > 0) give z_l,-m = the cos(m phi)
  // profile of z_lm times sin(m phi), once z_lm is known (SynthesizeIsotropic, or Finish).
  void AddLobe(int lobe, std::vector<Frame> frames);
  // Synthesizes the functions of band l (l < 0: all bands) whose lobes came without frames and
  // whose source is processed. Call after Wait().
  void SynthesizeIsotropic(int l = -1);
  // Waits for queued lobes; computes the tensor coefficients. Rethrows a processing error.
  ZonalData Finish();
  // The same for the plan truncated to `order` (<= the plan's): every lobe of bands <= order must
  // have been added; functions of higher bands already processed are dropped (adaptive capture).
  ZonalData Finish(int order);
  // Finish does not wait for the HDR images (hdr/) still queued for writing: this does, and
  // rethrows a failure to write one. Call it after writing zonal.exr, so that the coefficients
  // are on disk as soon as the last lobe is processed.
  void WaitForImages();
  // Waits until every lobe added so far is processed; rethrows a processing error. Then
  // Function() may be read until the next AddLobe.
  void Wait();
  // z_k on the exitant grid of basis function k, once its lobes are processed (else empty).
  const GridImage& Function(int k) const { return data_.functions.at(k); }
  const ExitantGrid& grid() const { return grid_; }
  const ProcessingStats& stats() const { return stats_; }

 private:
  void Process(int lobe, const std::vector<Frame>& frames);
  void ProcessSkipped(int lobe);
  void Worker();
  void QueueImage(std::string path, const HdrImage& hdr);
  void ImageWriter();
  void StopImageWriter();

  const CapturePlan& plan_;
  std::vector<LobePatternInfo> patterns_;
  const RigCalibration& calibration_;
  ProcessingOptions options_;
  ExitantGrid grid_;
  std::unique_ptr<PixelToGrid> resampler_;
  ZonalData data_;
  HdrImage dark_;
  bool have_dark_ = false;
  int pending_lobe_ = -1;
  HdrImage pending_;
  int next_lobe_ = 0;
  ProcessingStats stats_;
  // Background work.
  std::thread worker_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::pair<int, std::vector<Frame>>> queue_;
  bool stopping_ = false;
  int in_flight_ = 0;  // lobes queued or being processed
  std::vector<int> pending_synthesis_;  // functions k = (l, -m) awaiting z_lm
  bool skipped_positive_ = false;       // the last positive lobe came without frames
  std::exception_ptr error_;
  // HDR image writer.
  static constexpr size_t kMaxQueuedImages = 3;
  std::thread image_writer_;
  std::condition_variable image_cv_;
  std::deque<std::pair<std::string, HdrImage>> images_;
  bool images_done_ = false;
};

}  // namespace zbrdf
