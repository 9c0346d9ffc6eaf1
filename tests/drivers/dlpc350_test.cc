// DLPC350 protocol tests against the in-process emulator. Every expected report is written out
// byte by byte from the framing in drivers/dlpc350.h (flags, sequence, length LE = payload + 2,
// CMD3, CMD2, payload) and the command table of the DLPC350 Programmer's Guide.
#include "drivers/dlpc350.h"

#include <gtest/gtest.h>

#include <functional>

#include "basis/error.h"
#include "drivers/dlpc350_emulator.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

Dlpc350Report R(std::initializer_list<uint8_t> bytes) {
  Dlpc350Report r{};
  size_t i = 0;
  for (uint8_t b : bytes) r[i++] = b;
  return r;
}

struct Fixture {
  std::shared_ptr<Dlpc350Emulator::State> state = std::make_shared<Dlpc350Emulator::State>();
  Dlpc350 dlpc{std::make_unique<Dlpc350Emulator>(state)};
};

struct ByteCase {
  const char* name;
  std::function<void(Dlpc350&)> call;
  std::vector<Dlpc350Report> host;   // what the driver must send
  std::vector<Dlpc350Report> reply;  // what the emulator must answer
};

TEST(Dlpc350Test, EveryCommandIsByteExactBothWays) {
  const std::vector<ByteCase> cases = {
      {"SetStandby(true)", [](Dlpc350& d) { d.SetStandby(true); },
       {R({0x40, 0x00, 0x03, 0x00, 0x00, 0x02, 0x01})}, {R({0x40, 0x00, 0x00, 0x00})}},
      {"IsStandby", [](Dlpc350& d) { EXPECT_FALSE(d.IsStandby()); },
       {R({0xC0, 0x00, 0x02, 0x00, 0x00, 0x02})}, {R({0xC0, 0x00, 0x01, 0x00, 0x00})}},
      {"SetDisplayMode(pattern)",
       [](Dlpc350& d) { d.SetDisplayMode(Dlpc350DisplayMode::kPatternSequence); },
       {R({0x40, 0x00, 0x03, 0x00, 0x1B, 0x1A, 0x01})}, {R({0x40, 0x00, 0x00, 0x00})}},
      {"GetDisplayMode",
       [](Dlpc350& d) { EXPECT_EQ(d.GetDisplayMode(), Dlpc350DisplayMode::kVideo); },
       {R({0xC0, 0x00, 0x02, 0x00, 0x1B, 0x1A})}, {R({0xC0, 0x00, 0x01, 0x00, 0x00})}},
      {"SetInputSource(parallel, 24 bit)",
       [](Dlpc350& d) {
         d.SetInputSource(Dlpc350InputSource::kParallel, Dlpc350PortWidth::k24);
       },
       {R({0x40, 0x00, 0x03, 0x00, 0x00, 0x1A, 0x08})}, {R({0x40, 0x00, 0x00, 0x00})}},
      {"GetInputSource",
       [](Dlpc350& d) {
         Dlpc350InputSource source;
         Dlpc350PortWidth width;
         d.GetInputSource(&source, &width);
         EXPECT_EQ(source, Dlpc350InputSource::kParallel);
         EXPECT_EQ(width, Dlpc350PortWidth::k24);
       },
       {R({0xC0, 0x00, 0x02, 0x00, 0x00, 0x1A})}, {R({0xC0, 0x00, 0x01, 0x00, 0x08})}},
      {"SetLedEnables(R, B, manual)",
       [](Dlpc350& d) { d.SetLedEnables({false, true, false, true}); },
       {R({0x40, 0x00, 0x03, 0x00, 0x07, 0x1A, 0x05})}, {R({0x40, 0x00, 0x00, 0x00})}},
      {"GetLedEnables",
       [](Dlpc350& d) {
         const auto e = d.GetLedEnables();
         EXPECT_TRUE(e.sequencer_controls && e.red && e.green && e.blue);
       },
       {R({0xC0, 0x00, 0x02, 0x00, 0x07, 0x1A})}, {R({0xC0, 0x00, 0x01, 0x00, 0x0F})}},
      {"SetLedCurrents(0x10, 0x20, 0x30)",
       [](Dlpc350& d) { d.SetLedCurrents({0x10, 0x20, 0x30}); },
       {R({0x40, 0x00, 0x05, 0x00, 0x01, 0x0B, 0x10, 0x20, 0x30})},
       {R({0x40, 0x00, 0x00, 0x00})}},
      {"GetLedCurrents",
       [](Dlpc350& d) {
         const auto c = d.GetLedCurrents();
         EXPECT_EQ(c.red, 0x97);
         EXPECT_EQ(c.green, 0x78);
         EXPECT_EQ(c.blue, 0x7D);
       },
       {R({0xC0, 0x00, 0x02, 0x00, 0x01, 0x0B})}, {R({0xC0, 0x00, 0x03, 0x00, 0x97, 0x78, 0x7D})}},
      {"SetTriggerOut1(inverted, 0xBB, 0xC0)",
       [](Dlpc350& d) { d.SetTriggerOut1({true, 0xBB, 0xC0}); },
       {R({0x40, 0x00, 0x05, 0x00, 0x1D, 0x1A, 0x01, 0xBB, 0xC0})},
       {R({0x40, 0x00, 0x00, 0x00})}},
      {"GetTriggerOut1",
       [](Dlpc350& d) {
         const auto t = d.GetTriggerOut1();
         EXPECT_FALSE(t.invert);
         EXPECT_EQ(t.rising_delay, 0xBB);
       },
       {R({0xC0, 0x00, 0x02, 0x00, 0x1D, 0x1A})}, {R({0xC0, 0x00, 0x03, 0x00, 0x00, 0xBB, 0xBB})}},
      {"SetTriggerOut2(normal, 0xD5)",
       [](Dlpc350& d) { d.SetTriggerOut2({false, 0xD5, 0}); },
       {R({0x40, 0x00, 0x04, 0x00, 0x1E, 0x1A, 0x00, 0xD5})}, {R({0x40, 0x00, 0x00, 0x00})}},
      {"GetTriggerOut2", [](Dlpc350& d) { EXPECT_EQ(d.GetTriggerOut2().rising_delay, 0xBB); },
       {R({0xC0, 0x00, 0x02, 0x00, 0x1E, 0x1A})}, {R({0xC0, 0x00, 0x02, 0x00, 0x00, 0xBB})}},
      {"SetPatternSourceVideoPort(false)",
       [](Dlpc350& d) { d.SetPatternSourceVideoPort(false); },
       {R({0x40, 0x00, 0x03, 0x00, 0x22, 0x1A, 0x03})}, {R({0x40, 0x00, 0x00, 0x00})}},
      {"SetPatternTriggerMode(0)", [](Dlpc350& d) { d.SetPatternTriggerMode(0); },
       {R({0x40, 0x00, 0x03, 0x00, 0x23, 0x1A, 0x00})}, {R({0x40, 0x00, 0x00, 0x00})}},
      {"SetPatternExposure(10000, 20000)",
       [](Dlpc350& d) { d.SetPatternExposure(10000, 20000); },
       {R({0x40, 0x00, 0x0A, 0x00, 0x29, 0x1A, 0x10, 0x27, 0x00, 0x00, 0x20, 0x4E, 0x00, 0x00})},
       {R({0x40, 0x00, 0x00, 0x00})}},
      {"GetPatternExposure",
       [](Dlpc350& d) {
         uint32_t exposure = 0, period = 0;
         d.GetPatternExposure(&exposure, &period);
         EXPECT_EQ(exposure, 16666u);
         EXPECT_EQ(period, 16666u);
       },
       {R({0xC0, 0x00, 0x02, 0x00, 0x29, 0x1A})},
       {R({0xC0, 0x00, 0x08, 0x00, 0x1A, 0x41, 0x00, 0x00, 0x1A, 0x41, 0x00, 0x00})}},
      {"SetPatternConfig(3 entries, repeat, 3 per TRIG_OUT_2, 1 image)",
       [](Dlpc350& d) { d.SetPatternConfig(3, true, 3, 1); },
       {R({0x40, 0x00, 0x06, 0x00, 0x31, 0x1A, 0x02, 0x01, 0x02, 0x00})},
       {R({0x40, 0x00, 0x00, 0x00})}},
      {"StopPatternSequence", [](Dlpc350& d) { d.StopPatternSequence(); },
       {R({0x40, 0x00, 0x03, 0x00, 0x24, 0x1A, 0x00})}, {R({0x40, 0x00, 0x00, 0x00})}},
      {"PausePatternSequence", [](Dlpc350& d) { d.PausePatternSequence(); },
       {R({0x40, 0x00, 0x03, 0x00, 0x24, 0x1A, 0x01})}, {R({0x40, 0x00, 0x00, 0x00})}},
      {"GetStatus",
       [](Dlpc350& d) {
         const auto s = d.GetStatus();
         EXPECT_TRUE(s.InitializationDone());
         EXPECT_TRUE(s.MemoryTestPassed());
         EXPECT_FALSE(s.SequencerRunning());
         EXPECT_EQ(s.Problems(), "");
       },
       {R({0xC0, 0x00, 0x02, 0x00, 0x0A, 0x1A}), R({0xC0, 0x01, 0x02, 0x00, 0x0B, 0x1A}),
        R({0xC0, 0x02, 0x02, 0x00, 0x0C, 0x1A})},
       {R({0xC0, 0x00, 0x01, 0x00, 0x01}), R({0xC0, 0x01, 0x01, 0x00, 0x01}),
        R({0xC0, 0x02, 0x01, 0x00, 0x00})}},
      {"GetVersion",
       [](Dlpc350& d) {
         const auto v = d.GetVersion();
         EXPECT_EQ(v.application, 0x03000003u);
         EXPECT_EQ(v.ApplicationString(), "3.0.3");
         EXPECT_EQ(v.sequence_config, 0x01000002u);
       },
       {R({0xC0, 0x00, 0x02, 0x00, 0x05, 0x02})},
       {R({0xC0, 0x00, 0x10, 0x00, 0x03, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x02, 0x01, 0x00,
           0x00, 0x01, 0x02, 0x00, 0x00, 0x01})}},
      {"SendPatternLut(2 entries)",
       [](Dlpc350& d) {
         Dlpc350PatternEntry first;  // internal trigger, pattern 0, 8 bit, white
         Dlpc350PatternEntry second;
         second.trigger_type = 3;
         second.pattern_number = 2;
         second.buffer_swap = true;
         d.SendPatternLut({first, second});
       },
       // word = trigger | number << 2 | depth << 8 | leds << 12 | swap << 18:
       // 0x007800 and 0x04780B, three bytes little endian each.
       {R({0x40, 0x00, 0x03, 0x00, 0x33, 0x1A, 0x02}), R({0x40, 0x01, 0x03, 0x00, 0x32, 0x1A, 0x00}),
        R({0x40, 0x02, 0x08, 0x00, 0x34, 0x1A, 0x00, 0x78, 0x00, 0x0B, 0x78, 0x04}),
        R({0x40, 0x03, 0x03, 0x00, 0x33, 0x1A, 0x00})},
       {R({0x40, 0x00, 0x00, 0x00}), R({0x40, 0x01, 0x00, 0x00}), R({0x40, 0x02, 0x00, 0x00}),
        R({0x40, 0x03, 0x00, 0x00})}},
  };
  for (const auto& c : cases) {
    Fixture f;
    c.call(f.dlpc);
    EXPECT_EQ(f.state->from_host, c.host) << c.name;
    EXPECT_EQ(f.state->to_host, c.reply) << c.name;
  }
}

