// Session folders (acquisition/session.h): session.json through SessionFolder::Open and the
// capture plan it holds (CapturePlan::FromJson, as zbrdf process reads it), and the journal
// through ReadJournal. The input is session.json's bytes, a NUL, then journal.jsonl's bytes
// (no NUL: all of it is session.json and the journal is empty).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>

#include "acquisition/plan.h"
#include "acquisition/session.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string folder = [] {
    const std::string f = zbrdf::fuzz::ScratchDir() + "/session";
    std::filesystem::create_directories(f);
    return f;
  }();
  const auto* nul = static_cast<const uint8_t*>(std::memchr(data, 0, size));
  const size_t json_size = nul != nullptr ? static_cast<size_t>(nul - data) : size;
  const size_t journal_offset = nul != nullptr ? json_size + 1 : size;
  zbrdf::fuzz::WriteScratchFile("session/session.json", data, json_size);
  zbrdf::fuzz::WriteScratchFile("session/journal.jsonl", data + journal_offset,
                                size - journal_offset);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] {
    const zbrdf::SessionFolder session = zbrdf::SessionFolder::Open(folder);
    (void)session.ReadJournal();
    if (session.session().contains("plan")) {
      (void)zbrdf::CapturePlan::FromJson(session.session().at("plan"));
    }
  });
  return 0;
}
