#include "drivers/fake_gige_camera.h"

#include <arv.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "drivers/pixel_format.h"

namespace zbrdf {

namespace {

constexpr const char* kExtraFormats[] = {"Mono12",    "Mono12Packed",    "Mono12p",
                                         "BayerRG12", "BayerRG12Packed", "BayerRG12p",
                                         "BayerRG16", "BayerGB16",       "BGR8"};

// The fake's GenICam XML with more PixelFormat entries. The fake computes payload sizes from the
// format code's bits-per-pixel field, so any PFNC code works on the wire.
std::string ExtendedGenicamXml(const std::string& serial) {
  ArvFakeCamera* probe = arv_fake_camera_new(serial.c_str());
  size_t size = 0;
  const char* xml = arv_fake_camera_get_genicam_xml(probe, &size);
  std::string text(xml != nullptr ? xml : "", xml != nullptr ? size : 0);
  g_object_unref(probe);
  const std::string anchor = "<pValue>PixelFormatRegister</pValue>";
  const size_t enumeration = text.find("<Enumeration Name=\"PixelFormat\"");
  const size_t at = text.find(anchor, enumeration);
  if (enumeration == std::string::npos || at == std::string::npos) {
    throw DeviceError(
        "the Aravis fake camera's GenICam description has no PixelFormat "
        "enumeration; cannot add 12/16-bit formats (Aravis version changed?)");
  }
  std::string entries;
  for (const char* name : kExtraFormats) {
    if (text.find(std::string("<EnumEntry Name=\"") + name + "\"") != std::string::npos) continue;
    const PixelFormatInfo* format = FindPixelFormat(name);
    entries += std::string("<EnumEntry Name=\"") + name + "\" NameSpace=\"Standard\"><Value>" +
               std::to_string(format->pfnc) + "</Value></EnumEntry>\n\t\t";
  }
  text.insert(at, entries);
  return text;
}

}  // namespace

struct FakeGigECamera::State {
  FakeGigECameraOptions options;
  ArvGvFakeCamera* gv = nullptr;
  mutable std::mutex mutex;
  FakeFrameSource source;
  uint64_t filled = 0;
  std::string last_error;