TEST(Dlpc350Test, EncodersFollowTheHeaderLayout) {
  const auto write = EncodeDlpc350Write(0x7F, dlpc350::kLedCurrent, {1, 2, 3}, false);
  ASSERT_EQ(write.size(), 1u);
  EXPECT_EQ(write[0], R({0x00, 0x7F, 0x05, 0x00, 0x01, 0x0B, 1, 2, 3}));  // no reply wanted
  EXPECT_EQ(EncodeDlpc350Read(9, dlpc350::kMainStatus, {0xAA}),
            R({0xC0, 0x09, 0x03, 0x00, 0x0C, 0x1A, 0xAA}));
  const Dlpc350Reply nack = DecodeDlpc350Reply(R({0x60, 0x05, 0x00, 0x00}));
  EXPECT_TRUE(nack.nack);
  EXPECT_EQ(nack.sequence, 5);
  const Dlpc350Reply data = DecodeDlpc350Reply(R({0xC0, 0x06, 0x02, 0x00, 0x12, 0x34, 0x56}));
  EXPECT_FALSE(data.nack);
  EXPECT_EQ(data.data, (std::vector<uint8_t>{0x12, 0x34}));
}

TEST(Dlpc350Test, SequenceNumbersIncrementForEveryCommandAndWrap) {
  Fixture f;
  for (int i = 0; i < 300; ++i) f.dlpc.SetLedCurrents({1, 2, 3});
  ASSERT_EQ(f.state->from_host.size(), 300u);
  for (int i = 0; i < 300; ++i) {
    EXPECT_EQ(f.state->from_host[i][1], static_cast<uint8_t>(i % 256));
    EXPECT_EQ(f.state->to_host[i][1], static_cast<uint8_t>(i % 256));
  }
  EXPECT_EQ(f.dlpc.next_sequence(), static_cast<uint8_t>(300 % 256));
}

