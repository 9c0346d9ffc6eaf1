#include "acquisition/frame_writer.h"

#include <utility>

namespace zbrdf {

FrameWriter::FrameWriter(SessionFolder& session)
    : session_(session), thread_([this] { Run(); }) {}

FrameWriter::~FrameWriter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void FrameWriter::ThrowIfFailedLocked() {
  if (error_) std::rethrow_exception(error_);
}

void FrameWriter::Add(int index, Frame frame, const JournalEntry& plan_fields) {
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait(lock, [&] { return static_cast<int>(queue_.size()) < kMaxQueued || error_; });
  ThrowIfFailedLocked();
  queue_.push_back({index, std::move(frame), plan_fields});
  cv_.notify_all();
}

std::vector<JournalEntry> FrameWriter::Drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait(lock, [&] { return (queue_.empty() && writing_ == 0) || error_; });
  ThrowIfFailedLocked();
  return std::exchange(written_, {});
}

void FrameWriter::Run() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    cv_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
    // Stopping still writes what was handed over; after a failure nothing more is written.
    if (queue_.empty() || error_) return;
    Item item = std::move(queue_.front());
    queue_.pop_front();
    ++writing_;
    cv_.notify_all();  // room in the queue
    lock.unlock();
    std::exception_ptr error;
    JournalEntry entry;
    try {
      entry = session_.WriteFrame(item.index, item.frame);
      entry.lobe = item.plan_fields.lobe;
      entry.exposure = item.plan_fields.exposure;
      entry.repeat = item.plan_fields.repeat;
      entry.exposure_us_requested = item.plan_fields.exposure_us_requested;
      session_.AppendJournal(entry);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    --writing_;
    if (error) {
      error_ = error;
    } else {
      written_.push_back(std::move(entry));
    }
    cv_.notify_all();
  }
}

}  // namespace zbrdf
