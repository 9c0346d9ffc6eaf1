#include "drivers/rig_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "drivers/aravis_camera.h"

namespace zbrdf {

namespace {

std::string Format(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char text[256];
  std::snprintf(text, sizeof(text), format, a, b, c, d);
  return text;
}

struct Levels {
  double mean = 0;
  double p99 = 0;
  double saturated_fraction = 0;
  double full_scale = 1;
};

Levels Measure(const Frame& frame) {
  Levels levels;
  levels.full_scale = std::ldexp(1.0, frame.bit_depth) - 1.0;
  if (frame.data.empty()) return levels;
  double sum = 0;
  size_t saturated = 0;
  for (uint16_t v : frame.data) {
    sum += v;
    if (v >= levels.full_scale) ++saturated;
  }
  levels.mean = sum / static_cast<double>(frame.data.size());
  levels.saturated_fraction =
      static_cast<double>(saturated) / static_cast<double>(frame.data.size());
  std::vector<uint16_t> sorted = frame.data;
  const size_t k = std::min(sorted.size() - 1, sorted.size() * 99 / 100);
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
  levels.p99 = sorted[k];
  return levels;
}

Pattern Uniform(const ProjectorInfo& info, uint16_t level) {
  Pattern p;
  p.width = info.width;
  p.height = info.height;
  p.bit_depth = info.bit_depth;
  p.levels.assign(static_cast<size_t>(info.width) * static_cast<size_t>(info.height), level);
  return p;
}

Pattern Checkerboard(const ProjectorInfo& info, int cell) {
  Pattern p = Uniform(info, 0);
  const uint16_t white = static_cast<uint16_t>((1u << info.bit_depth) - 1u);
  for (int y = 0; y < info.height; ++y) {
    for (int x = 0; x < info.width; ++x) {
      if (((x / cell) + (y / cell)) % 2 == 0) {
        p.levels[static_cast<size_t>(y) * info.width + x] = white;
      }
    }
  }
  return p;
}

}  // namespace

bool RigCheckReport::AllPassed() const {
  return std::all_of(items.begin(), items.end(), [](const RigCheckItem& i) { return i.passed; });
}

void RigCheckOptions::Validate() const {
  OptionChecker check("RigCheckOptions");
  check.InRange("frames", frames, 1, 1000)
      .Positive("exposure_us", exposure_us)
      .Above("grab_timeout (ms)", static_cast<double>(grab_timeout.count()), 0)
      .Positive("budget_s", budget_s)
      .InRange("dark_max_fraction", dark_max_fraction, 0, 1)
      .InRange("white_min_contrast", white_min_contrast, 0, 1)
      .InRange("saturated_max_fraction", saturated_max_fraction, 0, 1)
      .Above("latency_window (ms)", static_cast<double>(latency_window.count()), 0)
      .AtLeast("steady_state_ms", steady_state_ms, 0)
      .ThrowIfInvalid();
}

RigCheckReport RunRigCheck(Camera& camera, Projector& projector, X11Display* display,
                           Dlpc350* control, const RigSyncConfig& sync, Clock& clock,
                           const RigCheckOptions& options) {
  options.Validate();
  RigCheckReport report;
  const auto start = std::chrono::steady_clock::now();
  auto elapsed_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  auto add = [&](const std::string& name, bool passed, const std::string& detail) {
    report.items.push_back({name, passed, detail});
  };
  auto out_of_time = [&](const std::string& name) {
    if (elapsed_s() < options.budget_s) return false;
    add(name, false,
        Format("skipped: the %.0f s budget ran out (a device is slow to answer; see the items "
               "above)",
               options.budget_s));
    return true;
  };
  const double settle_ms =
      sync.mode == SyncMode::kHardware ? sync.hardware_settle_ms : sync.software_settle_ms;

  // camera
  bool camera_ok = false;
  CameraInfo info;
  try {
    info = camera.Info();
    const double used = camera.SetExposure(options.exposure_us);
    camera_ok = true;
    add("camera", true,
        info.model + ", " + std::to_string(info.width) + "x" + std::to_string(info.height) + " " +
            PixelLayoutName(info.layout) + " " + std::to_string(info.bit_depth) + " bit, " +
            Format("exposure %.0f us", used));
  } catch (const Error& e) {
    add("camera", false, e.what());
  }

  // camera.frames
  if (!camera_ok) {
    add("camera.frames", false, "skipped: the camera did not open (see camera)");
  } else if (!out_of_time("camera.frames")) {
    int arrived = 0;
    std::string failure;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < options.frames && elapsed_s() < options.budget_s; ++i) {
      try {
        camera.Grab(options.grab_timeout);
        ++arrived;
      } catch (const Error& e) {
        failure = e.what();
        break;
      }
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::string stats;
    if (auto* aravis = dynamic_cast<AravisCamera*>(&camera)) {
      const AravisCameraStats s = aravis->Stats();
      stats = "; " + std::to_string(s.incomplete_frames) + " incomplete frames re-captured, " +
              std::to_string(s.timeouts) + " timeouts";
    }
    if (arrived == options.frames) {
      add("camera.frames", true,
          Format("%.0f/%.0f frames in %.2f s (%.1f fps)", arrived, options.frames, seconds,
                 arrived / std::max(seconds, 1e-9)) +
              stats);
    } else {
      camera_ok = failure.find("stopped answering") == std::string::npos;
      add("camera.frames", false,
          Format("%.0f/%.0f frames arrived: ", arrived, options.frames) +
              (failure.empty() ? std::string("budget ran out") : failure) + stats);
    }
  }

  // projector.control
  if (control != nullptr && !out_of_time("projector.control")) {
    try {
      const Dlpc350Status status = control->GetStatus();
      const Dlpc350Version version = control->GetVersion();
      const std::string problems = status.Problems();
      add("projector.control", problems.empty(),
          (problems.empty() ? "status OK" : "controller reports: " + problems) + ", firmware " +
              version.ApplicationString() +
              (status.SequencerRunning() ? ", sequencer running" : ""));
    } catch (const Error& e) {
      add("projector.control", false, e.what());
    }
  }

  // projector.display
  const ProjectorInfo pinfo = projector.Info();
  const uint16_t white_level = static_cast<uint16_t>((1u << pinfo.bit_depth) - 1u);
  bool display_ok = false;
  if (!out_of_time("projector.display")) {
    try {
      std::string mismatch;
      const Pattern patterns[] = {Uniform(pinfo, 0), Uniform(pinfo, white_level),
                                  Checkerboard(pinfo, std::max(8, pinfo.width / 16))};
      const char* names[] = {"black", "white", "checkerboard"};
      for (int i = 0; i < 3; ++i) {
        projector.Show(patterns[i]);
        if (display != nullptr && !CaptureMatches(display->ReadBack(), patterns[i])) {
          mismatch += (mismatch.empty() ? "" : ", ") + std::string(names[i]);
        }
      }
      display_ok = mismatch.empty();
      add("projector.display", display_ok,
          display_ok ? std::to_string(pinfo.width) + "x" + std::to_string(pinfo.height) + " on " +
                           pinfo.id +
                           (display != nullptr ? ": black, white, checkerboard read back exactly"
                                               : ": shown (no read-back available)")
                     : "read-back differs for " + mismatch +
                           ": another window covers the output, or the output is scaled; "
                           "check projector.x11_output");
    } catch (const Error& e) {
      add("projector.display", false, e.what());
    }
  }

  // projector.readback_latency
  if (display != nullptr && display_ok && !out_of_time("projector.readback_latency")) {
    try {
      const auto latency =
          display->MeasureReadbackLatency(Uniform(pinfo, white_level / 2), options.grab_timeout);
      add("projector.readback_latency", true,
          Format("%.2f ms from sending an image to the X server showing it (%.0f Hz output)",
                 latency.count() / 1000.0, display->RefreshHz()));
    } catch (const Error& e) {
      add("projector.readback_latency", false, e.what());
    }
  }

  // levels.dark, levels.white
  Levels dark, white;
  bool levels_ok = false;
  if (!camera_ok) {
    add("levels.dark", false, "skipped: no frames from the camera (see camera.frames)");
    add("levels.white", false, "skipped: no frames from the camera (see camera.frames)");
  } else if (!out_of_time("levels.dark")) {
    try {
      RigSyncConfig steady = sync;
      steady.software_settle_ms = std::max(sync.software_settle_ms, options.steady_state_ms);
      steady.hardware_settle_ms = std::max(sync.hardware_settle_ms, options.steady_state_ms);
      PatternCapture capture(camera, projector, clock, steady);
      dark = Measure(capture.ShowAndGrab(Uniform(pinfo, 0), options.grab_timeout));
      const bool dark_ok = dark.mean <= options.dark_max_fraction * dark.full_scale;
      add("levels.dark", dark_ok,
          Format("mean %.1f DN (%.1f%% of full scale), 99th percentile %.0f DN", dark.mean,
                 100 * dark.mean / dark.full_scale, dark.p99) +
              (dark_ok ? ""
                       : Format("; above %.0f%% of full scale: stray light or a wrong black "
                                "level; shield the rig and check the camera's BlackLevel",
                                100 * options.dark_max_fraction)));
      if (!out_of_time("levels.white")) {
        white = Measure(capture.ShowAndGrab(Uniform(pinfo, white_level), options.grab_timeout));
        const double contrast = (white.mean - dark.mean) / white.full_scale;
        const bool bright = contrast >= options.white_min_contrast;
        const bool unsaturated = white.saturated_fraction <= options.saturated_max_fraction;
        levels_ok = bright && unsaturated;
        std::string detail = Format(
            "mean %.1f DN, %.2f%% of samples saturated, %.1f%% of full "
            "scale above the dark frame",
            white.mean, 100 * white.saturated_fraction, 100 * contrast);
        if (!bright) {
          detail += Format(
              "; needs at least %.0f%%: is the projector on, its LEDs enabled, "
              "aimed at the sample, the lens uncovered? Raise "
              "camera.check_exposure_us or the LED currents",
              100 * options.white_min_contrast);
        } else if (!unsaturated) {
          detail +=
              "; too many saturated samples: lower camera.check_exposure_us or the LED "
              "currents";
        }
        add("levels.white", levels_ok, detail);
      }
    } catch (const Error& e) {
      add(report.items.back().name == "levels.dark" ? "levels.white" : "levels.dark", false,
          e.what());
    }
  }

  // sync.latency
  if (!levels_ok) {
    add("sync.latency", false,
        "skipped: needs a white frame clearly brighter than the dark frame (see levels.white)");
  } else if (!out_of_time("sync.latency")) {
    try {
      const double threshold = 0.5 * (dark.mean + white.mean);
      RigSyncConfig steady = sync;
      steady.software_settle_ms = std::max(sync.software_settle_ms, options.steady_state_ms);
      steady.hardware_settle_ms = std::max(sync.hardware_settle_ms, options.steady_state_ms);
      PatternCapture capture(camera, projector, clock, steady);
      capture.ShowAndGrab(Uniform(pinfo, 0), options.grab_timeout);  // settled dark
      projector.Show(Uniform(pinfo, white_level));
      const int64_t shown_us = clock.NowUs();
      const auto deadline = std::chrono::steady_clock::now() + options.latency_window;
      int64_t last_dark_start_us = shown_us;
      bool seen = false;
      int64_t bright_start_us = 0;
      while (std::chrono::steady_clock::now() < deadline) {
        const Frame frame = camera.Grab(options.grab_timeout);
        if (Measure(frame).mean >= threshold) {
          bright_start_us = frame.timestamp_us;
          seen = true;
          break;
        }
        last_dark_start_us = frame.timestamp_us;
      }
      if (!seen) {
        add("sync.latency", false,
            Format("the camera saw no change within %.0f ms of showing white: the projector "
                   "does not follow the display (input source, standby?)",
                   static_cast<double>(options.latency_window.count())));
      } else {
        // A frame reads above the midpoint once more than half its exposure is lit, so the
        // light arrived between the last dark frame's and the first bright frame's
        // mid-exposure.
        const double half_exposure_ms = 0.5 * options.exposure_us / 1000.0;
        const double low_ms =
            std::max(0.0, (last_dark_start_us - shown_us) / 1000.0 + half_exposure_ms);
        const double high_ms = (bright_start_us - shown_us) / 1000.0 + half_exposure_ms;
        const bool ok = high_ms <= settle_ms;
        add("sync.latency", ok,
            Format("light reached the sample %.1f to %.1f ms after Show() returned; settle time "
                   "%.1f ms",
                   low_ms, high_ms, settle_ms) +
                (ok ? ""
                    : "; raise sync." + SyncModeName(sync.mode) + "_settle_ms above " +
                          Format("%.0f", std::ceil(high_ms))));
      }
    } catch (const Error& e) {
      add("sync.latency", false, e.what());
    }
  }

  report.seconds = elapsed_s();
  return report;
}

}  // namespace zbrdf
