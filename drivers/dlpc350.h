// USB control of DLPC350-class projectors (TI DLP LightCrafter 4500, VID 0x0451 PID 0x6401).
//
// The DLPC350 takes commands as 64-byte HID reports on interrupt endpoints 0x01 (OUT) and 0x81
// (IN). Every message starts with a 4-byte header (TI DLPU010, "USB command format"):
//   byte 0  flags: bit 7 read (1) / write (0), bit 6 reply wanted, bit 5 NACK (set by the
//           controller in a reply when it rejected the command), bits 0-2 destination (0)
//   byte 1  sequence number, echoed in the reply so that a reply can be matched to its command
//   byte 2-3 length, little endian: number of bytes after the header
// A command then carries CMD3 (byte 4) and CMD2 (byte 5) (the 16-bit code CMD2<<8|CMD3 stored
// little endian) and its payload, so length = payload + 2. A reply carries the header and the
// read data (length = data bytes; a write acknowledge has length 0). Messages longer than one
// report continue in further 64-byte reports without a header.
//
// This driver numbers every command (reads too), asks for a reply to every write, discards
// replies with another sequence number (late answers to an earlier command), retries a command
// whose reply did not come within the timeout, and turns a NACK into a DeviceError that names
// the command. The transport is an interface so the protocol is tested byte for byte against an
// in-process emulator (drivers/dlpc350_emulator.h) and the real libusb path under umockdev
// (drivers/dlpc350_usb.h).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace zbrdf {

using Dlpc350Report = std::array<uint8_t, 64>;

// One HID endpoint pair. Implementations: LibusbDlpc350Transport, Dlpc350Emulator.
class Dlpc350Transport {
 public:
  virtual ~Dlpc350Transport() = default;
  // "DLPC350 USB 001/005 (0451:6401)": the prefix of error messages.
  virtual std::string Name() const = 0;
  // Sends one report on the OUT endpoint. Throws DeviceError on failure or timeout.
  virtual void Write(const Dlpc350Report& report, std::chrono::milliseconds timeout) = 0;
  // Receives one report from the IN endpoint; false if none arrived within the timeout.
  // Throws DeviceError on failure.
  virtual bool Read(Dlpc350Report* report, std::chrono::milliseconds timeout) = 0;
};

// Command codes, CMD2 << 8 | CMD3 (DLPC350 Programmer's Guide, TI DLPU010).
namespace dlpc350 {
constexpr uint16_t kPowerControl = 0x0200;        // 1 byte: 0 normal, 1 standby
constexpr uint16_t kGetVersion = 0x0205;          // read 16 bytes: app, API, SW config, seq config
constexpr uint16_t kLedCurrent = 0x0B01;          // 3 bytes: red, green, blue PWM (0-255)
constexpr uint16_t kInputSource = 0x1A00;         // 1 byte: source | port width << 3
constexpr uint16_t kLedEnable = 0x1A07;           // 1 byte: b0 red, b1 green, b2 blue, b3 sequencer
constexpr uint16_t kHardwareStatus = 0x1A0A;      // read 1 byte
constexpr uint16_t kSystemStatus = 0x1A0B;        // read 1 byte
constexpr uint16_t kMainStatus = 0x1A0C;          // read 1 byte
constexpr uint16_t kLutValidate = 0x1A1A;         // write 1 byte (0) starts; read: status
constexpr uint16_t kDisplayMode = 0x1A1B;         // 1 byte: 0 video, 1 pattern sequence
constexpr uint16_t kTrigOut1 = 0x1A1D;            // 3 bytes: invert, rising delay, falling delay
constexpr uint16_t kTrigOut2 = 0x1A1E;            // 2 bytes: invert, rising delay
constexpr uint16_t kPatternSource = 0x1A22;       // 1 byte: 0 video port, 3 flash
constexpr uint16_t kPatternTriggerMode = 0x1A23;  // 1 byte: 0 VSYNC, 1 internal/external, ...
constexpr uint16_t kPatternStartStop = 0x1A24;    // 1 byte: 0 stop, 1 pause, 2 start
constexpr uint16_t kPatternExposure = 0x1A29;     // 8 bytes: exposure us, period us (LE uint32)
constexpr uint16_t kPatternConfig = 0x1A31;   // 4 bytes: entries-1, repeat, trig2 pats-1, imgs-1
constexpr uint16_t kMailboxAddress = 0x1A32;  // 1 byte: offset in the open mailbox
constexpr uint16_t kMailboxControl = 0x1A33;  // 1 byte: 0 close, 1 image LUT, 2 pattern LUT
constexpr uint16_t kMailboxData = 0x1A34;     // n bytes: LUT entries
}  // namespace dlpc350

