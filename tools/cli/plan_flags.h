// Flags shared by the commands that plan a capture (simulate, capture).
#pragma once

#include "acquisition/capture_job.h"
#include "tools/cli/command.h"

namespace zbrdf::cli {

void AddPlanFlags(CommandLine& cl);
// Reads them into options (order, zone, bracket, repeats, grid, HDR images).
void ReadPlanFlags(const CommandLine& cl, CaptureJobOptions* options);

}  // namespace zbrdf::cli
