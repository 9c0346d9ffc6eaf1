// An in-process model of a DLPC350 controller behind the Dlpc350Transport interface.
//
// It parses the reports the host writes (drivers/dlpc350.h framing), keeps the controller's
// state (power, display mode, input source, LEDs, trigger outputs, pattern exposure, pattern
// config and LUT, validation, sequence start/stop, status registers, firmware version), answers
// reads, acknowledges writes that want a reply, and NACKs what the real controller rejects:
// unknown commands, payloads of the wrong length, out-of-range values, starting a pattern
// sequence that was not validated, changing the display mode or pattern setup while a sequence
// runs. Tests inspect every report in both directions through the shared State and can inject
// faults (dropped replies, forced NACKs, stale replies).
//
// Read() returns false at once when no reply is queued: replies are produced synchronously by
// Write(), so waiting out the timeout could not change the answer.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "drivers/dlpc350.h"

namespace zbrdf {

class Dlpc350Emulator final : public Dlpc350Transport {
 public:
  struct State {
    // Controller state.
    bool standby = false;
    uint8_t display_mode = 0;     // 0 video, 1 pattern
    uint8_t input_source = 0x08;  // parallel, 24 bit
    uint8_t led_enable = 0x0F;
    std::vector<uint8_t> led_currents = {0x97, 0x78, 0x7D};
    std::vector<uint8_t> trig_out1 = {0, 0xBB, 0xBB};
    std::vector<uint8_t> trig_out2 = {0, 0xBB};
    uint8_t pattern_source = 0;
    uint8_t pattern_trigger_mode = 1;
    uint8_t pattern_state = 0;  // 0 stopped, 1 paused, 2 running
    uint32_t pattern_exposure_us = 16666, pattern_period_us = 16666;
    std::vector<uint8_t> pattern_config = {0, 1, 0, 0};
    std::vector<uint32_t> pattern_lut;
    uint8_t mailbox = 0;
    uint8_t mailbox_address = 0;
    bool validated = false;
    int validation_polls_left = 0;
    uint8_t validation_status = 0;
    uint8_t hardware_status = 0x01;  // initialization done
    uint8_t system_status = 0x01;    // memory test passed
    std::vector<uint8_t> version = {0x03, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x02,
                                    0x01, 0x00, 0x00, 0x01, 0x02, 0x00, 0x00, 0x01};

    // Test hooks.
    int validation_busy_polls = 2;    // LUT_VALID reads reporting busy before the result
    int drop_replies = 0;             // drop this many of the next replies
    bool send_stale_reply = false;    // before the next reply, resend the previous one once
    std::set<uint16_t> forced_nacks;  // always NACK these commands

    // Traffic, in order.
    std::vector<Dlpc350Report> from_host;
    std::vector<Dlpc350Report> to_host;
    std::deque<Dlpc350Report> queue;
  };

  Dlpc350Emulator() : state_(std::make_shared<State>()) {}
  explicit Dlpc350Emulator(std::shared_ptr<State> state) : state_(std::move(state)) {}

  std::shared_ptr<State> state() const { return state_; }

  std::string Name() const override { return "DLPC350 emulator"; }
  void Write(const Dlpc350Report& report, std::chrono::milliseconds timeout) override;
  bool Read(Dlpc350Report* report, std::chrono::milliseconds timeout) override;

 private:
  void Handle(const std::vector<uint8_t>& message);
  // Returns false (NACK) if the write is invalid.
  bool ApplyWrite(uint16_t command, const std::vector<uint8_t>& payload);
  // Returns false (NACK) if the command cannot be read.
  bool ReadValue(uint16_t command, std::vector<uint8_t>* data);
  void Reply(uint8_t flags, uint8_t sequence, const std::vector<uint8_t>& data);

  std::shared_ptr<State> state_;
  std::vector<uint8_t> partial_;  // a multi-report message being assembled
  size_t partial_expected_ = 0;
  Dlpc350Report last_reply_{};
  bool have_last_reply_ = false;
};

}  // namespace zbrdf
