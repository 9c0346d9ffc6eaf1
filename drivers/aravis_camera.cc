#include "drivers/aravis_camera.h"

#include <arpa/inet.h>
#include <arv.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/option_checker.h"

namespace zbrdf {

namespace {

struct GObjectUnref {
  void operator()(gpointer object) const {
    if (object != nullptr) g_object_unref(object);
  }
};
template <class T>
using GPtr = std::unique_ptr<T, GObjectUnref>;

struct GInetAddressPtr {
  GInetAddress* address = nullptr;
  ~GInetAddressPtr() {
    if (address != nullptr) g_object_unref(address);
  }
};

// Returns the GError's message and frees it.
std::string TakeMessage(GError*& error) {
  std::string message = error != nullptr ? error->message : "unknown error";
  g_clear_error(&error);
  return message;
}

bool IsTimeout(const GError* error) {
  if (error == nullptr) return false;
  if (g_error_matches(error, ARV_DEVICE_ERROR, ARV_DEVICE_ERROR_TIMEOUT)) return true;
  return std::strstr(error->message, "timeout") != nullptr;
}

// Copies and frees a NULL-free array of n strings returned by arv_camera_dup_*_as_strings.
std::vector<std::string> TakeStrings(const char** strings, guint n) {
  std::vector<std::string> out;
  if (strings == nullptr) return out;
  for (guint i = 0; i < n; ++i) out.emplace_back(strings[i] != nullptr ? strings[i] : "");
  g_free(strings);
  return out;
}

std::string Join(const std::vector<std::string>& items, const std::string& separator = ", ") {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += separator;
    out += items[i];
  }
  return out;
}

std::string FormatNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

int64_t RealTimeUs() { return g_get_real_time(); }

}  // namespace

std::string LocalInterfaceFor(const std::string& remote_ip) {
  in_addr remote{};
  if (inet_pton(AF_INET, remote_ip.c_str(), &remote) != 1) {
    throw InputError("'" + remote_ip + "' is not an IPv4 address (use a dotted quad such as " +
                     "192.0.2.10)");
  }
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) throw DeviceError(std::string("cannot create a UDP socket: ") + strerror(errno));
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(3956);  // GVCP; connect() on UDP only selects a route, nothing is sent
  to.sin_addr = remote;
  sockaddr_in local{};
  socklen_t length = sizeof(local);
  const bool ok = connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof(to)) == 0 &&
                  getsockname(fd, reinterpret_cast<sockaddr*>(&local), &length) == 0;
  const int saved_errno = errno;
  close(fd);
  if (!ok) {
    throw DeviceError("no network route to camera " + remote_ip + ": " + strerror(saved_errno) +
                      " (check the interface configuration, or set camera.interface_ip)");
  }
  char text[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &local.sin_addr, text, sizeof(text));
  return text;
}

// ---------------------------------------------------------------------------------------------

struct AravisCamera::Impl {
  AravisCameraOptions options;
  Clock* clock = nullptr;
  SteadyClock own_clock;

  std::string address;
  std::string id;
  std::string description;
  std::string vendor, model, serial;

  GPtr<ArvDevice> device;
  GPtr<ArvCamera> camera;
  GPtr<ArvStream> stream;
  gulong control_lost_handler = 0;
  std::atomic<bool> control_lost{false};
  bool lost = false;  // a command timed out: the camera stopped answering
  bool acquiring = false;

  const PixelFormatInfo* format = nullptr;
  int width = 0, height = 0;
  size_t payload = 0;

  std::string exposure_feature;
  double camera_exposure_min_us = 0, camera_exposure_max_us = 0;
  double exposure_us = 0;
  std::string gain_feature;
  std::string gain_unit = "none";
  double gain = 0;

  TriggerMode trigger_mode = TriggerMode::kSoftware;
  AravisCameraStats stats;

  ~Impl() {
    if (camera && acquiring && !lost) {
      GError* error = nullptr;
      arv_camera_stop_acquisition(camera.get(), &error);
      g_clear_error(&error);
    }
    if (device && control_lost_handler != 0) {
      g_signal_handler_disconnect(device.get(), control_lost_handler);
    }
    stream.reset();  // stops the stream thread, frees the buffer pool
    camera.reset();
    device.reset();  // releases the control channel
  }

  [[noreturn]] void Fail(const std::string& what) const {
    throw DeviceError(description + ": " + what);
  }

