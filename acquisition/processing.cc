#include "acquisition/processing.h"

#include <chrono>
#include <cmath>
#include <filesystem>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfThreading.h>
#include <half.h>

#include "basis/error.h"
#include "basis/parallel.h"
#include "basis/spherical_harmonics.h"

namespace zbrdf {

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void WriteRgbHalfExr(const std::string& path, const cv::Mat& rgb) {
  const int w = rgb.cols, h = rgb.rows;
  std::vector<half> channels[3];
  for (int c = 0; c < 3; ++c) channels[c].resize(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y) {
    const cv::Vec3f* row = rgb.ptr<cv::Vec3f>(y);
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) channels[c][y * w + x] = half(std::min(row[x][c], 65000.0f));
    }
  }
  Imf::Header header(w, h);
  header.compression() = Imf::PIZ_COMPRESSION;
  Imf::FrameBuffer fb;
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    header.channels().insert(names[c], Imf::Channel(Imf::HALF));
    fb.insert(names[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(channels[c].data()),
                                   sizeof(half), sizeof(half) * w));
  }
  try {
    Imf::OutputFile file(path.c_str(), header, Imf::globalThreadCount());
    file.setFrameBuffer(fb);
    file.writePixels(h);
  } catch (const std::exception& e) {
    throw InputError("cannot write HDR image " + path + ": " + e.what());
  }
}

std::string SafeName(const std::string& lobe) {
  std::string out;
  for (char c : lobe) {
    if (c == ',') out += '_';
    else if (c == '+') out += "pos";
    else if (c == '-') out += (out.empty() || out.back() == '_') ? "m" : "neg";
    else out += c;
  }
  return out;
}

}  // namespace

ZonalProcessor::ZonalProcessor(const CapturePlan& plan, const std::vector<LobePatternInfo>& patterns,
                               const RigCalibration& calibration, const ProcessingOptions& options)
    : plan_(plan), patterns_(patterns), calibration_(calibration), options_(options) {
  if (patterns_.size() != plan.lobes.size()) {
    throw InputError("pattern set does not match the plan (" + std::to_string(patterns_.size()) +
                     " patterns for " + std::to_string(plan.lobes.size()) + " lobes)");
  }
  const auto start = Clock::now();
  grid_ = MakeExitantGrid(plan.zone(), options.theta_step_deg, options.phi_step_deg);
  resampler_ = std::make_unique<PixelToGrid>(calibration, grid_);
  data_.theta_min_rad = plan.theta_min_rad;
  data_.theta_max_rad = plan.theta_max_rad;
  data_.order = plan.order;
  data_.grid = grid_;
  data_.functions.resize(ShCount(plan.order));
  stats_.zonal_seconds += Since(start);
}

ZonalProcessor::~ZonalProcessor() {
  if (worker_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    cv_.notify_all();
    worker_.join();
  }
  StopImageWriter();
}

void ZonalProcessor::QueueImage(std::string path, const HdrImage& hdr) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!image_writer_.joinable()) image_writer_ = std::thread([this] { ImageWriter(); });
  image_cv_.wait(lock, [&] { return images_.size() < kMaxQueuedImages || error_; });
  HdrImage copy;  // only what the view needs
  copy.width = hdr.width;
  copy.height = hdr.height;
  copy.layout = hdr.layout;
  copy.rate = hdr.rate;
  images_.emplace_back(std::move(path), std::move(copy));
  image_cv_.notify_all();
}

void ZonalProcessor::ImageWriter() {
  while (true) {
    std::pair<std::string, HdrImage> item;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      image_cv_.wait(lock, [&] { return images_done_ || !images_.empty(); });
      if (images_.empty()) return;
      item = std::move(images_.front());
      images_.pop_front();
      image_cv_.notify_all();
    }
    const auto start = Clock::now();
    try {
      WriteRgbHalfExr(item.first, HdrToRgb(item.second));
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      image_cv_.notify_all();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.image_seconds += Since(start);
  }
}

void ZonalProcessor::StopImageWriter() {
  if (!image_writer_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    images_done_ = true;
  }
  image_cv_.notify_all();
  image_writer_.join();
}

void ZonalProcessor::Start() {
  // OpenEXR compresses the HDR images' line blocks on its own thread pool.
  if (Imf::globalThreadCount() < WorkerThreads()) Imf::setGlobalThreadCount(WorkerThreads());
  worker_ = std::thread([this] { Worker(); });
}

void ZonalProcessor::AddLobe(int lobe, std::vector<Frame> frames) {
  if (!worker_.joinable()) {
    Process(lobe, frames);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.emplace_back(lobe, std::move(frames));
  }
  cv_.notify_all();
}

void ZonalProcessor::Worker() {
  while (true) {
    std::pair<int, std::vector<Frame>> item;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;
      item = std::move(queue_.front());
      queue_.pop_front();
    }
    bool failed;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      failed = static_cast<bool>(error_);
    }
    try {
      if (!failed) Process(item.first, item.second);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
  }
}

