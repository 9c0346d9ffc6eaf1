// zbrdf report: one self-contained HTML page about a session, or an index of a folder of them.
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
                 "Given a session folder, writes DIR/report.html: one self-contained page (images\n"
                 "embedded, no script, no external resources). Its first screen answers: the\n"
                 "material ball of the session's fit (beside the true material's, for simulated\n"
                 "sessions), the recommended fit, its errors in numbers and words (in the zone,\n"
                 "over the hemisphere, image), the rig time and the warnings. Then the pictures\n"
                 "(fit against truth, balls, polar plots, figure 3.3, fit candidates, coefficient\n"
                 "energy, calibration figure); the raw metadata (session.json, report.json, fit\n"
                 "reports, files) last, folded.\n"
                 "\n"
                 "Given a folder that is not a session, finds the sessions in it (down to 3\n"
                 "levels), writes each one's report.html where it is missing or older than a file\n"
                 "of its session (all of them with --rebuild), and writes DIR/index.html: one row\n"
                 "per session with its ball, material, fit, order, errors, rig time and links.");
  cl.Positional("DIR", "a session folder, or a folder holding session folders")
      .Option("size", "N", "size of the material balls in pixels", "256")
      .Option("spp", "N", "samples per pixel of the balls", "32")
      .Option("out", "FILE", "where to write (default DIR/report.html, or DIR/index.html)")
      .Flag("rebuild", "folder: write every session's report.html, even those up to date")
      .Flag("json", "print the pages written (and a session's sections and notes) as JSON")
      .Epilog(
          "Examples:\n"
          "  zbrdf report results/blue-acrylic        # results/blue-acrylic/report.html\n"
          "  zbrdf report results/accuracy/sessions   # an index.html of every session in it\n"
          "\n"
          "The words for errors and their thresholds: docs/preview.md (zbrdf report).");
  if (!cl.Parse(args)) return 0;
  const std::string dir = cl.Positional(0);
  ReportOptions options;
  options.preview_size = cl.GetInt("size", 16, 1024);
  options.preview_spp = cl.GetInt("spp", 1, 4096);

  if (!SessionFolder::Exists(dir)) {
    const std::string out = cl.Has("out") ? cl.Get("out") : dir + "/index.html";
    const FolderReport r = WriteFolderReport(dir, out, options, cl.Has("rebuild"));
    std::vector<std::string> pages = r.written;
    pages.insert(pages.begin(), r.index);
    if (cl.Has("json")) {
      std::cout << nlohmann::json{{"index", r.index},
                                  {"pages", pages},
                                  {"written", r.written},
                                  {"kept", r.kept},
                                  {"failed", r.failed}}
                       .dump(2)
                << "\n";
    } else {
      std::printf("wrote %s: %zu sessions (%zu pages written, %zu up to date)\n", r.index.c_str(),
                  r.written.size() + r.kept.size() + r.failed.size(), r.written.size(),
                  r.kept.size());
      for (const std::string& f : r.failed) std::printf("  no page: %s\n", f.c_str());
    }
    if (!r.failed.empty()) {
      std::fprintf(stderr,
                   "zbrdf report: %zu of the sessions have no page (listed above); the "
                   "index says why\n",
                   r.failed.size());
      return 1;
    }
    return 0;
  }

  const SessionReportPage page = BuildSessionReport(dir, options);
  const std::string out = cl.Has("out") ? cl.Get("out") : SessionPath(dir, kReportPageFile);
  WriteFileAtomically(out, page.html);
  if (cl.Has("json")) {
    std::cout << nlohmann::json{{"report", out},
                                {"pages", {out}},
                                {"sections", page.sections},
                                {"notes", page.notes},
                                {"summary",
                                 [&] {
                                   nlohmann::json s = page.summary.ToJson();
                                   s.erase("thumbnail_png");
                                   return s;
                                 }()}}
                     .dump(2, ' ', false, nlohmann::json::error_handler_t::replace)
              << "\n";
  } else {
    std::printf("wrote %s (%zu KiB): %s, accuracy %s\n", out.c_str(), page.html.size() / 1024,
                page.summary.fit.empty() ? "no fit yet" : page.summary.fit.c_str(),
                page.summary.Verdict().c_str());
    for (const std::string& note : page.notes) std::printf("  note: %s\n", note.c_str());
  }
  return 0;
}

const CommandRegistration kReportCommand(
    {"report",
     "write a self-contained HTML report of a session, or an index of a "
     "folder of sessions",
     RunReport});

}  // namespace
}  // namespace zbrdf::cli
