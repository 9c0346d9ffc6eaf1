#include "drivers/hardware_rig.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "basis/error.h"

namespace zbrdf {

namespace {

std::string FormatSetting(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// Reads typed fields and collects every problem, so one run reports them all.
class FieldReader {
 public:
  explicit FieldReader(std::vector<std::string>* problems) : problems_(problems) {}

  void Problem(const std::string& field, const std::string& text) {
    problems_->push_back(field + " " + text);
  }

  // Flags keys of `node` that are not in `known`.
  void CheckKeys(const YAML::Node& node, const std::string& path,
                 const std::set<std::string>& known) {
    if (!node.IsMap()) return;
    for (const auto& item : node) {
      const std::string key = item.first.as<std::string>("");
      if (!known.count(key)) {
        std::string list;
        for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
        Problem((path.empty() ? "" : path + ".") + key,
                "is not a known field (expected one of " + list + ")");
      }
    }
  }

  bool IsMap(const YAML::Node& node, const std::string& path) {
    if (!node) return false;
    if (!node.IsMap()) {
      Problem(path, "must be a mapping of fields");
      return false;
    }
    return true;
  }

  std::optional<std::string> Text(const YAML::Node& parent, const std::string& key,
                                  const std::string& path) {
    const YAML::Node node = parent[key];
    if (!node) return std::nullopt;
    if (!node.IsScalar()) {
      Problem(path, "must be a single value");
      return std::nullopt;
    }
    return node.as<std::string>();
  }

  std::optional<double> Real(const YAML::Node& parent, const std::string& key,
                             const std::string& path, double min, double max) {
    const auto text = Text(parent, key, path);
    if (!text) return std::nullopt;
    double value = 0;
    try {
      size_t used = 0;
      value = std::stod(*text, &used);
      if (used != text->size()) throw std::invalid_argument("trailing characters");
    } catch (const std::exception&) {
      Problem(path, "must be a number (got '" + *text + "')");
      return std::nullopt;
    }
    if (!(value >= min && value <= max)) {
      Problem(path, "must be in [" + FormatSetting(min) + ", " + FormatSetting(max) + "] (got " +
                        *text + ")");
      return std::nullopt;
    }
    return value;
  }

  std::optional<int> Integer(const YAML::Node& parent, const std::string& key,
                             const std::string& path, int min, int max) {
    const auto value = Real(parent, key, path, min, max);
    if (!value) return std::nullopt;
    if (std::floor(*value) != *value) {
      Problem(path, "must be a whole number (got " + FormatSetting(*value) + ")");
      return std::nullopt;
    }
    return static_cast<int>(*value);
  }

  std::optional<bool> Boolean(const YAML::Node& parent, const std::string& key,
                              const std::string& path) {
    const auto text = Text(parent, key, path);
    if (!text) return std::nullopt;
    if (*text == "true" || *text == "yes" || *text == "on") return true;
    if (*text == "false" || *text == "no" || *text == "off") return false;
    Problem(path, "must be true or false (got '" + *text + "')");
    return std::nullopt;
  }

 private:
  std::vector<std::string>* problems_;
};

void ReadCamera(const YAML::Node& node, FieldReader& r, RigCameraConfig* c) {
  r.CheckKeys(node, "camera",
              {"ip", "serial", "interface_ip", "pixel_format", "gain", "exposure_min_us",
               "exposure_max_us", "check_exposure_us", "timeout_ms", "retries", "buffers",
               "packet_size", "trigger_line", "region"});
  if (auto v = r.Text(node, "ip", "camera.ip")) {
    if (IsIpv4Address(*v)) {
      c->ip = *v;
    } else {
      r.Problem("camera.ip", "'" + *v + "' is not an IPv4 address");
    }
  }
  if (auto v = r.Text(node, "serial", "camera.serial")) c->serial = *v;
  if (c->ip.empty() && c->serial.empty() && !node["ip"]) {
    r.Problem("camera", "needs ip (preferred) or serial");
  }
  if (auto v = r.Text(node, "interface_ip", "camera.interface_ip")) {
    if (IsIpv4Address(*v)) {
      c->interface_ip = *v;
    } else {
      r.Problem("camera.interface_ip", "'" + *v + "' is not an IPv4 address");
    }
  }
  if (auto v = r.Text(node, "pixel_format", "camera.pixel_format")) {
    if (FindPixelFormat(*v) != nullptr) {
      c->pixel_format = *v;
    } else {
      std::string names;
      for (const auto& f : SupportedPixelFormats())
        names += (names.empty() ? "" : ", ") + std::string(f.name);
      r.Problem("camera.pixel_format",
                "'" + *v + "' is not a format zbrdf can unpack (" + names + ")");
    }
  }
  if (auto v = r.Real(node, "gain", "camera.gain", -1e6, 1e6)) c->gain = *v;
  if (auto v = r.Real(node, "exposure_min_us", "camera.exposure_min_us", 1e-3, 1e9)) {
    c->exposure_min_us = *v;
  }
  if (auto v = r.Real(node, "exposure_max_us", "camera.exposure_max_us", 1e-3, 1e9)) {
    c->exposure_max_us = *v;
  }
  if (c->exposure_min_us > c->exposure_max_us) {
    r.Problem("camera.exposure_min_us", "(" + FormatSetting(c->exposure_min_us) +
                                            ") must not exceed camera.exposure_max_us (" +
                                            FormatSetting(c->exposure_max_us) + ")");
  }
  if (auto v = r.Real(node, "check_exposure_us", "camera.check_exposure_us", 1e-3, 1e9)) {
    c->check_exposure_us = *v;
  }
  if (c->check_exposure_us < c->exposure_min_us || c->check_exposure_us > c->exposure_max_us) {
    r.Problem("camera.check_exposure_us", "(" + FormatSetting(c->check_exposure_us) +
                                              ") must lie within the exposure limits [" +
                                              FormatSetting(c->exposure_min_us) + ", " +
                                              FormatSetting(c->exposure_max_us) + "]");
  }
  if (auto v = r.Integer(node, "timeout_ms", "camera.timeout_ms", 1, 600000)) c->timeout_ms = *v;
  if (auto v = r.Integer(node, "retries", "camera.retries", 0, 100)) c->retries = *v;
  if (auto v = r.Integer(node, "buffers", "camera.buffers", 1, 64)) c->buffers = *v;
  if (auto v = r.Integer(node, "packet_size", "camera.packet_size", 0, 16384)) {
    if (*v != 0 && *v < 576) {
      r.Problem("camera.packet_size",
                "must be 0 (camera default) or >= 576 bytes (got " + std::to_string(*v) + ")");
    } else {
      c->packet_size = *v;
    }
  }
  if (auto v = r.Text(node, "trigger_line", "camera.trigger_line")) {
    if (std::regex_match(*v, std::regex("Line[0-9]+"))) {
      c->trigger_line = *v;
    } else {
      r.Problem("camera.trigger_line",
                "must name an input line such as Line0 or Line1 (got '" + *v + "')");
    }
  }
  const YAML::Node region = node["region"];
  if (r.IsMap(region, "camera.region")) {
    r.CheckKeys(region, "camera.region", {"x", "y", "width", "height"});
    if (auto v = r.Integer(region, "x", "camera.region.x", 0, 65535)) c->region_x = *v;
    if (auto v = r.Integer(region, "y", "camera.region.y", 0, 65535)) c->region_y = *v;
    auto w = r.Integer(region, "width", "camera.region.width", 1, 65535);
    auto h = r.Integer(region, "height", "camera.region.height", 1, 65535);
    if (w && h) {
      c->region_width = *w;
      c->region_height = *h;
    } else if (!region["width"] || !region["height"]) {
      r.Problem("camera.region", "needs both width and height");
    }
  }
}

void ReadProjector(const YAML::Node& node, FieldReader& r, RigProjectorConfig* p) {
  r.CheckKeys(node, "projector",
              {"x11_display", "x11_output", "refresh_hz", "settle_frames", "usb", "led_currents",
               "trigger_output"});
  if (auto v = r.Text(node, "x11_display", "projector.x11_display")) p->x11_display = *v;
  if (auto v = r.Text(node, "x11_output", "projector.x11_output")) p->x11_output = *v;
  if (p->x11_output.empty()) {
    r.Problem("projector.x11_output", "is required (the RandR output name, e.g. HDMI-1)");
  }
  if (auto v = r.Real(node, "refresh_hz", "projector.refresh_hz", 0, 1000)) p->refresh_hz = *v;
  if (auto v = r.Integer(node, "settle_frames", "projector.settle_frames", 0, 60)) {
    p->settle_frames = *v;
  }
  if (auto v = r.Integer(node, "trigger_output", "projector.trigger_output", 1, 2)) {
    p->trigger_output = *v;
  }
  const YAML::Node usb = node["usb"];
  if (r.IsMap(usb, "projector.usb")) {
    p->usb = true;
    r.CheckKeys(usb, "projector.usb", {"bus", "address", "vid_pid", "auto_detach_kernel_driver"});
    auto bus = r.Integer(usb, "bus", "projector.usb.bus", 0, 255);
    auto address = r.Integer(usb, "address", "projector.usb.address", 1, 127);
    if (static_cast<bool>(usb["bus"]) != static_cast<bool>(usb["address"])) {
      r.Problem("projector.usb", "needs both bus and address, or neither (then vid_pid selects)");
    }
    if (bus && address) {
      p->usb_bus = *bus;
      p->usb_address = *address;
    }
    if (auto v = r.Text(usb, "vid_pid", "projector.usb.vid_pid")) {
      std::smatch m;
      if (std::regex_match(*v, m, std::regex("([0-9a-fA-F]{4}):([0-9a-fA-F]{4})"))) {
        p->usb_vendor_id = static_cast<uint16_t>(std::stoul(m[1].str(), nullptr, 16));
        p->usb_product_id = static_cast<uint16_t>(std::stoul(m[2].str(), nullptr, 16));
      } else {
        r.Problem("projector.usb.vid_pid", "must look like 0451:6401 (got '" + *v + "')");
      }
    }
    if (auto v = r.Boolean(usb, "auto_detach_kernel_driver",
                           "projector.usb.auto_detach_kernel_driver")) {
      p->usb_auto_detach_kernel_driver = *v;
    }
  }
  const YAML::Node leds = node["led_currents"];
  if (r.IsMap(leds, "projector.led_currents")) {
    r.CheckKeys(leds, "projector.led_currents", {"red", "green", "blue"});
    auto red = r.Integer(leds, "red", "projector.led_currents.red", 0, 255);
    auto green = r.Integer(leds, "green", "projector.led_currents.green", 0, 255);
    auto blue = r.Integer(leds, "blue", "projector.led_currents.blue", 0, 255);
    if (!leds["red"] || !leds["green"] || !leds["blue"]) {
      r.Problem("projector.led_currents", "needs red, green and blue (0-255 each)");
    } else if (red && green && blue) {
      p->led_currents = Dlpc350LedCurrents{static_cast<uint8_t>(*red), static_cast<uint8_t>(*green),
                                           static_cast<uint8_t>(*blue)};
    }
    if (!p->usb) {
      r.Problem("projector.led_currents", "needs projector.usb (LED currents are set over USB)");
    }
  }
}

void ReadSync(const YAML::Node& node, FieldReader& r, RigSyncConfig* s) {
  r.CheckKeys(node, "sync", {"mode", "software_settle_ms", "hardware_settle_ms"});
  if (auto v = r.Text(node, "mode", "sync.mode")) {
    if (*v == "hardware" || *v == "software") {
      s->mode = ParseSyncMode(*v);
    } else {
      r.Problem("sync.mode", "must be hardware or software (got '" + *v + "')");
    }
  }
  if (auto v = r.Real(node, "software_settle_ms", "sync.software_settle_ms", 0, 10000)) {
    s->software_settle_ms = *v;
  }
  if (auto v = r.Real(node, "hardware_settle_ms", "sync.hardware_settle_ms", 0, 10000)) {
    s->hardware_settle_ms = *v;
  }
}

}  // namespace

HardwareRig ParseHardwareRig(const std::string& yaml_text, const std::string& source_name) {
  HardwareRig rig;
  rig.source = source_name;
  const std::string prefix = "rig file " + source_name + ": ";
  YAML::Node loaded;
  try {
    loaded = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(prefix + "not valid YAML: " + e.what());
  }
  const YAML::Node root = loaded;
  std::vector<std::string> problems;
  FieldReader reader(&problems);
  if (!root.IsMap()) {
    throw InputError(prefix + "must be a mapping with camera, projector and sync sections");
  }
  reader.CheckKeys(root, "", {"camera", "projector", "sync"});
  if (reader.IsMap(root["camera"], "camera")) {
    ReadCamera(root["camera"], reader, &rig.camera);
  } else if (!root["camera"]) {
    reader.Problem("camera", "section is missing");
  }
  if (reader.IsMap(root["projector"], "projector")) {
    ReadProjector(root["projector"], reader, &rig.projector);
  } else if (!root["projector"]) {
    reader.Problem("projector", "section is missing");
  }
  if (reader.IsMap(root["sync"], "sync")) ReadSync(root["sync"], reader, &rig.sync);
  if (!problems.empty()) {
    std::string message = prefix;
    for (size_t i = 0; i < problems.size(); ++i) message += (i ? "; " : "") + problems[i];
    throw InputError(message);
  }
  return rig;
}

HardwareRig LoadHardwareRig(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw InputError("rig file " + path + ": cannot be read (does it exist?)");
  std::stringstream text;
  text << file.rdbuf();
  return ParseHardwareRig(text.str(), path);
}

AravisCameraOptions CameraOptionsFromRig(const HardwareRig& rig) {
  const RigCameraConfig& c = rig.camera;
  AravisCameraOptions o;
  o.ip = c.ip;
  o.serial = c.serial;
  o.interface_ip = c.interface_ip;
  o.pixel_format = c.pixel_format;
  o.gain = c.gain;
  o.exposure_min_us = c.exposure_min_us;
  o.exposure_max_us = c.exposure_max_us;
  o.region_x = c.region_x;
  o.region_y = c.region_y;
  o.region_width = c.region_width;
  o.region_height = c.region_height;
  o.trigger_mode =
      rig.sync.mode == SyncMode::kHardware ? TriggerMode::kHardwareLine : TriggerMode::kSoftware;
  o.trigger_line = c.trigger_line;
  o.retries = c.retries;
  o.buffers = c.buffers;
  o.packet_size = c.packet_size;
  return o;
}

}  // namespace zbrdf
