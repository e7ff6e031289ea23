#pragma once
/// @file
/// Reading a frame source ahead of its consumer on a thread of its own (docs/performance.md,
/// "Silhouette tracking of a camera file"): the silhouette tracker measures frame i while
/// frame i + 1 is read and decoded.

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>

#include "tracking/frame_source.h"

namespace hoof::tracking {

/// Reads the frames of a source in order on a thread of its own, up to `depth` frames ahead of
/// the caller, who takes them with Next(). A frame is handed to the caller as a header without
/// ownership of the reader's buffer (no reference count), and its owning cv::Mat goes back to the
/// reader thread, under the lock, when the caller asks for the next frame: so every change to a
/// buffer's reference count happens on the reader thread or under the lock. That matters because
/// a source may reuse its one frame buffer when no-one else holds it (tracking/camera_file.cc):
/// the buffer of a frame the caller is still measuring is never reused, and there is no
/// unsynchronised access to its count.
class ReadAhead {
 public:
  /// Starts reading `source` from frame 0; `depth` >= 1. The frames are `source.Read`'s (grey),
  /// or with `colour` its ReadColour's.
  ReadAhead(FrameSource& source, int depth, bool colour = false);
  /// Stops the reader and waits for it.
  ~ReadAhead();
  ReadAhead(const ReadAhead&) = delete;
  ReadAhead& operator=(const ReadAhead&) = delete;

  /// The next frame in order (valid until the next call); rethrows the error of reading it.
  cv::Mat Next();

 private:
  void Run();

  FrameSource& source_;
  const int depth_;
  const bool colour_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<cv::Mat> ready_;      // read, not yet taken
  std::vector<cv::Mat> returned_;  // taken and finished, to be released by the reader
  cv::Mat current_;                // the frame the caller is measuring (owning)
  std::exception_ptr error_;
  bool stop_ = false;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace hoof::tracking