  // Throws DeviceError naming the feature if `error` is set.
  void Check(GError*& error, const std::string& feature, const std::string& action) {
    if (error == nullptr) return;
    if (IsTimeout(error)) lost = true;
    const std::string message = TakeMessage(error);
    Fail(feature + ": " + action + " failed (" + message + ")" +
         (lost ? "; the camera stopped answering: check its power and network link, then "
                 "reopen it"
               : ""));
  }

  bool Available(const char* feature) {
    GError* error = nullptr;
    const gboolean available = arv_camera_is_feature_available(camera.get(), feature, &error);
    if (error != nullptr) {
      g_clear_error(&error);
      return false;
    }
    return available != FALSE;
  }

  std::vector<std::string> EnumEntries(const char* feature) {
    GError* error = nullptr;
    guint n = 0;
    const char** entries =
        arv_camera_dup_available_enumerations_as_strings(camera.get(), feature, &n, &error);
    Check(error, feature, "listing the entries");
    return TakeStrings(entries, n);
  }

  void SetEnum(const char* feature, const std::string& value) {
    GError* error = nullptr;
    arv_camera_set_string(camera.get(), feature, value.c_str(), &error);
    Check(error, feature, "setting it to '" + value + "'");
  }

  // Sets an enumeration to `value` if the feature exists and offers it; returns whether it did.
  bool SetEnumIfOffered(const char* feature, const std::string& value) {
    if (!Available(feature)) return false;
    const auto entries = EnumEntries(feature);
    if (std::find(entries.begin(), entries.end(), value) == entries.end()) return false;
    SetEnum(feature, value);
    return true;
  }

  void Open();
  void SelectPixelFormat();
  void ApplyRegion();
  void SetupExposureAndGain();
  void ApplyTrigger(TriggerMode mode);
  void CreateStream();
  void StartAcquisition();
  void StopAcquisition();
  void DrainQueue();
  double SetExposure(double value_us);
  double SetGain(double value);
  Frame ToFrame(ArvBuffer* buffer, int64_t exposure_start_us);
  Frame Grab(std::chrono::milliseconds timeout);
};

void AravisCamera::Impl::Open() {
  if (options.ip.empty()) {
    const std::string path =
        options.camera_directory.empty() ? DefaultCameraDirectoryPath() : options.camera_directory;
    for (const auto& entry : ReadCameraDirectory(path)) {
      if (entry.serial == options.serial) address = entry.ip;
    }
    if (address.empty()) {
      throw InputError("camera serial '" + options.serial + "' is not in the camera directory " +
                       path + "; run `zbrdf devices --save` once (it broadcasts on every network " +
                       "interface to find cameras), or give camera.ip instead");
    }
    id = options.serial;
  } else {
    address = options.ip;
    id = options.ip;
  }
  if (!IsIpv4Address(address)) {
    throw InputError("camera address '" + address + "' is not an IPv4 address");
  }
  description = "camera " + address;
  const std::string interface_ip =
      options.interface_ip.empty() ? LocalInterfaceFor(address) : options.interface_ip;
  if (!IsIpv4Address(interface_ip)) {
    throw InputError("camera interface address '" + interface_ip + "' is not an IPv4 address");
  }

  GInetAddressPtr interface_address{g_inet_address_new_from_string(interface_ip.c_str())};
  GInetAddressPtr device_address{g_inet_address_new_from_string(address.c_str())};
  GError* error = nullptr;
  // Unicast GVCP to this one address: no discovery broadcast.
  device.reset(arv_gv_device_new(interface_address.address, device_address.address, &error));
  if (error != nullptr || !device) {
    const std::string message = TakeMessage(error);
    throw DeviceError(description + ": no GigE Vision camera answers at this address via " +
                      "interface " + interface_ip + " (" + message + "); check the address, " +
                      "the cabling and that camera and interface share a subnet");
  }
  if (!arv_gv_device_is_controller(ARV_GV_DEVICE(device.get()))) {
    throw DeviceError(description + ": another application controls this camera (an Aravis " +
                      "viewer, another zbrdf?); close it and try again");
  }
  camera.reset(arv_camera_new_with_device(device.get(), &error));
  if (error != nullptr || !camera) {
    const std::string message = TakeMessage(error);
    throw DeviceError(description + ": cannot read its GenICam description (" + message + ")");
  }
  auto text = [&](const char* value) { return std::string(value != nullptr ? value : ""); };
  vendor = text(arv_camera_get_vendor_name(camera.get(), &error));
  g_clear_error(&error);
  model = text(arv_camera_get_model_name(camera.get(), &error));
  g_clear_error(&error);
  serial = text(arv_camera_get_device_serial_number(camera.get(), &error));
  g_clear_error(&error);
  description = "camera " + address + " (" + vendor + " " + model + ", serial " + serial + ")";
  if (!options.serial.empty() && options.serial != serial) {
    throw InputError(description + ": the rig file expects serial '" + options.serial +
                     "'; another camera answers at this address (fix camera.ip or " +
                     "camera.serial)");
  }

  control_lost_handler =
      g_signal_connect(device.get(), "control-lost", G_CALLBACK(+[](ArvGvDevice*, gpointer data) {
                         static_cast<Impl*>(data)->control_lost.store(true);
                       }),
                       this);

  SelectPixelFormat();
  ApplyRegion();
  // Automatic exposure, gain and white balance would change the radiometry between frames.
  SetEnumIfOffered("ExposureAuto", "Off");
  SetEnumIfOffered("GainAuto", "Off");
  SetEnumIfOffered("BalanceWhiteAuto", "Off");
  SetupExposureAndGain();
  if (Available("AcquisitionMode")) SetEnum("AcquisitionMode", "Continuous");
  ApplyTrigger(options.trigger_mode);
  if (options.packet_size > 0) {
    arv_camera_gv_set_packet_size(camera.get(), options.packet_size, &error);
    Check(error, "GevSCPSPacketSize", "setting it to " + std::to_string(options.packet_size));
  }
  CreateStream();
}

