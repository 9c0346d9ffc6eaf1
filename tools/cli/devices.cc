// zbrdf devices: lists cameras (by GigE Vision / USB3 Vision discovery, which BROADCASTS on every
// network interface), DLPC350 projectors on USB, and the X11 outputs a projector can be. The only
// place in zbrdf that runs network discovery; it runs only when a user types this command.
#include <iostream>
#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "drivers/aravis_camera.h"
#include "drivers/dlpc350_usb.h"
#include "drivers/x11_display.h"
#include "tools/cli/command.h"

namespace zbrdf::cli {
namespace {

int RunDevices(const std::vector<std::string>& args) {
  CommandLine cl("devices",
                 "List cameras, DLPC350 projectors on USB, and X11 outputs, for writing a rig "
                 "file.");
  cl.Flag("no-network", "skip camera discovery (sends nothing on the network)")
      .Flag("save",
            "remember each camera's serial -> IP in the camera directory, so that a rig file "
            "may name the camera by camera.serial")
      .Option("display", "NAME", "X display whose outputs to list (default: $DISPLAY)")
      .Flag("json", "print one JSON object instead of text")
      .Epilog(
          "WARNING: camera discovery BROADCASTS GigE Vision discovery packets on every\n"
          "network interface of this machine. Run it only on networks where that is\n"
          "allowed; use --no-network otherwise. Nothing else in zbrdf discovers: rig files\n"
          "name cameras by IP address (or by a serial saved here with --save).");
  if (!cl.Parse(args)) return 0;
  const bool json = cl.Has("json");
  nlohmann::json out;

  std::vector<DiscoveredCamera> cameras;
  if (!cl.Has("no-network")) {
    std::cerr << "zbrdf devices: WARNING: broadcasting GigE Vision discovery on every network "
                 "interface (use --no-network to skip)\n";
    cameras = DiscoverCamerasByBroadcast();
  }
  out["cameras"] = nlohmann::json::array();
  for (const auto& c : cameras) {
    out["cameras"].push_back({{"id", c.id},
                              {"protocol", c.protocol},
                              {"address", c.address},
                              {"vendor", c.vendor},
                              {"model", c.model},
                              {"serial", c.serial}});
  }
  if (cl.Has("save")) {
    std::vector<CameraDirectoryEntry> seen;
    for (const auto& c : cameras) {
      if (IsIpv4Address(c.address) && !c.serial.empty()) {
        seen.push_back({c.serial, c.address, c.vendor, c.model});
      }
    }
    WriteCameraDirectory(DefaultCameraDirectoryPath(), seen);
    out["camera_directory"] = DefaultCameraDirectoryPath();
  }

  out["dlpc350"] = nlohmann::json::array();
  for (const auto& d : ListUsbDevices(0x0451, 0x6401)) {
    out["dlpc350"].push_back({{"bus", d.bus}, {"address", d.address}, {"vid_pid", "0451:6401"}});
  }

  out["x11_outputs"] = nlohmann::json::array();
  std::string x11_error;
  try {
    for (const auto& o : ListX11Outputs(cl.Has("display") ? cl.Get("display") : "")) {
      out["x11_outputs"].push_back({{"name", o.name},
                                    {"connected", o.connected},
                                    {"active", o.active},
                                    {"x", o.x},
                                    {"y", o.y},
                                    {"width", o.width},
                                    {"height", o.height},
                                    {"refresh_hz", o.refresh_hz}});
    }
  } catch (const DeviceError& e) {
    x11_error = e.what();
    out["x11_error"] = x11_error;
  }

  if (json) {
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::cout << "cameras";
  if (cl.Has("no-network")) {
    std::cout << ": not searched (--no-network)\n";
  } else if (cameras.empty()) {
    std::cout << ": none answered discovery\n";
  } else {
    std::cout << ":\n";
    for (const auto& c : cameras) {
      std::cout << "  " << c.protocol << " " << (c.address.empty() ? "-" : c.address) << "  "
                << c.vendor << " " << c.model << "  serial " << c.serial << "\n";
    }
  }
  if (cl.Has("save")) {
    std::cout << "  saved serial -> IP in " << DefaultCameraDirectoryPath() << "\n";
  }
  std::cout << "DLPC350 projectors on USB (0451:6401)";
  if (out["dlpc350"].empty()) {
    std::cout << ": none\n";
  } else {
    std::cout << ":\n";
    for (const auto& d : out["dlpc350"]) {
      std::cout << "  bus " << d["bus"] << " address " << d["address"] << "\n";
    }
  }
  std::cout << "X11 outputs";
  if (!x11_error.empty()) {
    std::cout << ": " << x11_error << "\n";
  } else {
    std::cout << ":\n";
    for (const auto& o : out["x11_outputs"]) {
      std::cout << "  " << o["name"].get<std::string>() << "  "
                << (o["active"].get<bool>()
                        ? std::to_string(o["width"].get<int>()) + "x" +
                              std::to_string(o["height"].get<int>()) + "+" +
                              std::to_string(o["x"].get<int>()) + "+" +
                              std::to_string(o["y"].get<int>())
                        : std::string(o["connected"].get<bool>() ? "connected, inactive"
                                                                 : "disconnected"))
                << "\n";
    }
  }
  return 0;
}

const CommandRegistration kDevicesCommand(
    {"devices", "list cameras (broadcast discovery), DLPC350s and X11 outputs", RunDevices});

}  // namespace
}  // namespace zbrdf::cli
