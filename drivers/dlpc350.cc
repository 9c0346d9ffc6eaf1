#include "drivers/dlpc350.h"

#include <algorithm>
#include <cstdio>
#include <thread>

#include "basis/error.h"

namespace zbrdf {

namespace {

constexpr uint8_t kFlagRead = 0x80;
constexpr uint8_t kFlagReply = 0x40;
constexpr uint8_t kFlagNack = 0x20;
constexpr size_t kReportHeaderBytes = 4;

struct CommandName {
  uint16_t code;
  const char* name;
};
constexpr CommandName kCommandNames[] = {
    {dlpc350::kPowerControl, "POWER_CONTROL"},
    {dlpc350::kGetVersion, "GET_VERSION"},
    {dlpc350::kLedCurrent, "LED_CURRENT"},
    {dlpc350::kInputSource, "SOURCE_SEL"},
    {dlpc350::kLedEnable, "LED_ENABLE"},
    {dlpc350::kHardwareStatus, "STATUS_HW"},
    {dlpc350::kSystemStatus, "STATUS_SYS"},
    {dlpc350::kMainStatus, "STATUS_MAIN"},
    {dlpc350::kLutValidate, "LUT_VALID"},
    {dlpc350::kDisplayMode, "DISP_MODE"},
    {dlpc350::kTrigOut1, "TRIG_OUT1_CTL"},
    {dlpc350::kTrigOut2, "TRIG_OUT2_CTL"},
    {dlpc350::kPatternSource, "PAT_DISP_MODE"},
    {dlpc350::kPatternTriggerMode, "PAT_TRIG_MODE"},
    {dlpc350::kPatternStartStop, "PAT_START_STOP"},
    {dlpc350::kPatternExposure, "PAT_EXPO_PRD"},
    {dlpc350::kPatternConfig, "PAT_CONFIG"},
    {dlpc350::kMailboxAddress, "MBOX_ADDRESS"},
    {dlpc350::kMailboxControl, "MBOX_CONTROL"},
    {dlpc350::kMailboxData, "MBOX_DATA"},
};

void PutU32(std::vector<uint8_t>* out, uint32_t value) {
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<uint8_t>(value >> (8 * i)));
}

uint32_t GetU32(const std::vector<uint8_t>& in, size_t at) {
  return static_cast<uint32_t>(in[at]) | static_cast<uint32_t>(in[at + 1]) << 8 |
         static_cast<uint32_t>(in[at + 2]) << 16 | static_cast<uint32_t>(in[at + 3]) << 24;
}

std::string Hex(const std::vector<uint8_t>& bytes) {
  std::string out;
  char buffer[4];
  for (size_t i = 0; i < bytes.size(); ++i) {
    std::snprintf(buffer, sizeof(buffer), i == 0 ? "%02X" : " %02X", bytes[i]);
    out += buffer;
  }
  return out.empty() ? "none" : out;
}

}  // namespace

std::string Dlpc350CommandName(uint16_t command) {
  char code[16];
  std::snprintf(code, sizeof(code), "0x%04X", command);
  for (const auto& entry : kCommandNames) {
    if (entry.code == command) return std::string(entry.name) + " (" + code + ")";
  }
  return std::string("command ") + code;
}

std::vector<Dlpc350Report> EncodeDlpc350Write(uint8_t sequence, uint16_t command,
                                              const std::vector<uint8_t>& payload,
                                              bool reply_wanted) {
  const size_t length = payload.size() + 2;
  if (length > 0xFFFF) throw InputError("DLPC350 command payload too long");
  std::vector<uint8_t> message = {static_cast<uint8_t>(reply_wanted ? kFlagReply : 0),
                                  sequence,
                                  static_cast<uint8_t>(length & 0xFF),
                                  static_cast<uint8_t>(length >> 8),
                                  static_cast<uint8_t>(command & 0xFF),
                                  static_cast<uint8_t>(command >> 8)};
  message.insert(message.end(), payload.begin(), payload.end());
  std::vector<Dlpc350Report> reports;
  for (size_t at = 0; at < message.size(); at += 64) {
    Dlpc350Report report{};
    for (size_t i = 0; i < 64 && at + i < message.size(); ++i) report[i] = message[at + i];
    reports.push_back(report);
  }
  return reports;
}