void AravisCamera::Impl::SelectPixelFormat() {
  GError* error = nullptr;
  guint n = 0;
  const char** names = arv_camera_dup_available_pixel_formats_as_strings(camera.get(), &n, &error);
  Check(error, "PixelFormat", "listing the available formats");
  const std::vector<std::string> offered = TakeStrings(names, n);
  std::vector<std::string> usable;
  for (const auto& name : offered) {
    if (FindPixelFormat(name) != nullptr) usable.push_back(name);
  }
  if (options.pixel_format.empty()) {
    for (const auto& f : SupportedPixelFormats()) {
      if (std::find(offered.begin(), offered.end(), f.name) != offered.end()) {
        format = &f;
        break;
      }
    }
    if (format == nullptr) {
      throw InputError(description + ": PixelFormat: none of the formats it offers (" +
                       Join(offered) + ") is one zbrdf can unpack");
    }
  } else {
    if (std::find(offered.begin(), offered.end(), options.pixel_format) == offered.end()) {
      throw InputError(
          description + ": PixelFormat '" + options.pixel_format +
          "' is not offered; the camera offers " + Join(offered) +
          (usable.empty() ? std::string() : "; set camera.pixel_format to one of " + Join(usable)));
    }
    format = FindPixelFormat(options.pixel_format);
    if (format == nullptr) {
      throw InputError(description + ": PixelFormat '" + options.pixel_format +
                       "' cannot be unpacked by zbrdf; use one of " + Join(usable));
    }
  }
  arv_camera_set_pixel_format_from_string(camera.get(), format->name, &error);
  Check(error, "PixelFormat", std::string("setting it to ") + format->name);
  const ArvPixelFormat now = arv_camera_get_pixel_format(camera.get(), &error);
  Check(error, "PixelFormat", "reading it back");
  if (now != format->pfnc) {
    Fail(std::string("PixelFormat: set to ") + format->name + " but the camera reports 0x" + [&] {
      std::ostringstream hex;
      hex << std::hex << now;
      return hex.str();
    }());
  }
}

void AravisCamera::Impl::ApplyRegion() {
  GError* error = nullptr;
  if (options.region_width > 0 && options.region_height > 0) {
    arv_camera_set_region(camera.get(), options.region_x, options.region_y, options.region_width,
                          options.region_height, &error);
    Check(error, "Width/Height/OffsetX/OffsetY",
          "setting the region " + std::to_string(options.region_width) + "x" +
              std::to_string(options.region_height) + "+" + std::to_string(options.region_x) + "+" +
              std::to_string(options.region_y));
  }
  gint x = 0, y = 0;
  arv_camera_get_region(camera.get(), &x, &y, &width, &height, &error);
  Check(error, "Width/Height", "reading the region");
  if (options.region_width > 0 &&
      (width != options.region_width || height != options.region_height)) {
    Fail("Width/Height: asked for " + std::to_string(options.region_width) + "x" +
         std::to_string(options.region_height) + ", the camera uses " + std::to_string(width) +
         "x" + std::to_string(height) + " (check the camera's size increments)");
  }
}