TEST(Dlpc350Test, NackBecomesADeviceErrorNamingTheCommand) {
  Fixture f;
  f.state->forced_nacks.insert(dlpc350::kLedCurrent);
  try {
    f.dlpc.SetLedCurrents({1, 2, 3});
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("DLPC350 emulator"), std::string::npos) << message;
    EXPECT_NE(message.find("LED_CURRENT (0x0B01)"), std::string::npos) << message;
    EXPECT_NE(message.find("NACK"), std::string::npos) << message;
  }
  // The NACK reply carries the NACK flag (bit 5) and the command's sequence number.
  EXPECT_EQ(f.state->to_host.back(), R({0x60, 0x00, 0x00, 0x00}));
}

TEST(Dlpc350Test, InvalidCommandsAreNacked) {
  Fixture f;
  EXPECT_THROW(f.dlpc.WriteCommand(0x1234, {0}), DeviceError);                   // unknown command
  EXPECT_THROW(f.dlpc.WriteCommand(dlpc350::kLedCurrent, {1, 2}), DeviceError);  // short payload
  EXPECT_THROW(f.dlpc.WriteCommand(dlpc350::kPowerControl, {2}), DeviceError);   // out of range
  EXPECT_THROW(f.dlpc.ReadCommand(dlpc350::kMailboxData, 1), DeviceError);       // not readable
  EXPECT_THROW(f.dlpc.StartPatternSequence(), DeviceError);   // video mode, not validated
  EXPECT_THROW(f.dlpc.SetPatternTriggerMode(7), InputError);  // caught before sending
  EXPECT_EQ(f.state->from_host.size(), 5u);
}

