// The report of a capture job (report.json in the session folder, and `--json` output).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "acquisition/capture_job.h"

namespace zbrdf {

// Frames, capture time (modeled for the virtual rig), processing times, pattern quantization
// errors, saturation and grid-fill counts.
nlohmann::json CaptureJobReport(const CaptureJobResult& result, double device_time_s);

// Writes report.json atomically into the session folder.
void WriteSessionReport(const std::string& session_dir, const nlohmann::json& report);

// One line to stderr before the capture starts: zone, order, patterns, bracket, frames and the
// predicted capture time on the rig. Suitable as CaptureJobOptions::on_plan.
void PrintPlanSummary(const CapturePlan& plan, double predicted_s);

// A few human-readable lines.
std::string FormatCaptureSummary(const nlohmann::json& report);

}  // namespace zbrdf