void AravisCamera::Impl::SetupExposureAndGain() {
  GError* error = nullptr;
  if (Available("ExposureTime")) {
    exposure_feature = "ExposureTime";
  } else if (Available("ExposureTimeAbs")) {
    exposure_feature = "ExposureTimeAbs";
  } else {
    Fail(
        "neither ExposureTime nor ExposureTimeAbs is available; zbrdf needs a camera with "
        "manual exposure control");
  }
  arv_camera_get_float_bounds(camera.get(), exposure_feature.c_str(), &camera_exposure_min_us,
                              &camera_exposure_max_us, &error);
  Check(error, exposure_feature, "reading its bounds");
  if (options.exposure_min_us > options.exposure_max_us) {
    throw InputError(description + ": exposure limits [" + FormatNumber(options.exposure_min_us) +
                     ", " + FormatNumber(options.exposure_max_us) + "] us are empty");
  }
  if (options.exposure_us) {
    SetExposure(*options.exposure_us);
  } else {
    exposure_us = arv_camera_get_float(camera.get(), exposure_feature.c_str(), &error);
    Check(error, exposure_feature, "reading it");
  }

  if (Available("Gain")) {
    gain_feature = "Gain";
    gain_unit = "dB";
    gain = arv_camera_get_float(camera.get(), "Gain", &error);
  } else if (Available("GainRaw")) {
    gain_feature = "GainRaw";
    gain_unit = "raw";
    gain = static_cast<double>(arv_camera_get_integer(camera.get(), "GainRaw", &error));
  }
  if (!gain_feature.empty()) Check(error, gain_feature, "reading it");
  if (options.gain) SetGain(*options.gain);
}

double AravisCamera::Impl::SetExposure(double value_us) {
  const double lo = std::max(camera_exposure_min_us, options.exposure_min_us);
  const double hi = std::min(camera_exposure_max_us, options.exposure_max_us);
  if (!(value_us >= lo && value_us <= hi)) {
    Fail(exposure_feature + ": " + FormatNumber(value_us) + " us is outside the allowed range [" +
         FormatNumber(lo) + ", " + FormatNumber(hi) + "] us (camera [" +
         FormatNumber(camera_exposure_min_us) + ", " + FormatNumber(camera_exposure_max_us) +
         "], rig file [" + FormatNumber(options.exposure_min_us) + ", " +
         FormatNumber(options.exposure_max_us) + "])");
  }
  GError* error = nullptr;
  arv_camera_set_float(camera.get(), exposure_feature.c_str(), value_us, &error);
  Check(error, exposure_feature, "setting it to " + FormatNumber(value_us) + " us");
  exposure_us = arv_camera_get_float(camera.get(), exposure_feature.c_str(), &error);
  Check(error, exposure_feature, "reading it back");
  return exposure_us;
}

double AravisCamera::Impl::SetGain(double value) {
  if (gain_feature.empty()) Fail("Gain/GainRaw: the camera has no gain control");
  GError* error = nullptr;
  if (gain_feature == "Gain") {
    double lo = 0, hi = 0;
    arv_camera_get_float_bounds(camera.get(), "Gain", &lo, &hi, &error);
    Check(error, "Gain", "reading its bounds");
    if (!(value >= lo && value <= hi)) {
      Fail("Gain: " + FormatNumber(value) + " dB is outside [" + FormatNumber(lo) + ", " +
           FormatNumber(hi) + "] dB");
    }
    arv_camera_set_float(camera.get(), "Gain", value, &error);
    Check(error, "Gain", "setting it to " + FormatNumber(value) + " dB");
    gain = arv_camera_get_float(camera.get(), "Gain", &error);
  } else {
    gint64 lo = 0, hi = 0;
    arv_camera_get_integer_bounds(camera.get(), "GainRaw", &lo, &hi, &error);
    Check(error, "GainRaw", "reading its bounds");
    const double rounded = std::round(value);
    if (!(rounded >= static_cast<double>(lo) && rounded <= static_cast<double>(hi))) {
      Fail("GainRaw: " + FormatNumber(value) + " is outside [" + std::to_string(lo) + ", " +
           std::to_string(hi) + "]");
    }
    arv_camera_set_integer(camera.get(), "GainRaw", static_cast<gint64>(rounded), &error);
    Check(error, "GainRaw", "setting it to " + FormatNumber(rounded));
    gain = static_cast<double>(arv_camera_get_integer(camera.get(), "GainRaw", &error));
  }
  Check(error, gain_feature, "reading it back");
  return gain;
}