Dlpc350Report EncodeDlpc350Read(uint8_t sequence, uint16_t command,
                                const std::vector<uint8_t>& parameter) {
  if (parameter.size() > 58) throw InputError("DLPC350 read parameter too long");
  const size_t length = parameter.size() + 2;
  Dlpc350Report report{};
  report[0] = kFlagRead | kFlagReply;
  report[1] = sequence;
  report[2] = static_cast<uint8_t>(length);
  report[3] = 0;
  report[4] = static_cast<uint8_t>(command & 0xFF);
  report[5] = static_cast<uint8_t>(command >> 8);
  for (size_t i = 0; i < parameter.size(); ++i) report[6 + i] = parameter[i];
  return report;
}

Dlpc350Reply DecodeDlpc350Reply(const Dlpc350Report& report) {
  Dlpc350Reply reply;
  reply.nack = (report[0] & kFlagNack) != 0;
  reply.sequence = report[1];
  const size_t length = static_cast<size_t>(report[2]) | static_cast<size_t>(report[3]) << 8;
  const size_t n = std::min(length, report.size() - kReportHeaderBytes);
  reply.data.assign(report.begin() + kReportHeaderBytes, report.begin() + kReportHeaderBytes + n);
  return reply;
}

std::string Dlpc350Status::Problems() const {
  std::vector<std::string> problems;
  if (!InitializationDone()) problems.push_back("internal initialization not done");
  if (ControllerDmdIncompatible()) problems.push_back("controller and DMD incompatible");
  if (DmdResetControllerError()) problems.push_back("DMD reset controller error");
  if (ForcedSwapError()) problems.push_back("forced buffer swap error");
  if (SequencerAbort()) problems.push_back("sequencer aborted");
  if (SequencerError()) problems.push_back("sequencer error");
  if (!MemoryTestPassed()) problems.push_back("internal memory test failed");
  if (DmdParked()) problems.push_back("DMD parked (projector in standby?)");
  std::string out;
  for (size_t i = 0; i < problems.size(); ++i) out += (i ? "; " : "") + problems[i];
  return out;
}

std::string Dlpc350Version::ApplicationString() const {
  return std::to_string(application >> 24) + "." + std::to_string((application >> 16) & 0xFF) +
         "." + std::to_string(application & 0xFFFF);
}

uint32_t Dlpc350PatternEntry::Encode() const {
  return (trigger_type & 0x3u) | (pattern_number & 0x3Fu) << 2 | (bit_depth & 0xFu) << 8 |
         (leds & 0x7u) << 12 | (invert ? 1u << 16 : 0u) | (insert_black ? 1u << 17 : 0u) |
         (buffer_swap ? 1u << 18 : 0u) | (trigger_out_previous ? 1u << 19 : 0u);
}

std::string Dlpc350ValidationResult::Problems() const {
  std::vector<std::string> problems;
  if (ExposureOrPeriodInvalid()) problems.push_back("exposure or frame period invalid");
  if (PatternNumberInvalid()) problems.push_back("pattern numbers in the LUT invalid");
  if (TriggerOut1Overlap()) problems.push_back("TRIG_OUT_1 continuous or overlapping black");
  if (PostVectorMissing()) problems.push_back("post vector missing before external trigger");
  if (PeriodExposureDifferenceTooSmall()) {
    problems.push_back("frame period minus exposure below 230 us");
  }
  std::string out;
  for (size_t i = 0; i < problems.size(); ++i) out += (i ? "; " : "") + problems[i];
  return out;
}

// ---------------------------------------------------------------------------------------------

Dlpc350::Dlpc350(std::unique_ptr<Dlpc350Transport> transport, Dlpc350Options options)
    : transport_(std::move(transport)), options_(options) {
  if (!transport_) throw InputError("Dlpc350 needs a transport");
  if (options_.retries < 0) throw InputError("DLPC350 retries must be >= 0");
}

Dlpc350Reply Dlpc350::Exchange(uint16_t command, const std::vector<Dlpc350Report>& reports,
                               const std::string& what) {
  const uint8_t sequence = reports.front()[1];
  for (int attempt = 0; attempt <= options_.retries; ++attempt) {
    for (const auto& report : reports) transport_->Write(report, options_.reply_timeout);
    const auto deadline = std::chrono::steady_clock::now() + options_.reply_timeout;
    while (true) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) break;
      Dlpc350Report raw{};
      if (!transport_->Read(&raw, left)) break;
      Dlpc350Reply reply = DecodeDlpc350Reply(raw);
      if (reply.sequence != sequence) continue;  // a late reply to an earlier command
      if (reply.nack) {
        throw DeviceError(transport_->Name() + ": " + Dlpc350CommandName(command) + " " + what +
                          " was rejected (NACK); the controller refuses this value or this "
                          "command in its current mode (stop the pattern sequence before "
                          "reconfiguring it)");
      }
      return reply;
    }
  }
  throw DeviceError(transport_->Name() + ": no reply to " + Dlpc350CommandName(command) + " " +
                    what + " within " + std::to_string(options_.reply_timeout.count()) + " ms (" +
                    std::to_string(options_.retries + 1) +
                    " attempts); check the USB cable and that the projector is powered");
}