TEST(Dlpc350Test, ALostReplyIsRetriedWithTheSameSequenceNumber) {
  Fixture f;
  f.state->drop_replies = 1;
  f.dlpc.SetLedCurrents({4, 5, 6});
  ASSERT_EQ(f.state->from_host.size(), 2u);
  EXPECT_EQ(f.state->from_host[0], f.state->from_host[1]);
  EXPECT_EQ(f.state->led_currents, (std::vector<uint8_t>{4, 5, 6}));
}

TEST(Dlpc350Test, RepeatedTimeoutsThrowNamingTheCommand) {
  auto state = std::make_shared<Dlpc350Emulator::State>();
  Dlpc350Options options;
  options.retries = 2;
  options.reply_timeout = std::chrono::milliseconds(20);
  Dlpc350 dlpc(std::make_unique<Dlpc350Emulator>(state), options);
  state->drop_replies = 3;
  try {
    dlpc.GetStatus();
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("no reply to STATUS_HW (0x1A0A)"), std::string::npos) << message;
    EXPECT_NE(message.find("3 attempts"), std::string::npos) << message;
  }
  EXPECT_EQ(state->from_host.size(), 3u);
}

TEST(Dlpc350Test, StaleRepliesWithAnotherSequenceNumberAreDiscarded) {
  Fixture f;
  f.dlpc.SetLedCurrents({7, 8, 9});
  f.state->send_stale_reply = true;  // the next answer is preceded by the previous one again
  const auto currents = f.dlpc.GetLedCurrents();
  EXPECT_EQ(currents.red, 7);
  EXPECT_EQ(currents.blue, 9);
  ASSERT_EQ(f.state->to_host.size(), 3u);
  EXPECT_EQ(f.state->to_host[1], R({0x40, 0x00, 0x00, 0x00}));  // the stale write ack, seq 0
  EXPECT_EQ(f.state->to_host[2], R({0xC0, 0x01, 0x03, 0x00, 7, 8, 9}));
}