void AravisCamera::Impl::ApplyTrigger(TriggerMode mode) {
  const bool was_acquiring = acquiring;
  if (was_acquiring) StopAcquisition();
  SetEnumIfOffered("TriggerSelector", "FrameStart");
  if (!Available("TriggerMode") || !Available("TriggerSource")) {
    Fail("TriggerMode/TriggerSource: not available; zbrdf needs a triggerable camera");
  }
  SetEnum("TriggerMode", "On");
  const std::string source = mode == TriggerMode::kSoftware ? "Software" : options.trigger_line;
  const auto sources = EnumEntries("TriggerSource");
  if (std::find(sources.begin(), sources.end(), source) == sources.end()) {
    throw InputError(description + ": TriggerSource '" + source + "' is not offered; it offers " +
                     Join(sources) +
                     (mode == TriggerMode::kHardwareLine ? " (set camera.trigger_line)" : ""));
  }
  SetEnum("TriggerSource", source);
  if (mode == TriggerMode::kHardwareLine) SetEnumIfOffered("TriggerActivation", "RisingEdge");
  if (mode == TriggerMode::kSoftware && !Available("TriggerSoftware")) {
    Fail("TriggerSoftware: not available; use sync.mode: hardware");
  }
  trigger_mode = mode;
  if (was_acquiring) StartAcquisition();
}

void AravisCamera::Impl::CreateStream() {
  GError* error = nullptr;
  payload = arv_camera_get_payload(camera.get(), &error);
  Check(error, "PayloadSize", "reading it");
  if (payload < PayloadBytes(*format, width, height)) {
    Fail("PayloadSize " + std::to_string(payload) + " bytes is smaller than a " +
         std::to_string(width) + "x" + std::to_string(height) + " " + format->name + " image (" +
         std::to_string(PayloadBytes(*format, width, height)) + " bytes)");
  }
  stream.reset(arv_camera_create_stream(camera.get(), nullptr, nullptr, &error));
  if (error != nullptr || !stream) {
    const std::string message = TakeMessage(error);
    Fail("cannot create the GVSP stream (" + message + ")");
  }
  if (ARV_IS_GV_STREAM(stream.get())) {
    g_object_set(stream.get(), "packet-resend",
                 options.packet_resend ? ARV_GV_STREAM_PACKET_RESEND_ALWAYS
                                       : ARV_GV_STREAM_PACKET_RESEND_NEVER,
                 nullptr);
    if (options.frame_retention_us > 0) {
      g_object_set(stream.get(), "frame-retention", static_cast<guint>(options.frame_retention_us),
                   nullptr);
    }
    if (options.packet_timeout_us > 0) {
      g_object_set(stream.get(), "packet-timeout", static_cast<guint>(options.packet_timeout_us),
                   nullptr);
    }
  }
  for (int i = 0; i < std::max(1, options.buffers); ++i) {
    arv_stream_push_buffer(stream.get(), arv_buffer_new_allocate(payload));
  }
}

void AravisCamera::Impl::StartAcquisition() {
  GError* error = nullptr;
  arv_camera_start_acquisition(camera.get(), &error);
  Check(error, "AcquisitionStart", "executing it");
  acquiring = true;
}

void AravisCamera::Impl::StopAcquisition() {
  GError* error = nullptr;
  acquiring = false;
  arv_camera_stop_acquisition(camera.get(), &error);
  Check(error, "AcquisitionStop", "executing it");
}

void AravisCamera::Impl::DrainQueue() {
  while (ArvBuffer* buffer = arv_stream_try_pop_buffer(stream.get())) {
    arv_stream_push_buffer(stream.get(), buffer);
  }
}