  static void Fill(ArvBuffer* buffer, void* data, guint32 exposure_us, guint32 gain,
                   ArvPixelFormat pixel_format) {
    auto* self = static_cast<State*>(data);
    std::lock_guard<std::mutex> lock(self->mutex);
    FakeFrameRequest request;
    request.index = self->filled++;
    request.width = arv_buffer_get_image_width(buffer);
    request.height = arv_buffer_get_image_height(buffer);
    request.exposure_us = exposure_us;
    request.gain_raw = static_cast<int>(gain);
    const PixelFormatInfo* format = FindPixelFormat(pixel_format);
    // arv_buffer_get_data's size is the received size, 0 while the fake fills the buffer; the
    // allocation is the fake's payload, width * height * bits-per-pixel / 8.
    auto* bytes = static_cast<uint8_t*>(const_cast<void*>(arv_buffer_get_data(buffer, nullptr)));
    const size_t allocated = static_cast<size_t>(request.width) *
                             static_cast<size_t>(request.height) *
                             ARV_PIXEL_FORMAT_BIT_PER_PIXEL(pixel_format) / 8;
    try {
      if (format == nullptr) throw InputError("pixel format code is not one zbrdf can pack");
      request.pixel_format = format->name;
      request.layout = format->layout;
      request.bit_depth = format->bit_depth;
      if (PayloadBytes(*format, request.width, request.height) > allocated) {
        throw InputError("an odd pixel count does not fit a packed 12-bit payload");
      }
      std::vector<uint16_t> samples;
      self->source(request, &samples);
      PackPixels(*format, samples, request.width, request.height, bytes);
    } catch (const std::exception& e) {
      self->last_error = "frame " + std::to_string(request.index) + ": " + e.what();
      std::fill(bytes, bytes + allocated, uint8_t{0});
    } catch (...) {
      self->last_error = "frame " + std::to_string(request.index) + ": unknown exception";
      std::fill(bytes, bytes + allocated, uint8_t{0});
    }
  }
};

void FakeGigECameraOptions::Validate() const {
  OptionChecker check("FakeGigECameraOptions");
  check.Require(!serial.empty(), "serial", "must not be empty")
      .InRangeAbove("trigger_rate_hz", trigger_rate_hz, 0, 1e6)
      .ThrowIfInvalid();
}

FakeGigECamera::FakeGigECamera(const FakeGigECameraOptions& options)
    : state_(std::make_unique<State>()) {
  options.Validate();
  state_->options = options;
  std::string xml_path;
  if (options.extra_pixel_formats) {
    static std::atomic<int> counter{0};
    xml_path =
        (std::filesystem::temp_directory_path() / ("zbrdf-fake-camera-" + std::to_string(getpid()) +
                                                   "-" + std::to_string(counter++) + ".xml"))
            .string();
    WriteFileAtomically(xml_path, ExtendedGenicamXml(options.serial));
  }
  state_->gv = arv_gv_fake_camera_new_full(kAddress, options.serial.c_str(),
                                           xml_path.empty() ? nullptr : xml_path.c_str());
  if (!xml_path.empty()) std::filesystem::remove(xml_path);  // read at construction
  if (state_->gv == nullptr || !arv_gv_fake_camera_is_running(state_->gv)) {
    Stop();
    throw DeviceError(std::string("cannot start the fake GigE Vision camera on ") + kAddress +
                      ":3956; is another one (e.g. arv-fake-gv-camera-0.8) already running?");
  }
  ArvFakeCamera* fake = arv_gv_fake_camera_get_fake_camera(state_->gv);
  arv_fake_camera_set_trigger_frequency(fake, options.trigger_rate_hz);
}

FakeGigECamera::~FakeGigECamera() { Stop(); }

void FakeGigECamera::SetFrameSource(FakeFrameSource source) {
  if (state_->gv == nullptr) throw DeviceError("the fake camera was stopped");
  ArvFakeCamera* fake = arv_gv_fake_camera_get_fake_camera(state_->gv);
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->source = std::move(source);
  }
  if (state_->source) {
    arv_fake_camera_set_fill_pattern(fake, &State::Fill, state_.get());
  } else {
    arv_fake_camera_set_fill_pattern(fake, nullptr, nullptr);
  }
}

void FakeGigECamera::SetLostPacketRatio(double ratio, uint32_t seed) {
  if (!(ratio >= 0 && ratio <= 1)) throw InputError("lost packet ratio must be in [0, 1]");
  if (state_->gv == nullptr) throw DeviceError("the fake camera was stopped");
  // The fake draws its drops from GLib's global generator (g_random_double per packet).
  g_random_set_seed(seed);
  g_object_set(state_->gv, "gvsp-lost-ratio", ratio, nullptr);
}

void FakeGigECamera::Stop() {
  if (state_->gv != nullptr) {
    g_object_unref(state_->gv);  // joins the fake's thread and closes its sockets
    state_->gv = nullptr;
  }
}

uint32_t FakeGigECamera::ReadRegister(uint32_t address) const {
  if (state_->gv == nullptr) throw DeviceError("the fake camera was stopped");
  guint32 value = 0;
  arv_fake_camera_read_register(arv_gv_fake_camera_get_fake_camera(state_->gv), address, &value);
  return value;
}

void FakeGigECamera::WriteRegister(uint32_t address, uint32_t value) {
  if (state_->gv == nullptr) throw DeviceError("the fake camera was stopped");
  arv_fake_camera_write_register(arv_gv_fake_camera_get_fake_camera(state_->gv), address, value);
}

std::string FakeGigECamera::Serial() const { return state_->options.serial; }

uint64_t FakeGigECamera::FramesFilled() const {
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->filled;
}

std::string FakeGigECamera::LastSourceError() const {
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->last_error;
}

}  // namespace zbrdf
