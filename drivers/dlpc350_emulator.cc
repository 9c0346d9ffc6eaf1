#include "drivers/dlpc350_emulator.h"

#include <algorithm>

namespace zbrdf {

namespace {

constexpr uint8_t kEmulatedFlagRead = 0x80;
constexpr uint8_t kEmulatedFlagReply = 0x40;
constexpr uint8_t kEmulatedFlagNack = 0x20;

uint32_t U32(const std::vector<uint8_t>& p, size_t at) {
  return static_cast<uint32_t>(p[at]) | static_cast<uint32_t>(p[at + 1]) << 8 |
         static_cast<uint32_t>(p[at + 2]) << 16 | static_cast<uint32_t>(p[at + 3]) << 24;
}

void AppendU32(std::vector<uint8_t>* out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<uint8_t>(v >> (8 * i)));
}

// Payload length of each writable command; absent: not writable.
const std::map<uint16_t, size_t>& WriteLengths() {
  static const std::map<uint16_t, size_t> lengths = {
      {dlpc350::kPowerControl, 1},     {dlpc350::kLedCurrent, 3},
      {dlpc350::kInputSource, 1},      {dlpc350::kLedEnable, 1},
      {dlpc350::kLutValidate, 1},      {dlpc350::kDisplayMode, 1},
      {dlpc350::kTrigOut1, 3},         {dlpc350::kTrigOut2, 2},
      {dlpc350::kPatternSource, 1},    {dlpc350::kPatternTriggerMode, 1},
      {dlpc350::kPatternStartStop, 1}, {dlpc350::kPatternExposure, 8},
      {dlpc350::kPatternConfig, 4},    {dlpc350::kMailboxAddress, 1},
      {dlpc350::kMailboxControl, 1},
  };
  return lengths;
}

// Settings that must not change while a sequence runs, and that need re-validation.
bool IsPatternSetup(uint16_t command) {
  return command == dlpc350::kDisplayMode || command == dlpc350::kTrigOut1 ||
         command == dlpc350::kTrigOut2 || command == dlpc350::kPatternSource ||
         command == dlpc350::kPatternTriggerMode || command == dlpc350::kPatternExposure ||
         command == dlpc350::kPatternConfig || command == dlpc350::kMailboxData;
}

}  // namespace

void Dlpc350Emulator::Write(const Dlpc350Report& report, std::chrono::milliseconds) {
  State& s = *state_;
  s.from_host.push_back(report);
  if (partial_expected_ > 0) {  // continuation of a long message: raw bytes
    for (uint8_t byte : report) {
      if (partial_.size() < partial_expected_) partial_.push_back(byte);
    }
  } else {
    const size_t length = static_cast<size_t>(report[2]) | static_cast<size_t>(report[3]) << 8;
    partial_expected_ = 4 + length;
    partial_.assign(report.begin(), report.begin() + std::min<size_t>(64, partial_expected_));
  }
  if (partial_.size() >= partial_expected_) {
    std::vector<uint8_t> message;
    message.swap(partial_);
    partial_expected_ = 0;
    Handle(message);
  }
}

bool Dlpc350Emulator::Read(Dlpc350Report* report, std::chrono::milliseconds) {
  State& s = *state_;
  if (s.queue.empty()) return false;
  *report = s.queue.front();
  s.queue.pop_front();
  return true;
}

void Dlpc350Emulator::Reply(uint8_t flags, uint8_t sequence, const std::vector<uint8_t>& data) {
  State& s = *state_;
  Dlpc350Report report{};
  report[0] = flags;
  report[1] = sequence;
  report[2] = static_cast<uint8_t>(data.size());
  report[3] = static_cast<uint8_t>(data.size() >> 8);
  for (size_t i = 0; i < data.size() && i < 60; ++i) report[4 + i] = data[i];
  if (s.send_stale_reply && have_last_reply_) {
    s.send_stale_reply = false;
    s.to_host.push_back(last_reply_);
    s.queue.push_back(last_reply_);
  }
  last_reply_ = report;
  have_last_reply_ = true;
  if (s.drop_replies > 0) {
    --s.drop_replies;
    return;
  }
  s.to_host.push_back(report);
  s.queue.push_back(report);
}