Frame AravisCamera::Impl::ToFrame(ArvBuffer* buffer, int64_t exposure_start_us) {
  const ArvBufferPayloadType type = arv_buffer_get_payload_type(buffer);
  if (type != ARV_BUFFER_PAYLOAD_TYPE_IMAGE &&
      type != ARV_BUFFER_PAYLOAD_TYPE_EXTENDED_CHUNK_DATA &&
      type != ARV_BUFFER_PAYLOAD_TYPE_CHUNK_DATA) {
    Fail("received a non-image payload (type " + std::to_string(static_cast<int>(type)) + ")");
  }
  const ArvPixelFormat pixel_format = arv_buffer_get_image_pixel_format(buffer);
  if (pixel_format != format->pfnc) {
    Fail(std::string("PixelFormat: expected ") + format->name + " frames, received format 0x" +
         [&] {
           std::ostringstream hex;
           hex << std::hex << pixel_format;
           return hex.str();
         }());
  }
  Frame frame;
  frame.width = arv_buffer_get_image_width(buffer);
  frame.height = arv_buffer_get_image_height(buffer);
  frame.layout = format->layout;
  frame.bit_depth = format->bit_depth;
  size_t size = 0;
  const auto* data = static_cast<const uint8_t*>(arv_buffer_get_image_data(buffer, &size));
  try {
    UnpackPixels(*format, data, size, frame.width, frame.height, &frame.data);
  } catch (const DeviceError& e) {
    Fail(e.what());
  }
  frame.exposure_us = exposure_us;
  frame.gain = gain;
  frame.frame_id = arv_buffer_get_frame_id(buffer);
  frame.timestamp_us = exposure_start_us;
  return frame;
}

Frame AravisCamera::Impl::Grab(std::chrono::milliseconds timeout) {
  if (lost) Fail("the camera stopped answering earlier; reopen it");
  if (control_lost.load()) {
    lost = true;
    Fail(
        "the control channel was lost (heartbeat failed); check the network link and reopen "
        "the camera");
  }
  if (timeout.count() <= 0) throw InputError(description + ": Grab timeout must be > 0 ms");
  if (!acquiring) StartAcquisition();
  const guint64 timeout_us = static_cast<guint64>(timeout.count()) * 1000u;
  int incomplete = 0, timeouts = 0;
  std::string last_status;

  if (trigger_mode == TriggerMode::kSoftware) {
    for (int attempt = 0; attempt <= options.retries; ++attempt) {
      DrainQueue();  // a late frame from a previous attempt must not answer this trigger
      const int64_t trigger_us = clock->NowUs();
      GError* error = nullptr;
      arv_camera_software_trigger(camera.get(), &error);
      Check(error, "TriggerSoftware", "executing it");
      ArvBuffer* buffer = arv_stream_timeout_pop_buffer(stream.get(), timeout_us);
      if (buffer == nullptr) {
        ++timeouts;
        ++stats.timeouts;
        continue;
      }
      const ArvBufferStatus status = arv_buffer_get_status(buffer);
      if (status != ARV_BUFFER_STATUS_SUCCESS) {
        ++incomplete;
        ++stats.incomplete_frames;
        last_status = std::to_string(static_cast<int>(status));
        arv_stream_push_buffer(stream.get(), buffer);
        continue;
      }
      try {
        Frame frame = ToFrame(buffer, trigger_us);
        arv_stream_push_buffer(stream.get(), buffer);
        ++stats.frames;
        return frame;
      } catch (...) {
        arv_stream_push_buffer(stream.get(), buffer);
        throw;
      }
    }
    Fail("no complete frame after " + std::to_string(options.retries + 1) + " software triggers: " +
         std::to_string(incomplete) + " arrived with missing packets (ArvBufferStatus " +
         (last_status.empty() ? "-" : last_status) + "), " + std::to_string(timeouts) +
         " brought no frame within " + std::to_string(timeout.count()) +
         " ms; check the network (packet size, jumbo frames, cable), raise camera.timeout_ms "
         "or camera.retries");
  }

  // Hardware line trigger: frames arrive whenever the projector triggers. Drop what is queued
  // and every frame whose first packet arrived before this call plus one exposure time (it was
  // at least partly exposed before the call, i.e. possibly under the previous pattern).
  DrainQueue();
  const int64_t call_real_us = RealTimeUs();
  const int64_t call_clock_us = clock->NowUs();
  const int64_t earliest_real_us = call_real_us + static_cast<int64_t>(exposure_us);
  const auto deadline = std::chrono::steady_clock::now() + timeout * (options.retries + 1);
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::microseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    ArvBuffer* buffer =
        arv_stream_timeout_pop_buffer(stream.get(), static_cast<guint64>(left.count()));
    if (buffer == nullptr) break;
    const int64_t arrival_real_us =
        static_cast<int64_t>(arv_buffer_get_system_timestamp(buffer) / 1000u);
    if (arrival_real_us < earliest_real_us) {
      ++stats.stale_frames;
      arv_stream_push_buffer(stream.get(), buffer);
      continue;
    }
    if (arv_buffer_get_status(buffer) != ARV_BUFFER_STATUS_SUCCESS) {
      ++incomplete;
      ++stats.incomplete_frames;
      arv_stream_push_buffer(stream.get(), buffer);
      if (incomplete > options.retries) {
        Fail(std::to_string(incomplete) + " line-triggered frames in a row arrived with missing " +
             "packets; check the network (packet size, jumbo frames, cable)");
      }
      continue;
    }
    try {
      // Exposure start on the session clock: the first packet left the camera after the
      // exposure ended, so step back by the time since arrival and by the exposure time.
      const int64_t start_us =
          call_clock_us + (arrival_real_us - call_real_us) - static_cast<int64_t>(exposure_us);
      Frame frame = ToFrame(buffer, start_us);
      arv_stream_push_buffer(stream.get(), buffer);
      ++stats.frames;
      return frame;
    } catch (...) {
      arv_stream_push_buffer(stream.get(), buffer);
      throw;
    }
  }
  ++stats.timeouts;
  Fail("no frame triggered on " + options.trigger_line + " within " +
       std::to_string(timeout.count() * (options.retries + 1)) +
       " ms; check the trigger cable from the projector's trigger output, the projector's "
       "trigger configuration, and camera.trigger_line");
}