void Dlpc350::WriteCommand(uint16_t command, const std::vector<uint8_t>& payload) {
  const auto reports = EncodeDlpc350Write(sequence_++, command, payload, true);
  Exchange(command, reports, "write of " + Hex(payload));
}

std::vector<uint8_t> Dlpc350::ReadCommand(uint16_t command, size_t expected_bytes,
                                          const std::vector<uint8_t>& parameter) {
  const Dlpc350Report report = EncodeDlpc350Read(sequence_++, command, parameter);
  Dlpc350Reply reply = Exchange(command, {report}, "read");
  if (reply.data.size() < expected_bytes) {
    throw DeviceError(transport_->Name() + ": " + Dlpc350CommandName(command) + " read returned " +
                      std::to_string(reply.data.size()) + " bytes, expected " +
                      std::to_string(expected_bytes));
  }
  reply.data.resize(expected_bytes);
  return reply.data;
}

void Dlpc350::SetStandby(bool standby) {
  WriteCommand(dlpc350::kPowerControl, {static_cast<uint8_t>(standby ? 1 : 0)});
}

bool Dlpc350::IsStandby() { return (ReadCommand(dlpc350::kPowerControl, 1)[0] & 0x03) != 0; }

void Dlpc350::SetDisplayMode(Dlpc350DisplayMode mode) {
  WriteCommand(dlpc350::kDisplayMode, {static_cast<uint8_t>(mode)});
}

Dlpc350DisplayMode Dlpc350::GetDisplayMode() {
  return ReadCommand(dlpc350::kDisplayMode, 1)[0] != 0 ? Dlpc350DisplayMode::kPatternSequence
                                                       : Dlpc350DisplayMode::kVideo;
}

void Dlpc350::SetInputSource(Dlpc350InputSource source, Dlpc350PortWidth width) {
  WriteCommand(dlpc350::kInputSource,
               {static_cast<uint8_t>(static_cast<int>(source) | static_cast<int>(width) << 3)});
}

void Dlpc350::GetInputSource(Dlpc350InputSource* source, Dlpc350PortWidth* width) {
  const uint8_t value = ReadCommand(dlpc350::kInputSource, 1)[0];
  *source = static_cast<Dlpc350InputSource>(value & 0x07);
  *width = static_cast<Dlpc350PortWidth>(value >> 3);
}

void Dlpc350::SetLedEnables(const Dlpc350LedEnables& e) {
  const uint8_t value =
      static_cast<uint8_t>((e.red ? 0x01 : 0) | (e.green ? 0x02 : 0) | (e.blue ? 0x04 : 0) |
                           (e.sequencer_controls ? 0x08 : 0));
  WriteCommand(dlpc350::kLedEnable, {value});
}

Dlpc350LedEnables Dlpc350::GetLedEnables() {
  const uint8_t value = ReadCommand(dlpc350::kLedEnable, 1)[0];
  Dlpc350LedEnables e;
  e.red = value & 0x01;
  e.green = value & 0x02;
  e.blue = value & 0x04;
  e.sequencer_controls = value & 0x08;
  return e;
}

void Dlpc350::SetLedCurrents(const Dlpc350LedCurrents& c) {
  WriteCommand(dlpc350::kLedCurrent, {c.red, c.green, c.blue});
}

Dlpc350LedCurrents Dlpc350::GetLedCurrents() {
  const auto data = ReadCommand(dlpc350::kLedCurrent, 3);
  return {data[0], data[1], data[2]};
}

void Dlpc350::SetTriggerOut1(const Dlpc350TriggerOut& t) {
  WriteCommand(dlpc350::kTrigOut1,
               {static_cast<uint8_t>(t.invert ? 1 : 0), t.rising_delay, t.falling_delay});
}

Dlpc350TriggerOut Dlpc350::GetTriggerOut1() {
  const auto data = ReadCommand(dlpc350::kTrigOut1, 3);
  return {data[0] != 0, data[1], data[2]};
}

void Dlpc350::SetTriggerOut2(const Dlpc350TriggerOut& t) {
  WriteCommand(dlpc350::kTrigOut2, {static_cast<uint8_t>(t.invert ? 1 : 0), t.rising_delay});
}

