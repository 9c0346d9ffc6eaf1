// Writes a capture's frames to the session folder on a thread of its own, so that the capture
// grabs the next frame while the last one is encoded (TIFF/zstd), written, fsynced and
// journaled: on the simulated rig those took as long as rendering the frames, and on the
// hardware rig they are time the camera's buffers would otherwise have to cover.
//
// The contract is RunCapture's (acquisition/session.h): every frame handed over ends up on disk,
// then its journal line, in the order handed over, unless a write fails; after the first failure
// nothing more is written (the journal ends at the last frame on disk, as if the capture had
// stopped there) and the error is thrown to the capture at its next call. Destroying the writer
// (an exception on its way out of the capture) still writes every frame handed over before.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "acquisition/session.h"

namespace zbrdf {

class FrameWriter {
 public:
  // Frames waiting to be written at most; Add blocks beyond (memory stays bounded when the disk
  // is slower than the camera).
  // Two: a crash loses at most four frames (one being written, two waiting, one being grabbed).
  static constexpr int kMaxQueued = 2;

  explicit FrameWriter(SessionFolder& session);
  // Writes what was handed over (errors are dropped: the capture is already failing).
  ~FrameWriter();
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  // Hands frame `index` over with its journal fields set by the capture (lobe, exposure, repeat,
  // exposure_us_requested; the rest comes from SessionFolder::WriteFrame). Blocks while
  // kMaxQueued frames wait. Throws the first failed write's error (FileWriteError, ...).
  void Add(int index, Frame frame, const JournalEntry& plan_fields);
  // Waits until every frame handed over is written and journaled and returns their entries, in
  // the order handed over (each once). Throws the first failed write's error.
  std::vector<JournalEntry> Drain();

 private:
  struct Item {
    int index;
    Frame frame;
    JournalEntry plan_fields;
  };
  void Run();
  void ThrowIfFailedLocked();

  SessionFolder& session_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Item> queue_;
  int writing_ = 0;  // items taken from the queue and not yet done
  bool stopping_ = false;
  std::exception_ptr error_;
  std::vector<JournalEntry> written_;
  std::thread thread_;
};

}  // namespace zbrdf