// ---------------------------------------------------------------------------------------------

void AravisCameraOptions::Validate() const {
  OptionChecker check("AravisCameraOptions");
  check.Require(!ip.empty() || !serial.empty(), "ip",
                "or serial must be given: the camera's IP address (camera.ip) or its serial "
                "number (camera.serial)")
      .AtLeast("exposure_min_us", exposure_min_us, 0)
      .Require(exposure_max_us >= exposure_min_us, "exposure_max_us",
               "must be >= exposure_min_us (got " + FormatOptionValue(exposure_max_us) + " < " +
                   FormatOptionValue(exposure_min_us) + ")");
  if (exposure_us) check.Positive("exposure_us", *exposure_us);
  if (gain) {
    check.Require(std::isfinite(*gain), "gain",
                  "must be finite (got " + FormatOptionValue(*gain) + ")");
  }
  check.AtLeast("region_x", region_x, 0)
      .AtLeast("region_y", region_y, 0)
      .AtLeast("region_width", region_width, 0)
      .AtLeast("region_height", region_height, 0)
      .InRange("retries", retries, 0, 100)
      .InRange("buffers", buffers, 1, 64)
      .Require(packet_size == 0 || (packet_size >= 576 && packet_size <= 16384), "packet_size",
               "must be 0 (the camera's value) or in [576, 16384] bytes (got " +
                   std::to_string(packet_size) + ")")
      .AtLeast("frame_retention_us", frame_retention_us, 0)
      .AtLeast("packet_timeout_us", packet_timeout_us, 0)
      .ThrowIfInvalid();
}

AravisCamera::AravisCamera(const AravisCameraOptions& options, Clock* clock)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->clock = clock != nullptr ? clock : &impl_->own_clock;
  options.Validate();
  impl_->Open();
}

AravisCamera::~AravisCamera() = default;

CameraInfo AravisCamera::Info() const {
  CameraInfo info;
  info.id = impl_->id;
  info.model = impl_->vendor + " " + impl_->model;
  info.width = impl_->width;
  info.height = impl_->height;
  info.layout = impl_->format->layout;
  info.bit_depth = impl_->format->bit_depth;
  info.min_exposure_us = std::max(impl_->camera_exposure_min_us, impl_->options.exposure_min_us);
  info.max_exposure_us = std::min(impl_->camera_exposure_max_us, impl_->options.exposure_max_us);
  info.gain_unit = impl_->gain_unit;
  return info;
}