void ZonalProcessor::Process(int lobe, const std::vector<Frame>& frames) {
  if (lobe != next_lobe_) {
    throw InternalError("lobe " + std::to_string(lobe) + " processed out of order (expected " +
                        std::to_string(next_lobe_) + ")");
  }
  ++next_lobe_;
  const PlannedLobe& planned = plan_.lobes[lobe];
  const std::string name = planned.Name();
  auto start = Clock::now();
  HdrImage hdr = MergeExposures(frames, calibration_, "lobe " + name, options_.hdr);
  stats_.saturated_pixels += hdr.saturated_pixels;
  stats_.hdr_seconds += Since(start);
  if (options_.write_hdr_images && !options_.hdr_folder.empty()) {
    QueueImage(options_.hdr_folder + "/" + SafeName(name) + ".exr", hdr);
  }
  start = Clock::now();
  if (planned.kind == PlannedLobe::Kind::kDark) {
    dark_ = std::move(hdr);
    have_dark_ = true;
    stats_.zonal_seconds += Since(start);
    return;
  }
  if (!have_dark_) throw InputError("the dark pattern must be processed before the lobes");
  const int k = ShIndex(planned.l, planned.m);
  const bool has_negative =
      planned.kind == PlannedLobe::Kind::kPositive && lobe + 1 < static_cast<int>(plan_.lobes.size()) &&
      plan_.lobes[lobe + 1].kind == PlannedLobe::Kind::kNegative &&
      plan_.lobes[lobe + 1].l == planned.l && plan_.lobes[lobe + 1].m == planned.m;
  if (has_negative) {
    pending_ = std::move(hdr);
    pending_lobe_ = lobe;
    stats_.zonal_seconds += Since(start);
    return;
  }
  // z = (X+ - D) / (K s+) - (X- - D) / (K s-), with the dark's variance entering through its
  // net coefficient (1/s+ - 1/s-).
  const bool pair = planned.kind == PlannedLobe::Kind::kNegative;
  if (pair && pending_lobe_ != lobe - 1) {
    throw InputError("negative lobe " + name + " has no positive partner before it in the plan");
  }
  const HdrImage& pos = pair ? pending_ : hdr;
  const double s_pos = patterns_[pair ? lobe - 1 : lobe].radiance_per_unit_z;
  const double s_neg = pair ? patterns_[lobe].radiance_per_unit_z : 0.0;
  const size_t pixels = pos.rate.size();
  std::vector<float> value(pixels, 0.0f), variance(pixels, 0.0f);
  std::vector<uint8_t> valid(pixels, 0);
  for (size_t p = 0; p < pixels; ++p) {
    const double k_p = calibration_.camera_response[p];
    if (k_p <= 0 || !pos.valid[p] || !dark_.valid[p] || (pair && !hdr.valid[p])) continue;
    const double a = s_pos > 0 ? 1 / (k_p * s_pos) : 0.0;
    const double b = pair && s_neg > 0 ? 1 / (k_p * s_neg) : 0.0;
    double z = (pos.rate[p] - dark_.rate[p]) * a;
    double var = pos.variance[p] * a * a + dark_.variance[p] * (a - b) * (a - b);
    if (pair) {
      z -= (hdr.rate[p] - dark_.rate[p]) * b;
      var += hdr.variance[p] * b * b;
    }
    value[p] = static_cast<float>(z);
    variance[p] = static_cast<float>(var);
    valid[p] = 1;
  }
  if (options_.pixel_values) options_.pixel_values(k, value, valid);
  GridImage grid = resampler_->Resample(value, variance, valid);
  for (int ch = 0; ch < 3; ++ch) {
    const double scale = calibration_.channel_scale[ch];
    for (float& v : grid.value[ch]) v = static_cast<float>(v * scale);
    for (float& v : grid.variance[ch]) v = static_cast<float>(v * scale * scale);
  }
  data_.functions[k] = std::move(grid);
  if (pair) {
    pending_ = HdrImage();
    pending_lobe_ = -1;
  }
  stats_.zonal_seconds += Since(start);
}

ZonalData ZonalProcessor::Finish() {
  if (worker_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    cv_.notify_all();
    worker_.join();
  }
  StopImageWriter();
  if (error_) std::rethrow_exception(error_);
  if (next_lobe_ != static_cast<int>(plan_.lobes.size())) {
    throw InputError("processing incomplete: " + std::to_string(next_lobe_) + " of " +
                     std::to_string(plan_.lobes.size()) + " lobes have frames");
  }
  const auto start = Clock::now();
  ProjectExitant(&data_);
  stats_.zonal_seconds += Since(start);
  for (uint8_t f : data_.functions[0].filled) stats_.filled_cells += f;
  return std::move(data_);
}

}  // namespace zbrdf