// The command's name for messages, e.g. "LED_CURRENT (0x0B01)".
std::string Dlpc350CommandName(uint16_t command);

// ---- Framing (exposed for tests; Dlpc350 uses these) ----

// The reports of a write command with `payload` (one report unless payload > 58 bytes).
std::vector<Dlpc350Report> EncodeDlpc350Write(uint8_t sequence, uint16_t command,
                                              const std::vector<uint8_t>& payload,
                                              bool reply_wanted = true);
// The report of a read command (reply wanted); `parameter` is sent after the command code.
Dlpc350Report EncodeDlpc350Read(uint8_t sequence, uint16_t command,
                                const std::vector<uint8_t>& parameter = {});

struct Dlpc350Reply {
  bool nack = false;
  uint8_t sequence = 0;
  std::vector<uint8_t> data;  // `length` bytes after the header (at most 60)
};
Dlpc350Reply DecodeDlpc350Reply(const Dlpc350Report& report);

// ---- Typed commands ----

enum class Dlpc350DisplayMode { kVideo = 0, kPatternSequence = 1 };
enum class Dlpc350InputSource { kParallel = 0, kTestPattern = 1, kFlash = 2, kFpdLink = 3 };
// Parallel port width: 0 = 30 bit, 1 = 24 bit, 2 = 20 bit, 3 = 16 bit, 4 = 10 bit, 5 = 8 bit.
enum class Dlpc350PortWidth { k30 = 0, k24 = 1, k20 = 2, k16 = 3, k10 = 4, k8 = 5 };

struct Dlpc350LedEnables {
  bool sequencer_controls = true;  // the sequencer drives the LED enables (video mode default)
  bool red = true, green = true, blue = true;
};

struct Dlpc350LedCurrents {
  uint8_t red = 0, green = 0, blue = 0;  // PWM duty 0-255
};

// TRIG_OUT delays: each step is 107.2 ns; 0xBB = 0 us, 0x00 = -20.05 us, 0xD5 = +2.787 us.
struct Dlpc350TriggerOut {
  bool invert = false;
  uint8_t rising_delay = 0xBB;
  uint8_t falling_delay = 0xBB;  // TRIG_OUT_1 only
};

struct Dlpc350Status {
  uint8_t hardware = 0, system = 0, main = 0;
  // Programmer's guide, "DLPC350 Status Commands".
  bool InitializationDone() const { return hardware & 0x01; }
  bool ControllerDmdIncompatible() const { return hardware & 0x02; }
  bool DmdResetControllerError() const { return hardware & 0x04; }
  bool ForcedSwapError() const { return hardware & 0x08; }
  bool SequencerAbort() const { return hardware & 0x40; }
  bool SequencerError() const { return hardware & 0x80; }
  bool MemoryTestPassed() const { return system & 0x01; }
  bool DmdParked() const { return main & 0x01; }
  bool SequencerRunning() const { return main & 0x02; }
  bool VideoFrozen() const { return main & 0x04; }
  // Empty when healthy, else a list of the problems ("sequencer error; DMD parked").
  std::string Problems() const;
};

struct Dlpc350Version {
  uint32_t application = 0, api = 0, software_config = 0, sequence_config = 0;
  // "major.minor.patch" of the application firmware.
  std::string ApplicationString() const;
};

