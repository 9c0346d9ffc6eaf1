#include "drivers/x11_display.h"

#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/extensions/Xrandr.h>

#include <algorithm>
#include <bit>
#include <mutex>
#include <thread>

#include "basis/error.h"

namespace zbrdf {

namespace {

// Xlib's default handlers exit() the process; ours record the error for the caller to throw.
std::mutex g_error_mutex;
std::string g_last_error;

int RecordXError(Display* display, XErrorEvent* event) {
  char text[256] = {};
  XGetErrorText(display, event->error_code, text, sizeof(text));
  std::lock_guard<std::mutex> lock(g_error_mutex);
  g_last_error = std::string(text) + " (request " + std::to_string(event->request_code) + "." +
                 std::to_string(event->minor_code) + ")";
  return 0;
}

int IgnoreXIOError(Display*) { return 0; }

void InstallErrorHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    XSetErrorHandler(&RecordXError);
    XSetIOErrorHandler(&IgnoreXIOError);
  });
}

std::string TakeXError() {
  std::lock_guard<std::mutex> lock(g_error_mutex);
  std::string error;
  error.swap(g_last_error);
  return error;
}

double ModeRefreshHz(const XRRModeInfo& mode) {
  if (mode.dotClock == 0 || mode.hTotal == 0 || mode.vTotal == 0) return 0;
  double lines = mode.vTotal;
  if (mode.modeFlags & RR_DoubleScan) lines *= 2;
  if (mode.modeFlags & RR_Interlace) lines /= 2;
  return static_cast<double>(mode.dotClock) / (static_cast<double>(mode.hTotal) * lines);
}

struct Channel {
  int shift = 0;
  int bits = 0;
};

Channel ChannelOf(unsigned long mask) {
  Channel c;
  if (mask == 0) return c;
  c.shift = std::countr_zero(mask);
  c.bits = std::popcount(mask);
  return c;
}

std::vector<X11OutputInfo> QueryOutputs(Display* display) {
  std::vector<X11OutputInfo> outputs;
  const Window root = DefaultRootWindow(display);
  XRRScreenResources* resources = XRRGetScreenResourcesCurrent(display, root);
  if (resources == nullptr) return outputs;
  for (int i = 0; i < resources->noutput; ++i) {
    XRROutputInfo* output = XRRGetOutputInfo(display, resources, resources->outputs[i]);
    if (output == nullptr) continue;
    X11OutputInfo info;
    info.name.assign(output->name, static_cast<size_t>(output->nameLen));
    info.connected = output->connection == RR_Connected;
    if (output->crtc != 0) {
      XRRCrtcInfo* crtc = XRRGetCrtcInfo(display, resources, output->crtc);
      if (crtc != nullptr) {
        info.active = crtc->mode != 0 && crtc->width > 0 && crtc->height > 0;
        info.x = crtc->x;
        info.y = crtc->y;
        info.width = static_cast<int>(crtc->width);
        info.height = static_cast<int>(crtc->height);
        for (int m = 0; m < resources->nmode; ++m) {
          if (resources->modes[m].id == crtc->mode) {
            info.refresh_hz = ModeRefreshHz(resources->modes[m]);
          }
        }
        XRRFreeCrtcInfo(crtc);
      }
    }
    XRRFreeOutputInfo(output);
    outputs.push_back(info);
  }
  XRRFreeScreenResources(resources);
  return outputs;
}

}  // namespace

struct X11Display::Impl {
  X11DisplayOptions options;
  std::string display_name;
  Display* display = nullptr;
  Window window = 0;
  GC gc = nullptr;
  Cursor cursor = 0;
  Visual* visual = nullptr;
  int depth = 0;
  X11OutputInfo output;
  double refresh_hz = 60;
  Channel red, green, blue;
  int bit_depth = 8;
  bool connection_lost = false;

  ~Impl() {
    if (display == nullptr) return;
    if (!connection_lost) {
      if (gc != nullptr) XFreeGC(display, gc);
      if (window != 0) XDestroyWindow(display, window);
      if (cursor != 0) XFreeCursor(display, cursor);
      XSync(display, False);
    }
    XCloseDisplay(display);
  }