TEST(Dlpc350Test, LongMessagesContinueInHeaderlessReports) {
  Fixture f;
  std::vector<Dlpc350PatternEntry> entries(30);
  for (size_t i = 0; i < entries.size(); ++i) {
    entries[i].bit_depth = 1;
    entries[i].pattern_number = static_cast<uint8_t>(i % 24);
  }
  f.dlpc.SendPatternLut(entries);
  // MBOX_CONTROL, MBOX_ADDRESS, MBOX_DATA in two reports (4 + 2 + 90 bytes), MBOX_CONTROL.
  ASSERT_EQ(f.state->from_host.size(), 5u);
  const Dlpc350Report& first = f.state->from_host[2];
  EXPECT_EQ(first[0], 0x40);
  EXPECT_EQ(first[2], 92);  // 90 payload bytes + the 2 command bytes
  EXPECT_EQ(first[3], 0);
  EXPECT_EQ(first[4], 0x34);
  EXPECT_EQ(first[5], 0x1A);
  const Dlpc350Report& second = f.state->from_host[3];
  // Entry 19 occupies payload bytes 57-59, i.e. message bytes 63-65: its first byte ends the
  // first report, the other two open the second one.
  const uint32_t word19 = entries[19].Encode();
  EXPECT_EQ(first[63], static_cast<uint8_t>(word19));
  EXPECT_EQ(second[0], static_cast<uint8_t>(word19 >> 8));
  EXPECT_EQ(second[1], static_cast<uint8_t>(word19 >> 16));
  ASSERT_EQ(f.state->pattern_lut.size(), 30u);
  for (size_t i = 0; i < entries.size(); ++i)
    EXPECT_EQ(f.state->pattern_lut[i], entries[i].Encode());
}

TEST(Dlpc350Test, PatternSequenceSetupValidatesStartsAndStops) {
  Fixture f;
  Dlpc350& d = f.dlpc;
  d.SetDisplayMode(Dlpc350DisplayMode::kPatternSequence);
  d.SetPatternSourceVideoPort(true);
  d.SetPatternTriggerMode(0);
  d.SetPatternExposure(8000, 8333);
  Dlpc350PatternEntry entry;
  entry.pattern_number = 1;
  d.SendPatternLut({entry, entry});
  d.SetPatternConfig(2, true, 2, 1);
  const Dlpc350ValidationResult result = d.ValidatePatternSequence();
  EXPECT_TRUE(result.Valid()) << result.Problems();
  d.StartPatternSequence();
  EXPECT_TRUE(d.GetStatus().SequencerRunning());
  // The setup may not change while the sequence runs.
  EXPECT_THROW(d.SetPatternExposure(4000, 8333), DeviceError);
  d.StopPatternSequence();
  EXPECT_FALSE(d.GetStatus().SequencerRunning());
  // An exposure 100 us shorter than the period violates the 230 us rule: validation says so and
  // the controller refuses to start.
  d.SetPatternExposure(8233, 8333);
  const Dlpc350ValidationResult bad = d.ValidatePatternSequence();
  EXPECT_TRUE(bad.PeriodExposureDifferenceTooSmall());
  EXPECT_FALSE(bad.Valid());
  EXPECT_THROW(d.StartPatternSequence(), DeviceError);
  // The validation polls read "busy" (bit 7) before the result.
  const auto& replies = f.state->to_host;
  int busy = 0;
  for (const auto& r : replies) busy += (r[0] == 0xC0 && r[2] == 1 && r[4] == 0x80) ? 1 : 0;
  EXPECT_EQ(busy, 2 * f.state->validation_busy_polls);
}

TEST(Dlpc350Test, StatusProblemsAreSpelledOut) {
  Dlpc350Status status;
  status.hardware = 0x80 | 0x01;
  status.system = 0x01;
  status.main = 0x01;
  EXPECT_EQ(status.Problems(), "sequencer error; DMD parked (projector in standby?)");
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