// One pattern LUT entry (programmer's guide, "Pattern Display LUT Definition").
struct Dlpc350PatternEntry {
  uint8_t trigger_type = 0;    // 0 internal, 1 external positive, 2 external negative, 3 none
  uint8_t pattern_number = 0;  // 0-63 (bit planes of the selected bit depth)
  uint8_t bit_depth = 8;       // 1-8
  uint8_t leds = 7;            // b0 red, b1 green, b2 blue
  bool invert = false;
  bool insert_black = false;
  bool buffer_swap = false;
  bool trigger_out_previous = false;
  uint32_t Encode() const;  // the 24-bit LUT word
};

struct Dlpc350ValidationResult {
  uint8_t status = 0;  // bits 0-4 as below
  bool ExposureOrPeriodInvalid() const { return status & 0x01; }
  bool PatternNumberInvalid() const { return status & 0x02; }
  bool TriggerOut1Overlap() const { return status & 0x04; }
  bool PostVectorMissing() const { return status & 0x08; }
  bool PeriodExposureDifferenceTooSmall() const { return status & 0x10; }
  bool Valid() const { return (status & 0x1F) == 0; }
  std::string Problems() const;
};

struct Dlpc350Options {
  std::chrono::milliseconds reply_timeout{500};
  int retries = 1;  // re-sends of a command whose reply timed out
  // Validation runs in the controller; poll its busy bit at most this long.
  std::chrono::milliseconds validation_timeout{3000};
};

class Dlpc350 {
 public:
  explicit Dlpc350(std::unique_ptr<Dlpc350Transport> transport, Dlpc350Options options = {});

  std::string Name() const { return transport_->Name(); }

  void SetStandby(bool standby);
  bool IsStandby();
  void SetDisplayMode(Dlpc350DisplayMode mode);
  Dlpc350DisplayMode GetDisplayMode();
  void SetInputSource(Dlpc350InputSource source, Dlpc350PortWidth width);
  void GetInputSource(Dlpc350InputSource* source, Dlpc350PortWidth* width);
  void SetLedEnables(const Dlpc350LedEnables& enables);
  Dlpc350LedEnables GetLedEnables();
  void SetLedCurrents(const Dlpc350LedCurrents& currents);
  Dlpc350LedCurrents GetLedCurrents();
  void SetTriggerOut1(const Dlpc350TriggerOut& config);
  Dlpc350TriggerOut GetTriggerOut1();
  void SetTriggerOut2(const Dlpc350TriggerOut& config);
  Dlpc350TriggerOut GetTriggerOut2();
  // Pattern display data from the video port (true: HDMI/parallel) or from flash (false).
  void SetPatternSourceVideoPort(bool video_port);
  void SetPatternTriggerMode(uint8_t mode);
  void SetPatternExposure(uint32_t exposure_us, uint32_t period_us);
  void GetPatternExposure(uint32_t* exposure_us, uint32_t* period_us);
  void SetPatternConfig(int lut_entries, bool repeat, int patterns_per_trigger_out2,
                        int image_entries);
  // Opens the pattern mailbox, writes the entries from offset 0, closes it (at most 128).
  void SendPatternLut(const std::vector<Dlpc350PatternEntry>& entries);
  // Starts validation and polls until the controller is done; throws DeviceError on timeout.
  Dlpc350ValidationResult ValidatePatternSequence();
  void StartPatternSequence();
  void PausePatternSequence();
  void StopPatternSequence();
  Dlpc350Status GetStatus();
  Dlpc350Version GetVersion();

  // Raw access (used by the typed commands above).
  void WriteCommand(uint16_t command, const std::vector<uint8_t>& payload);
  std::vector<uint8_t> ReadCommand(uint16_t command, size_t expected_bytes,
                                   const std::vector<uint8_t>& parameter = {});
  uint8_t next_sequence() const { return sequence_; }

 private:
  Dlpc350Reply Exchange(uint16_t command, const std::vector<Dlpc350Report>& reports,
                        const std::string& what);

  std::unique_ptr<Dlpc350Transport> transport_;
  Dlpc350Options options_;
  uint8_t sequence_ = 0;
};

}  // namespace zbrdf
