// zbrdf report: one self-contained HTML page about a session.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "acquisition/session.h"
#include "basis/atomic_file.h"
#include "pictures/html_report.h"
#include "tools/cli/command.h"

namespace zbrdf::cli {
namespace {

int RunReport(const std::vector<std::string>& args) {
  CommandLine cl("report",
                 "Writes SESSION/report.html: one self-contained page (images embedded, no\n"
                 "external resources) with the session's settings, timings and errors "
                 "(session.json,\nreport.json), the calibration figure (graycard.png), previews "
                 "and plots of the\nsession's BRDF, the coefficient energy per band, and for "
                 "simulated sessions the\nfit against the true material.");
  cl.Positional("SESSION", "the session folder")
      .Option("size", "N", "preview size in pixels", "192")
      .Option("spp", "N", "preview samples per pixel", "32")
      .Option("out", "FILE", "where to write (default SESSION/report.html)")
      .Flag("json", "print the sections and notes as JSON");
  if (!cl.Parse(args)) return 0;
  const std::string dir = cl.Positional(0);
  ReportOptions options;
  options.preview_size = cl.GetInt("size", 16, 1024);
  options.preview_spp = cl.GetInt("spp", 1, 4096);
  const SessionReportPage page = BuildSessionReport(dir, options);
  const std::string out = cl.Has("out") ? cl.Get("out") : SessionPath(dir, kReportPageFile);
  WriteFileAtomically(out, page.html);
  if (cl.Has("json")) {
    std::cout << nlohmann::json{{"report", out}, {"sections", page.sections}, {"notes", page.notes}}
                     .dump(2)
              << "\n";
  } else {
    std::printf("wrote %s (%zu KiB)\n", out.c_str(), page.html.size() / 1024);
    for (const std::string& note : page.notes) std::printf("  note: %s\n", note.c_str());
  }
  return 0;
}

const CommandRegistration kReg({"report", "write a self-contained HTML report of a session",
                                RunReport});

}  // namespace
}  // namespace zbrdf::cli
