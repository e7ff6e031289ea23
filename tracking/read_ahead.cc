#include "tracking/read_ahead.h"

namespace hoof::tracking {

ReadAhead::ReadAhead(FrameSource& source, int depth, bool colour)
    : source_(source), depth_(depth), colour_(colour) {
  thread_ = std::thread([this] { Run(); });
}

ReadAhead::~ReadAhead() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

cv::Mat ReadAhead::Next() {
  std::unique_lock lock(mutex_);
  if (!current_.empty()) returned_.push_back(std::move(current_));
  changed_.notify_all();
  changed_.wait(lock, [&] { return !ready_.empty() || error_; });
  if (ready_.empty()) std::rethrow_exception(error_);
  current_ = std::move(ready_.front());
  ready_.pop_front();
  changed_.notify_all();
  return cv::Mat(current_.rows, current_.cols, current_.type(), current_.data, current_.step[0]);
}

void ReadAhead::Run() {
  for (int i = 0; i < source_.count(); ++i) {
    std::vector<cv::Mat> done;
    {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [&] { return stop_ || static_cast<int>(ready_.size()) < depth_; });
      if (stop_) return;
      done.swap(returned_);
    }
    done.clear();  // the caller's finished frames, released on this thread
    cv::Mat frame;
    try {
      frame = colour_ ? source_.ReadColour(i) : source_.Read(i);
    } catch (...) {
      std::lock_guard lock(mutex_);
      error_ = std::current_exception();
      changed_.notify_all();
      return;
    }
    {
      std::lock_guard lock(mutex_);
      ready_.push_back(std::move(frame));
    }
    changed_.notify_all();
  }
}

}  // namespace hoof::tracking