void Dlpc350Emulator::Handle(const std::vector<uint8_t>& message) {
  State& s = *state_;
  if (message.size() < 6) return;  // too short to carry a command: the controller ignores it
  const uint8_t flags = message[0];
  const uint8_t sequence = message[1];
  const bool read = (flags & kEmulatedFlagRead) != 0;
  const bool reply_wanted = (flags & kEmulatedFlagReply) != 0;
  const uint16_t command = static_cast<uint16_t>(message[4] | message[5] << 8);
  const std::vector<uint8_t> payload(message.begin() + 6, message.end());
  const bool forced_nack = s.forced_nacks.count(command) > 0;
  if (read) {
    std::vector<uint8_t> data;
    const bool ok = !forced_nack && ReadValue(command, &data);
    Reply(
        static_cast<uint8_t>(kEmulatedFlagRead | kEmulatedFlagReply | (ok ? 0 : kEmulatedFlagNack)),
        sequence, ok ? data : std::vector<uint8_t>{});
    return;
  }
  const bool ok = !forced_nack && ApplyWrite(command, payload);
  if (reply_wanted || !ok) {
    Reply(static_cast<uint8_t>(kEmulatedFlagReply | (ok ? 0 : kEmulatedFlagNack)), sequence, {});
  }
}

bool Dlpc350Emulator::ApplyWrite(uint16_t command, const std::vector<uint8_t>& p) {
  State& s = *state_;
  if (command == dlpc350::kMailboxData) {
    // Pattern LUT entries, 3 bytes each, from the mailbox offset.
    if (s.mailbox != 2 || p.empty() || p.size() % 3 != 0) return false;
    if (s.pattern_state == 2) return false;
    const size_t first = s.mailbox_address;
    const size_t n = p.size() / 3;
    if (first + n > 128) return false;
    if (s.pattern_lut.size() < first + n) s.pattern_lut.resize(first + n);
    for (size_t i = 0; i < n; ++i) {
      s.pattern_lut[first + i] = static_cast<uint32_t>(p[3 * i]) |
                                 static_cast<uint32_t>(p[3 * i + 1]) << 8 |
                                 static_cast<uint32_t>(p[3 * i + 2]) << 16;
    }
    s.validated = false;
    return true;
  }
  const auto length = WriteLengths().find(command);
  if (length == WriteLengths().end() || p.size() != length->second) return false;
  if (IsPatternSetup(command) && s.pattern_state == 2) return false;
  switch (command) {
    case dlpc350::kPowerControl:
      if (p[0] > 1) return false;
      s.standby = p[0] == 1;
      return true;
    case dlpc350::kLedCurrent:
      s.led_currents = p;
      return true;
    case dlpc350::kInputSource:
      if ((p[0] & 0x07) > 3 || (p[0] >> 3) > 5) return false;
      s.input_source = p[0];
      return true;
    case dlpc350::kLedEnable:
      if (p[0] > 0x0F) return false;
      s.led_enable = p[0];
      return true;
    case dlpc350::kLutValidate:
      s.validation_polls_left = s.validation_busy_polls;
      {
        // Programmer's guide, LUT_VALID status bits.
        uint8_t status = 0;
        if (s.pattern_exposure_us == 0 || s.pattern_exposure_us > s.pattern_period_us) {
          status |= 0x01;
        } else if (s.pattern_exposure_us != s.pattern_period_us &&
                   s.pattern_period_us - s.pattern_exposure_us < 230) {
          status |= 0x10;
        }
        const size_t entries = static_cast<size_t>(s.pattern_config[0]) + 1;
        if (s.pattern_lut.size() < entries) status |= 0x02;
        for (size_t i = 0; i < entries && i < s.pattern_lut.size(); ++i) {
          const uint32_t word = s.pattern_lut[i];
          const uint32_t number = (word >> 2) & 0x3F, depth = (word >> 8) & 0xF;
          if (depth < 1 || depth > 8 || number >= 24 / depth) status |= 0x02;
        }
        s.validation_status = status;
        s.validated = (status & 0x1F) == 0;
      }
      return true;
    case dlpc350::kDisplayMode:
      if (p[0] > 1) return false;
      s.display_mode = p[0];
      s.validated = false;
      return true;
    case dlpc350::kTrigOut1:
      if (p[0] > 1) return false;
      s.trig_out1 = p;
      s.validated = false;
      return true;
    case dlpc350::kTrigOut2:
      if (p[0] > 1) return false;
      s.trig_out2 = p;
      s.validated = false;
      return true;
    case dlpc350::kPatternSource:
      if (p[0] != 0 && p[0] != 3) return false;
      s.pattern_source = p[0];
      s.validated = false;
      return true;
    case dlpc350::kPatternTriggerMode:
      if (p[0] > 4) return false;
      s.pattern_trigger_mode = p[0];
      s.validated = false;
      return true;
    case dlpc350::kPatternStartStop:
      if (p[0] > 2) return false;
      // Starting needs pattern mode and a validated sequence; the guide requires validation
      // after every change of the pattern setup.
      if (p[0] == 2 && (s.display_mode != 1 || !s.validated || s.standby)) return false;
      s.pattern_state = p[0];
      return true;
    case dlpc350::kPatternExposure:
      s.pattern_exposure_us = U32(p, 0);
      s.pattern_period_us = U32(p, 4);
      s.validated = false;
      return true;
    case dlpc350::kPatternConfig:
      if (p[1] > 1 || p[3] > 63) return false;
      s.pattern_config = p;
      s.validated = false;
      return true;
    case dlpc350::kMailboxAddress:
      if (p[0] > 127) return false;
      s.mailbox_address = p[0];
      return true;
    case dlpc350::kMailboxControl:
      if (p[0] > 3) return false;
      s.mailbox = p[0];
      if (p[0] != 0) s.mailbox_address = 0;
      return true;
    default:
      return false;
  }
}