  std::string Describe() const { return "X display " + display_name + " output " + options.output; }

  // Call after a request batch: XSync and turn recorded errors into DeviceError.
  void Sync(const std::string& action) {
    if (connection_lost) throw DeviceError(Describe() + ": the X connection was lost");
    XSync(display, False);
    if (connection_lost) {
      throw DeviceError(Describe() + ": the X connection was lost while " + action +
                        "; is the X server still running?");
    }
    const std::string error = TakeXError();
    if (!error.empty()) throw DeviceError(Describe() + ": X error while " + action + ": " + error);
  }

  unsigned long PixelOf(uint16_t level8) const {
    auto scale = [&](const Channel& c) {
      const unsigned long max = (1ul << c.bits) - 1ul;
      return ((static_cast<unsigned long>(level8) * max + 127ul) / 255ul) << c.shift;
    };
    return scale(red) | scale(green) | scale(blue);
  }

  void Validate(const Pattern& pattern) const {
    if (pattern.width != output.width || pattern.height != output.height) {
      throw InputError(Describe() + ": pattern is " + std::to_string(pattern.width) + "x" +
                       std::to_string(pattern.height) + ", the output is " +
                       std::to_string(output.width) + "x" + std::to_string(output.height));
    }
    if (pattern.bit_depth != bit_depth) {
      throw InputError(Describe() + ": pattern bit depth " + std::to_string(pattern.bit_depth) +
                       " does not match the display's " + std::to_string(bit_depth));
    }
    const size_t n = static_cast<size_t>(pattern.width) * static_cast<size_t>(pattern.height);
    if (pattern.levels.size() != n) {
      throw InputError(Describe() + ": pattern has " + std::to_string(pattern.levels.size()) +
                       " levels, expected " + std::to_string(n));
    }
    const uint16_t max_level = static_cast<uint16_t>((1u << bit_depth) - 1u);
    for (size_t i = 0; i < n; ++i) {
      if (pattern.levels[i] > max_level) {
        throw InputError(Describe() + ": pattern level " + std::to_string(pattern.levels[i]) +
                         " at pixel " + std::to_string(i) + " exceeds " +
                         std::to_string(max_level));
      }
    }
  }

  // Sends the image (no wait for it to be displayed).
  void Put(const Pattern& pattern) {
    Validate(pattern);
    const int w = output.width, h = output.height;
    XImage* image = XCreateImage(display, visual, static_cast<unsigned>(depth), ZPixmap, 0, nullptr,
                                 static_cast<unsigned>(w), static_cast<unsigned>(h), 32, 0);
    if (image == nullptr) throw DeviceError(Describe() + ": XCreateImage failed");
    std::vector<char> data(static_cast<size_t>(image->bytes_per_line) * static_cast<size_t>(h));
    image->data = data.data();
    const bool direct32 =
        image->bits_per_pixel == 32 &&
        image->byte_order == (std::endian::native == std::endian::little ? LSBFirst : MSBFirst);
    unsigned long lut[256];
    for (int v = 0; v < 256; ++v) lut[v] = PixelOf(static_cast<uint16_t>(v));
    for (int y = 0; y < h; ++y) {
      const uint16_t* row = pattern.levels.data() + static_cast<size_t>(y) * w;
      if (direct32) {
        auto* out = reinterpret_cast<uint32_t*>(data.data() +
                                                static_cast<size_t>(y) * image->bytes_per_line);
        for (int x = 0; x < w; ++x) out[x] = static_cast<uint32_t>(lut[row[x] & 0xFF]);
      } else {
        for (int x = 0; x < w; ++x) XPutPixel(image, x, y, lut[row[x] & 0xFF]);
      }
    }
    XRaiseWindow(display, window);
    XPutImage(display, window, gc, image, 0, 0, 0, 0, static_cast<unsigned>(w),
              static_cast<unsigned>(h));
    image->data = nullptr;  // owned by `data`
    XDestroyImage(image);
    Sync("drawing the pattern");
  }
};

