#include "acquisition/processing.h"

#include <chrono>
#include <cmath>
#include <filesystem>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfThreading.h>
#include <half.h>

#include "acquisition/half_convert.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "basis/spherical_harmonics.h"
#include "basis/stopwatch.h"

namespace zbrdf {

namespace {

void WriteRgbHalfExr(const std::string& path, const cv::Mat& rgb) {
  const int w = rgb.cols, h = rgb.rows;
  std::vector<half> channels[3];
  for (int c = 0; c < 3; ++c) channels[c].resize(static_cast<size_t>(w) * h);
  std::vector<float> plane(3 * static_cast<size_t>(w));  // a row's channels, clipped
  for (int y = 0; y < h; ++y) {
    const cv::Vec3f* row = rgb.ptr<cv::Vec3f>(y);
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c)
        plane[c * static_cast<size_t>(w) + x] = std::min(row[x][c], 65000.0f);
    }
    for (int c = 0; c < 3; ++c) {
      FloatsToHalf(&plane[c * static_cast<size_t>(w)], w, &channels[c][static_cast<size_t>(y) * w]);
    }
  }
  Imf::Header header(w, h);
  header.compression() = Imf::PIZ_COMPRESSION;
  Imf::FrameBuffer fb;
  for (int c = 0; c < 3; ++c) {
    header.channels().insert(kRgbChannelNames[c], Imf::Channel(Imf::HALF));
    fb.insert(kRgbChannelNames[c],
              Imf::Slice(Imf::HALF, reinterpret_cast<char*>(channels[c].data()), sizeof(half),
                         sizeof(half) * w));
  }
  Imf::StdOSStream stream;  // encoded in memory, written through basis/atomic_file.h
  try {
    Imf::OutputFile file(stream, header, Imf::globalThreadCount());
    file.setFrameBuffer(fb);
    file.writePixels(h);
  } catch (const std::exception& e) {
    throw InputError("cannot encode HDR image " + path + ": " + e.what());
  }
  WriteFileAtomically(path, stream.str());
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

void ProcessingOptions::Validate() const {
  OptionChecker check("ProcessingOptions");
  check.InRangeAbove("theta_step_deg", theta_step_deg, 0, 10)
      .InRangeAbove("phi_step_deg", phi_step_deg, 0, 10)
      .Nested("hdr", hdr)
      .ThrowIfInvalid();
}

ZonalData ZonalLayout(const CapturePlan& plan, const ProcessingOptions& options) {
  ZonalData data;
  data.theta_min_rad = plan.theta_min_rad;
  data.theta_max_rad = plan.theta_max_rad;
  data.order = plan.order;
  data.grid = MakeExitantGrid(plan.zone(), options.theta_step_deg, options.phi_step_deg);
  return data;
}

ZonalProcessor::ZonalProcessor(const CapturePlan& plan, const std::vector<LobePatternInfo>& patterns,
                               const RigCalibration& calibration, const ProcessingOptions& options)
    : plan_(plan), patterns_(patterns), calibration_(calibration), options_(options) {
  options.Validate();
  if (patterns_.size() != plan.lobes.size()) {
    throw InputError("pattern set does not match the plan (" + std::to_string(patterns_.size()) +
                     " patterns for " + std::to_string(plan.lobes.size()) + " lobes)");
  }
  const auto start = WallClock::now();
  data_ = ZonalLayout(plan, options);
  grid_ = data_.grid;
  resampler_ = std::make_unique<PixelToGrid>(calibration, grid_);
  data_.functions.resize(ShCount(plan.order));
  stats_.zonal_seconds += SecondsSince(start);
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
    const auto start = WallClock::now();
    try {
      WriteRgbHalfExr(item.first, HdrToRgb(item.second));
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      image_cv_.notify_all();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.image_seconds += SecondsSince(start);
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

void ZonalProcessor::WaitForImages() {
  StopImageWriter();
  if (error_) std::rethrow_exception(error_);
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
    ++in_flight_;
  }
  cv_.notify_all();
}

void ZonalProcessor::Wait() {
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait(lock, [&] { return in_flight_ == 0 || error_; });
  if (error_) std::rethrow_exception(error_);
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
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --in_flight_;
    }
    cv_.notify_all();
  }
}

