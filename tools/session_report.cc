#include "tools/session_report.h"

#include <cstdio>

#include "acquisition/session.h"
#include "basis/atomic_file.h"
#include "basis/zone.h"

namespace zbrdf {

nlohmann::json CaptureJobReport(const CaptureJobResult& r, double device_time_s) {
  nlohmann::json j;
  j["complete"] = r.complete;
  j["zone_deg"] = {RadToDeg(r.plan.theta_min_rad), RadToDeg(r.plan.theta_max_rad)};
  j["order"] = r.plan.order;
  j["patterns"] = r.plan.lobes.size();
  j["frames"] = r.plan.frame_count();
  j["frames_captured"] = r.capture.frames_captured;
  j["frames_reused"] = r.capture.frames_reused;
  // What a resume did not trust or repaired, and where --force-new moved the folder's contents.
  if (r.capture.journal_lines_rejected > 0) {
    j["journal_lines_rejected"] = r.capture.journal_lines_rejected;
    j["first_rejection"] = r.capture.first_rejection;
  }
  if (r.repairs.any()) j["repairs"] = r.repairs.Summary();
  if (!r.moved_aside.empty()) j["moved_aside"] = r.moved_aside;
  j["exposures_us"] = r.plan.exposures_us;
  j["capture_time_model_s"] = device_time_s;
  j["capture_time_predicted_s"] = r.predicted_capture_time_s;
  // Processing streams with the capture: zonal.exr was on disk this long after the last frame.
  if (r.complete) j["ready_after_last_frame_s"] = r.ready_after_last_frame_s;
  j["saturated_pixel_lobes"] = r.processing.saturated_pixels;
  j["grid_cells_filled"] = r.processing.filled_cells;
  j["grid"] = {{"theta_step_deg", RadToDeg(r.zonal.grid.theta_step_rad)},
               {"phi_step_deg", RadToDeg(r.zonal.grid.phi_step_rad)},
               {"n_theta", r.zonal.grid.n_theta},
               {"n_phi", r.zonal.grid.n_phi}};
  // Adaptive sessions: which bands were taken and why it stopped; predicted_s was for the
  // largest order, capture_time_model_s is what it took.
  if (!r.adaptive.is_null()) {
    j["adaptive"] = r.adaptive;
    // Lobes isotropy made redundant have no frames.
    int skipped = 0;
    for (const PlannedLobe& lobe : r.plan.lobes) {
      for (const auto& name : r.adaptive.value("skipped_lobes", nlohmann::json::array())) {
        skipped += name.get<std::string>() == lobe.Name();
      }
    }
    j["patterns"] = r.plan.lobes.size() - skipped;
    j["frames"] = r.plan.frame_count() - skipped * static_cast<int>(r.plan.exposures_us.size()) * r.plan.repeats;
  }
  return j;
}

void PrintPlanSummary(const CapturePlan& plan, double predicted_s) {
  std::string bracket;
  for (double t : plan.exposures_us) {
    char b[32];
    std::snprintf(b, sizeof(b), "%s%.4g", bracket.empty() ? "" : ", ", t * 1e-3);
    bracket += b;
  }
  std::fprintf(stderr,
               "plan: zone %.1f-%.1f deg, order %d: %zu patterns x %zu exposures (%s ms) x %d = %d "
               "frames; predicted capture time on the rig %.1f s\n",
               RadToDeg(plan.theta_min_rad), RadToDeg(plan.theta_max_rad), plan.order,
               plan.lobes.size(), plan.exposures_us.size(), bracket.c_str(), plan.repeats,
               plan.frame_count(), predicted_s);
}

void WriteSessionReport(const std::string& session_dir, const nlohmann::json& report) {
  WriteFileAtomically(SessionPath(session_dir, kReportFile), report.dump(2) + "\n");
}

std::string FormatCaptureSummary(const nlohmann::json& j) {
  char buf[1024];
  std::string out;
  std::snprintf(buf, sizeof(buf), "  zone %.1f-%.1f deg, order %d: %d patterns, %d frames\n",
                j["zone_deg"][0].get<double>(), j["zone_deg"][1].get<double>(), j["order"].get<int>(),
                j["patterns"].get<int>(), j["frames"].get<int>());
  out += buf;
  std::snprintf(buf, sizeof(buf), "  capture time on the rig: %.1f s (predicted %.1f s)\n",
                j["capture_time_model_s"].get<double>(), j["capture_time_predicted_s"].get<double>());
  out += buf;
  if (j.contains("ready_after_last_frame_s")) {
    std::snprintf(buf, sizeof(buf), "  zonal.exr written %.2f s after the last frame\n",
                  j["ready_after_last_frame_s"].get<double>());
    out += buf;
  }
  if (j.value("frames_reused", 0) > 0) {
    std::snprintf(buf, sizeof(buf), "  resumed: %d frames kept from earlier runs, %d captured\n",
                  j.value("frames_reused", 0), j.value("frames_captured", 0));
    out += buf;
  }
  if (j.contains("journal_lines_rejected")) {
    out += "  not trusted: " + std::to_string(j["journal_lines_rejected"].get<int>()) +
           " journal line(s), captured again (first: " + j.value("first_rejection", std::string()) +
           ")\n";
  }
  if (j.contains("repairs")) out += "  repaired: " + j["repairs"].get<std::string>() + "\n";
  if (j.contains("moved_aside")) {
    out += "  the folder's earlier contents were moved to " + j["moved_aside"].get<std::string>() +
           "\n";
  }
  if (j.contains("adaptive")) {
    const nlohmann::json& a = j["adaptive"];
    std::snprintf(buf, sizeof(buf), "  adaptive: order %d of at most %d (%s), predicted error %.3g%%\n",
                  a.value("order", 0), a.value("max_order", 0),
                  a.value("reason", std::string()).c_str(), 100 * a.value("predicted_error", 0.0));
    out += buf;
  }
  if (j.contains("wall_time_s")) {
    const auto& w = j["wall_time_s"];
    std::string stages;
    for (auto it = w.begin(); it != w.end(); ++it) {
      std::snprintf(buf, sizeof(buf), "%s%s %.2f s", stages.empty() ? "" : ", ", it.key().c_str(),
                    it.value().get<double>());
      stages += buf;
    }
    out += "  wall time: " + stages + "\n";
  }
  if (j.contains("coefficient_error_in_zone")) {
    std::snprintf(buf, sizeof(buf), "  coefficient error in the zone: %.3g%% (relative L2 against the material)\n",
                  100 * j["coefficient_error_in_zone"].get<double>());
    out += buf;
  }
  return out;
}

}  // namespace zbrdf