double AravisCamera::SetExposure(double exposure_us) { return impl_->SetExposure(exposure_us); }

void AravisCamera::SetTriggerMode(TriggerMode mode) { impl_->ApplyTrigger(mode); }

Frame AravisCamera::Grab(std::chrono::milliseconds timeout) { return impl_->Grab(timeout); }

double AravisCamera::SetGain(double gain) { return impl_->SetGain(gain); }

std::string AravisCamera::PixelFormatName() const { return impl_->format->name; }

std::string AravisCamera::SerialNumber() const { return impl_->serial; }

AravisCameraStats AravisCamera::Stats() const { return impl_->stats; }

std::string AravisCamera::Describe() const { return impl_->description; }

// ---------------------------------------------------------------------------------------------

std::string DefaultCameraDirectoryPath() {
  const char* cache = std::getenv("XDG_CACHE_HOME");
  if (cache != nullptr && cache[0] != '\0') return std::string(cache) + "/zbrdf/cameras.yaml";
  const char* home = std::getenv("HOME");
  return std::string(home != nullptr ? home : ".") + "/.cache/zbrdf/cameras.yaml";
}

std::vector<CameraDirectoryEntry> ReadCameraDirectory(const std::string& path) {
  std::vector<CameraDirectoryEntry> entries;
  if (!std::filesystem::exists(path)) return entries;
  try {
    const YAML::Node root = YAML::LoadFile(path);
    const YAML::Node cameras = root["cameras"];
    if (!cameras) return entries;
    if (!cameras.IsSequence()) throw InputError("'cameras' must be a list");
    for (const auto& node : cameras) {
      CameraDirectoryEntry entry;
      entry.serial = node["serial"].as<std::string>("");
      entry.ip = node["ip"].as<std::string>("");
      entry.vendor = node["vendor"].as<std::string>("");
      entry.model = node["model"].as<std::string>("");
      if (!entry.serial.empty() && IsIpv4Address(entry.ip)) entries.push_back(entry);
    }
  } catch (const YAML::Exception& e) {
    throw InputError("camera directory " + path + ": " + e.what() +
                     " (delete it and run `zbrdf devices --save` again)");
  } catch (const InputError& e) {
    throw InputError("camera directory " + path + ": " + e.what());
  }
  return entries;
}

void WriteCameraDirectory(const std::string& path, const std::vector<CameraDirectoryEntry>& seen) {
  std::vector<CameraDirectoryEntry> merged = ReadCameraDirectory(path);
  for (const auto& entry : seen) {
    auto it = std::find_if(merged.begin(), merged.end(),
                           [&](const CameraDirectoryEntry& e) { return e.serial == entry.serial; });
    if (it != merged.end()) {
      *it = entry;
    } else {
      merged.push_back(entry);
    }
  }
  YAML::Emitter out;
  out << YAML::Comment("Cameras seen by `zbrdf devices --save` (serial -> IP address).");
  out << YAML::BeginMap << YAML::Key << "cameras" << YAML::Value << YAML::BeginSeq;
  for (const auto& e : merged) {
    out << YAML::BeginMap << YAML::Key << "serial" << YAML::Value << e.serial << YAML::Key << "ip"
        << YAML::Value << e.ip << YAML::Key << "vendor" << YAML::Value << e.vendor << YAML::Key
        << "model" << YAML::Value << e.model << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  WriteFileAtomically(path, std::string(out.c_str()) + "\n");
}

std::vector<DiscoveredCamera> DiscoverCamerasByBroadcast() {
  // The one place that enumerates devices: GVCP discovery broadcasts on every interface.
  arv_update_device_list();
  std::vector<DiscoveredCamera> cameras;
  const unsigned int n = arv_get_n_devices();
  auto text = [](const char* value) { return std::string(value != nullptr ? value : ""); };
  for (unsigned int i = 0; i < n; ++i) {
    DiscoveredCamera camera;
    camera.id = text(arv_get_device_id(i));
    camera.protocol = text(arv_get_device_protocol(i));
    camera.address = text(arv_get_device_address(i));
    camera.vendor = text(arv_get_device_vendor(i));
    camera.model = text(arv_get_device_model(i));
    camera.serial = text(arv_get_device_serial_nbr(i));
    cameras.push_back(camera);
  }
  return cameras;
}

}  // namespace zbrdf