X11Display::X11Display(const X11DisplayOptions& options) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.options = options;
  InstallErrorHandlers();
  const char* env = std::getenv("DISPLAY");
  d.display_name = !options.display.empty() ? options.display : (env != nullptr ? env : "");
  if (d.display_name.empty()) {
    throw DeviceError(
        "X display: none given and $DISPLAY is not set; set projector.x11_display "
        "or run on the machine's desktop session");
  }
  if (options.output.empty()) {
    throw InputError("X display " + d.display_name + ": no output name given (e.g. HDMI-1)");
  }
  if (options.settle_frames < 0) throw InputError("settle_frames must be >= 0");
  d.display = XOpenDisplay(d.display_name.c_str());
  if (d.display == nullptr) {
    throw DeviceError("X display " + d.display_name + ": cannot open it (is the X server " +
                      "running and is access allowed for this user?)");
  }
  XSetIOErrorExitHandler(
      d.display, [](Display*, void* data) { static_cast<Impl*>(data)->connection_lost = true; },
      impl_.get());
  int event_base = 0, error_base = 0;
  if (!XRRQueryExtension(d.display, &event_base, &error_base)) {
    throw DeviceError(d.Describe() +
                      ": the X server has no RandR extension, cannot locate outputs");
  }
  const auto outputs = QueryOutputs(d.display);
  std::string names;
  bool found = false;
  for (const auto& o : outputs) {
    names += (names.empty() ? "" : ", ") + o.name + (o.active ? "" : " (inactive)");
    if (o.name == options.output) {
      d.output = o;
      found = true;
    }
  }
  if (!found || !d.output.active) {
    throw InputError(
        d.Describe() +
        (found ? " is not active (no mode set; enable it with xrandr)" : " does not exist") +
        "; outputs: " + (names.empty() ? "none" : names));
  }
  d.refresh_hz = options.refresh_hz > 0 ? options.refresh_hz
                                        : (d.output.refresh_hz > 0 ? d.output.refresh_hz : 60.0);

  const int screen = DefaultScreen(d.display);
  d.visual = DefaultVisual(d.display, screen);
  d.depth = DefaultDepth(d.display, screen);
  if (d.visual->c_class != TrueColor) {
    throw DeviceError(d.Describe() + ": the default visual is not TrueColor (depth " +
                      std::to_string(d.depth) + "); run the X server at depth 24");
  }
  d.red = ChannelOf(d.visual->red_mask);
  d.green = ChannelOf(d.visual->green_mask);
  d.blue = ChannelOf(d.visual->blue_mask);
  d.bit_depth = std::min({d.red.bits, d.green.bits, d.blue.bits, 8});

  const Window root = RootWindow(d.display, screen);
  // An invisible cursor: the projector must show only the pattern.
  char empty[8] = {};
  Pixmap blank = XCreateBitmapFromData(d.display, root, empty, 8, 8);
  XColor black{};
  d.cursor = XCreatePixmapCursor(d.display, blank, blank, &black, &black, 0, 0);
  XFreePixmap(d.display, blank);

  XSetWindowAttributes attributes{};
  attributes.override_redirect = True;  // no window manager: exact placement, no decoration
  attributes.background_pixel = BlackPixel(d.display, screen);
  attributes.border_pixel = 0;
  attributes.backing_store = Always;
  attributes.cursor = d.cursor;
  d.window = XCreateWindow(
      d.display, root, d.output.x, d.output.y, static_cast<unsigned>(d.output.width),
      static_cast<unsigned>(d.output.height), 0, d.depth, InputOutput, d.visual,
      CWOverrideRedirect | CWBackPixel | CWBorderPixel | CWBackingStore | CWCursor, &attributes);
  XStoreName(d.display, d.window, "zbrdf projector");
  d.gc = XCreateGC(d.display, d.window, 0, nullptr);
  XMapRaised(d.display, d.window);
  d.Sync("creating the full-screen window");
}

X11Display::~X11Display() = default;

ProjectorInfo X11Display::Info() const {
  ProjectorInfo info;
  info.id = impl_->options.output;
  info.model =
      impl_->options.model.empty() ? "X11 output " + impl_->options.output : impl_->options.model;
  info.width = impl_->output.width;
  info.height = impl_->output.height;
  info.bit_depth = impl_->bit_depth;
  return info;
}