bool Dlpc350Emulator::ReadValue(uint16_t command, std::vector<uint8_t>* d) {
  State& s = *state_;
  switch (command) {
    case dlpc350::kPowerControl:
      *d = {static_cast<uint8_t>(s.standby ? 1 : 0)};
      return true;
    case dlpc350::kGetVersion:
      *d = s.version;
      return true;
    case dlpc350::kLedCurrent:
      *d = s.led_currents;
      return true;
    case dlpc350::kInputSource:
      *d = {s.input_source};
      return true;
    case dlpc350::kLedEnable:
      *d = {s.led_enable};
      return true;
    case dlpc350::kHardwareStatus:
      *d = {s.hardware_status};
      return true;
    case dlpc350::kSystemStatus:
      *d = {s.system_status};
      return true;
    case dlpc350::kMainStatus:
      // b0 DMD parked (in standby), b1 sequencer running.
      *d = {static_cast<uint8_t>((s.standby ? 0x01 : 0) | (s.pattern_state == 2 ? 0x02 : 0))};
      return true;
    case dlpc350::kLutValidate:
      if (s.validation_polls_left > 0) {
        --s.validation_polls_left;
        *d = {0x80};  // busy
      } else {
        *d = {s.validation_status};
      }
      return true;
    case dlpc350::kDisplayMode:
      *d = {s.display_mode};
      return true;
    case dlpc350::kTrigOut1:
      *d = s.trig_out1;
      return true;
    case dlpc350::kTrigOut2:
      *d = s.trig_out2;
      return true;
    case dlpc350::kPatternSource:
      *d = {s.pattern_source};
      return true;
    case dlpc350::kPatternTriggerMode:
      *d = {s.pattern_trigger_mode};
      return true;
    case dlpc350::kPatternStartStop:
      *d = {s.pattern_state};
      return true;
    case dlpc350::kPatternExposure:
      d->clear();
      AppendU32(d, s.pattern_exposure_us);
      AppendU32(d, s.pattern_period_us);
      return true;
    case dlpc350::kPatternConfig:
      *d = s.pattern_config;
      return true;
    default:
      return false;
  }
}

}  // namespace zbrdf