Dlpc350TriggerOut Dlpc350::GetTriggerOut2() {
  const auto data = ReadCommand(dlpc350::kTrigOut2, 2);
  Dlpc350TriggerOut t;
  t.invert = data[0] != 0;
  t.rising_delay = data[1];
  return t;
}

void Dlpc350::SetPatternSourceVideoPort(bool video_port) {
  WriteCommand(dlpc350::kPatternSource, {static_cast<uint8_t>(video_port ? 0 : 3)});
}

void Dlpc350::SetPatternTriggerMode(uint8_t mode) {
  if (mode > 4) throw InputError(Name() + ": pattern trigger mode must be 0-4");
  WriteCommand(dlpc350::kPatternTriggerMode, {mode});
}

void Dlpc350::SetPatternExposure(uint32_t exposure_us, uint32_t period_us) {
  std::vector<uint8_t> payload;
  PutU32(&payload, exposure_us);
  PutU32(&payload, period_us);
  WriteCommand(dlpc350::kPatternExposure, payload);
}

void Dlpc350::GetPatternExposure(uint32_t* exposure_us, uint32_t* period_us) {
  const auto data = ReadCommand(dlpc350::kPatternExposure, 8);
  *exposure_us = GetU32(data, 0);
  *period_us = GetU32(data, 4);
}

void Dlpc350::SetPatternConfig(int lut_entries, bool repeat, int patterns_per_trigger_out2,
                               int image_entries) {
  if (lut_entries < 1 || lut_entries > 128 || patterns_per_trigger_out2 < 1 ||
      patterns_per_trigger_out2 > 256 || image_entries < 1 || image_entries > 64) {
    throw InputError(Name() +
                     ": pattern config out of range (LUT entries 1-128, patterns per "
                     "TRIG_OUT_2 1-256, image entries 1-64)");
  }
  // The firmware takes counts minus one (0 means 1).
  WriteCommand(dlpc350::kPatternConfig,
               {static_cast<uint8_t>(lut_entries - 1), static_cast<uint8_t>(repeat ? 1 : 0),
                static_cast<uint8_t>(patterns_per_trigger_out2 - 1),
                static_cast<uint8_t>(image_entries - 1)});
}

void Dlpc350::SendPatternLut(const std::vector<Dlpc350PatternEntry>& entries) {
  if (entries.empty() || entries.size() > 128) {
    throw InputError(Name() + ": a pattern LUT has 1 to 128 entries, got " +
                     std::to_string(entries.size()));
  }
  std::vector<uint8_t> payload;
  for (const auto& entry : entries) {
    const uint32_t word = entry.Encode();
    payload.push_back(static_cast<uint8_t>(word));
    payload.push_back(static_cast<uint8_t>(word >> 8));
    payload.push_back(static_cast<uint8_t>(word >> 16));
  }
  WriteCommand(dlpc350::kMailboxControl, {2});
  WriteCommand(dlpc350::kMailboxAddress, {0});
  WriteCommand(dlpc350::kMailboxData, payload);
  WriteCommand(dlpc350::kMailboxControl, {0});
}

Dlpc350ValidationResult Dlpc350::ValidatePatternSequence() {
  WriteCommand(dlpc350::kLutValidate, {0});
  const auto deadline = std::chrono::steady_clock::now() + options_.validation_timeout;
  while (true) {
    const uint8_t status = ReadCommand(dlpc350::kLutValidate, 1)[0];
    if ((status & 0x80) == 0) return Dlpc350ValidationResult{status};
    if (std::chrono::steady_clock::now() > deadline) {
      throw DeviceError(Name() + ": pattern sequence validation still busy after " +
                        std::to_string(options_.validation_timeout.count()) + " ms");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void Dlpc350::StartPatternSequence() { WriteCommand(dlpc350::kPatternStartStop, {2}); }
void Dlpc350::PausePatternSequence() { WriteCommand(dlpc350::kPatternStartStop, {1}); }
void Dlpc350::StopPatternSequence() { WriteCommand(dlpc350::kPatternStartStop, {0}); }

Dlpc350Status Dlpc350::GetStatus() {
  Dlpc350Status status;
  status.hardware = ReadCommand(dlpc350::kHardwareStatus, 1)[0];
  status.system = ReadCommand(dlpc350::kSystemStatus, 1)[0];
  status.main = ReadCommand(dlpc350::kMainStatus, 1)[0];
  return status;
}

Dlpc350Version Dlpc350::GetVersion() {
  const auto data = ReadCommand(dlpc350::kGetVersion, 16);
  return {GetU32(data, 0), GetU32(data, 4), GetU32(data, 8), GetU32(data, 12)};
}

}  // namespace zbrdf