void X11Display::Show(const Pattern& pattern) {
  impl_->Put(pattern);
  // Let the scan-out pass over the new image (see the header: no vsync lock).
  const double frame_s = 1.0 / impl_->refresh_hz;
  std::this_thread::sleep_for(
      std::chrono::duration<double>(frame_s * impl_->options.settle_frames));
}

X11Capture X11Display::ReadBack() {
  Impl& d = *impl_;
  XImage* image = XGetImage(d.display, DefaultRootWindow(d.display), d.output.x, d.output.y,
                            static_cast<unsigned>(d.output.width),
                            static_cast<unsigned>(d.output.height), AllPlanes, ZPixmap);
  if (image == nullptr) {
    d.Sync("reading the screen back");
    throw DeviceError(d.Describe() + ": XGetImage returned nothing");
  }
  X11Capture capture;
  capture.width = d.output.width;
  capture.height = d.output.height;
  capture.rgb.resize(static_cast<size_t>(capture.width) * capture.height * 3);
  auto channel = [](unsigned long pixel, const Channel& c) {
    const unsigned long max = (1ul << c.bits) - 1ul;
    return static_cast<uint8_t>((((pixel >> c.shift) & max) * 255ul + max / 2) / max);
  };
  for (int y = 0; y < capture.height; ++y) {
    for (int x = 0; x < capture.width; ++x) {
      const unsigned long pixel = XGetPixel(image, x, y);
      uint8_t* out = &capture.rgb[(static_cast<size_t>(y) * capture.width + x) * 3];
      out[0] = channel(pixel, d.red);
      out[1] = channel(pixel, d.green);
      out[2] = channel(pixel, d.blue);
    }
  }
  XDestroyImage(image);
  d.Sync("reading the screen back");
  return capture;
}

std::chrono::microseconds X11Display::MeasureReadbackLatency(const Pattern& pattern,
                                                             std::chrono::milliseconds timeout) {
  const auto start = std::chrono::steady_clock::now();
  impl_->Put(pattern);
  while (true) {
    const X11Capture capture = ReadBack();
    const auto now = std::chrono::steady_clock::now();
    if (CaptureMatches(capture, pattern)) {
      return std::chrono::duration_cast<std::chrono::microseconds>(now - start);
    }
    if (now - start > timeout) {
      throw DeviceError(impl_->Describe() + ": the screen did not show the pattern within " +
                        std::to_string(timeout.count()) + " ms (another window on top, or a " +
                        "compositor that does not update the root window?)");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

double X11Display::RefreshHz() const { return impl_->refresh_hz; }

std::vector<X11OutputInfo> ListX11Outputs(const std::string& display_name) {
  InstallErrorHandlers();
  const char* env = std::getenv("DISPLAY");
  const std::string name = !display_name.empty() ? display_name : (env != nullptr ? env : "");
  Display* display = name.empty() ? nullptr : XOpenDisplay(name.c_str());
  if (display == nullptr) {
    throw DeviceError("X display " + (name.empty() ? std::string("($DISPLAY unset)") : name) +
                      ": cannot open it");
  }
  int event_base = 0, error_base = 0;
  std::vector<X11OutputInfo> outputs;
  if (XRRQueryExtension(display, &event_base, &error_base)) outputs = QueryOutputs(display);
  XCloseDisplay(display);
  return outputs;
}

bool CaptureMatches(const X11Capture& capture, const Pattern& pattern) {
  if (capture.width != pattern.width || capture.height != pattern.height) return false;
  const int shift = pattern.bit_depth > 8 ? pattern.bit_depth - 8 : 0;
  const size_t n = static_cast<size_t>(pattern.width) * static_cast<size_t>(pattern.height);
  if (pattern.levels.size() != n || capture.rgb.size() != 3 * n) return false;
  for (size_t i = 0; i < n; ++i) {
    const uint8_t level = static_cast<uint8_t>(pattern.levels[i] >> shift);
    if (capture.rgb[3 * i] != level || capture.rgb[3 * i + 1] != level ||
        capture.rgb[3 * i + 2] != level) {
      return false;
    }
  }
  return true;
}

}  // namespace zbrdf