void ZonalProcessor::Process(int lobe, const std::vector<Frame>& frames) {
  if (lobe != next_lobe_) {
    throw InternalError("lobe " + std::to_string(lobe) + " processed out of order (expected " +
                        std::to_string(next_lobe_) + ")");
  }
  if (frames.empty()) {
    ProcessSkipped(lobe);
    ++next_lobe_;
    return;
  }
  ++next_lobe_;
  skipped_positive_ = false;
  const PlannedLobe& planned = plan_.lobes[lobe];
  const std::string name = planned.Name();
  auto start = WallClock::now();
  HdrImage hdr = MergeExposures(frames, calibration_, "lobe " + name, options_.hdr);
  stats_.saturated_pixels += hdr.saturated_pixels;
  stats_.hdr_seconds += SecondsSince(start);
  if (options_.write_hdr_images && !options_.hdr_folder.empty()) {
    QueueImage(options_.hdr_folder + "/" + SafeName(name) + ".exr", hdr);
  }
  start = WallClock::now();
  if (planned.kind == PlannedLobe::Kind::kDark) {
    dark_ = std::move(hdr);
    have_dark_ = true;
    stats_.zonal_seconds += SecondsSince(start);
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
    stats_.zonal_seconds += SecondsSince(start);
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
  stats_.zonal_seconds += SecondsSince(start);
}

namespace {

// Per theta row and channel, the least-squares coefficient of the sampled harmonic h in `value`,
// and its variance from the cells' (independent) variances.
void ProjectRows(const GridImage& g, const ExitantGrid& grid, const std::vector<double>& h,
                 std::array<std::vector<double>, 3>* coef, std::array<std::vector<double>, 3>* var) {
  double hh = 0;
  for (double v : h) hh += v * v;
  for (int ch = 0; ch < 3; ++ch) {
    (*coef)[ch].assign(grid.n_theta, 0.0);
    (*var)[ch].assign(grid.n_theta, 0.0);
    if (g.value[ch].size() != static_cast<size_t>(grid.cells())) continue;
    for (int i = 0; i < grid.n_theta; ++i) {
      double dot = 0, v = 0;
      for (int j = 0; j < grid.n_phi; ++j) {
        const size_t c = static_cast<size_t>(i) * grid.n_phi + j;
        dot += g.value[ch][c] * h[j];
        if (c < g.variance[ch].size()) v += g.variance[ch][c] * h[j] * h[j];
      }
      (*coef)[ch][i] = dot / hh;
      (*var)[ch][i] = v / (hh * hh);
    }
  }
}

std::vector<double> Harmonic(const ExitantGrid& grid, int m, bool sine) {
  std::vector<double> h(grid.n_phi);
  for (int j = 0; j < grid.n_phi; ++j) {
    const double phi = (j + 0.5) * grid.phi_step_rad;
    h[j] = m == 0 ? 1.0 : sine ? std::sin(m * phi) : std::cos(m * phi);
  }
  return h;
}

// A function that is `scale` x coef(theta) x h(phi), with the coefficients' variances.
GridImage FromRows(const ExitantGrid& grid, const std::vector<double>& h, double scale,
                   const std::array<std::vector<double>, 3>& coef,
                   const std::array<std::vector<double>, 3>& var) {
  GridImage out;
  for (int ch = 0; ch < 3; ++ch) {
    out.value[ch].assign(grid.cells(), 0.0f);
    out.variance[ch].assign(grid.cells(), 0.0f);
    out.weight[ch].assign(grid.cells(), 0.0f);
    for (int i = 0; i < grid.n_theta; ++i) {
      for (int j = 0; j < grid.n_phi; ++j) {
        const size_t c = static_cast<size_t>(i) * grid.n_phi + j;
        out.value[ch][c] = static_cast<float>(scale * coef[ch][i] * h[j]);
        out.variance[ch][c] = static_cast<float>(scale * scale * var[ch][i] * h[j] * h[j]);
      }
    }
  }
  out.filled.assign(grid.cells(), 0);
  return out;
}

}  // namespace

void ZonalProcessor::ProcessSkipped(int lobe) {
  const PlannedLobe& planned = plan_.lobes[lobe];
  if (planned.kind == PlannedLobe::Kind::kDark) throw InputError("the dark pattern cannot be skipped");
  const auto start = WallClock::now();
  const int k = ShIndex(planned.l, planned.m);
  if (planned.kind == PlannedLobe::Kind::kPositive) {
    if (planned.m >= 0) {
      throw InputError("lobe " + planned.Name() + " cannot be skipped (isotropy makes only the "
                       "lobes of Z_l,-m and the negative lobes of Z_l,m, m > 0, redundant)");
    }
    skipped_positive_ = true;
    return;
  }
  if (planned.m < 0 && skipped_positive_) {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_synthesis_.push_back(k);
    return;
  }
  if (planned.m <= 0 || pending_lobe_ != lobe - 1) {
    throw InputError("lobe " + planned.Name() + " was skipped but its partner was measured; "
                     "only the negative lobe of Z_l,m with m > 0 may be skipped alone");
  }
  // The positive lobe's response per unit Z, z+ = (X+ - D) / (K s+), on the grid.
  const HdrImage& pos = pending_;
  const double s_pos = patterns_[lobe - 1].radiance_per_unit_z;
  const size_t pixels = pos.rate.size();
  std::vector<float> value(pixels, 0.0f), variance(pixels, 0.0f);
  std::vector<uint8_t> valid(pixels, 0);
  for (size_t p = 0; p < pixels; ++p) {
    const double k_p = calibration_.camera_response[p];
    if (k_p <= 0 || !pos.valid[p] || !dark_.valid[p] || s_pos <= 0) continue;
    const double a = 1 / (k_p * s_pos);
    value[p] = static_cast<float>((pos.rate[p] - dark_.rate[p]) * a);
    variance[p] = static_cast<float>((pos.variance[p] + dark_.variance[p]) * a * a);
    valid[p] = 1;
  }
  GridImage half = resampler_->Resample(value, variance, valid);
  for (int ch = 0; ch < 3; ++ch) {
    const double scale = calibration_.channel_scale[ch];
    for (float& v : half.value[ch]) v = static_cast<float>(v * scale);
    for (float& v : half.variance[ch]) v = static_cast<float>(v * scale * scale);
  }
  // Isotropy: z- (phi) = z+ (phi - pi/m), so z = z+ - z- keeps the odd multiples of m in z+'s
  // azimuthal spectrum, doubled; z has only the m-th: z = 2 c_m(theta) cos(m phi).
  const std::vector<double> h = Harmonic(grid_, planned.m, false);
  std::array<std::vector<double>, 3> coef, var;
  ProjectRows(half, grid_, h, &coef, &var);
  data_.functions[k] = FromRows(grid_, h, 2.0, coef, var);
  pending_ = HdrImage();
  pending_lobe_ = -1;
  stats_.zonal_seconds += SecondsSince(start);
}

void ZonalProcessor::SynthesizeIsotropic(int l) {
  std::vector<int> left;
  std::vector<int> pending;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pending.swap(pending_synthesis_);
  }
  for (int k : pending) {
    int kl, km;
    ShDegreeOrder(k, &kl, &km);
    const GridImage& source = data_.functions[ShIndex(kl, -km)];
    if ((l >= 0 && kl != l) || source.value[0].size() != static_cast<size_t>(grid_.cells())) {
      left.push_back(k);
      continue;
    }
    // z_l,-m (phi) = z_l,m (phi - pi / (2m)): the cos(m phi) profile of z_lm times sin(m phi).
    std::array<std::vector<double>, 3> coef, var;
    ProjectRows(source, grid_, Harmonic(grid_, -km, false), &coef, &var);
    data_.functions[k] = FromRows(grid_, Harmonic(grid_, -km, true), 1.0, coef, var);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  pending_synthesis_.insert(pending_synthesis_.end(), left.begin(), left.end());
}

ZonalData ZonalProcessor::Finish() { return Finish(plan_.order); }

ZonalData ZonalProcessor::Finish(int order) {
  if (order < 0 || order > plan_.order) {
    throw InternalError("Finish: order " + std::to_string(order) + " outside the plan's 0.." +
                        std::to_string(plan_.order));
  }
  int lobes_needed = 0;
  for (const PlannedLobe& lobe : plan_.lobes) {
    if (lobe.kind == PlannedLobe::Kind::kDark || lobe.l <= order) ++lobes_needed;
  }
  if (worker_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    cv_.notify_all();
    worker_.join();
  }
  // The HDR images may still be on their way to disk (WaitForImages); the coefficients do not
  // need them.
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (error_) std::rethrow_exception(error_);
  }
  SynthesizeIsotropic();
  if (next_lobe_ < lobes_needed) {
    throw InputError("processing incomplete: " + std::to_string(next_lobe_) + " of " +
                     std::to_string(lobes_needed) + " lobes have frames");
  }
  data_.order = order;
  data_.functions.resize(ShCount(order));
  const auto start = WallClock::now();
  ProjectExitant(&data_);
  stats_.zonal_seconds += SecondsSince(start);
  for (uint8_t f : data_.functions[0].filled) stats_.filled_cells += f;
  return std::move(data_);
}

}  // namespace zbrdf
