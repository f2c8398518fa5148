// Internal: buffers of one shape reused from frame to frame. Why: a network's input blob and its
// outputs are megabytes a frame (MoveNet at max:640: a 3.7 MB blob, 8.7 MB of maps), and a fresh
// buffer of that size is fresh pages from the kernel, each one faulted in on first write. On
// vtest.avi at max:640 cv::dnn::blobFromImage took 4.1 ms into a fresh blob and 0.66 ms into a
// reused one; jointflow-track took ~430 minor page faults a frame.
//
// A buffer is free again once nobody but the pool holds it: the pool hands out cv::Mat headers
// that share its buffers, and cv::Mat counts its holders (atomically), so a frame's maps that the
// tracker or an asynchronous run still holds are never written over. Header-only, because the
// OpenVINO module (a library of its own) uses it too.
#pragma once

#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

namespace jointflow::detail {

class MatPool {
 public:
  /// A continuous Mat of these `sizes` and `type` that nobody else holds; its contents are
  /// whatever it held before. Calls on one pool come from one thread at a time.
  cv::Mat take(const std::vector<int>& sizes, int type) {
    ++clock_;
    cv::Mat found;
    for (Entry& e : entries_) {
      if (found.empty() && free(e) && e.mat.type() == type && shapeOf(e.mat) == sizes) {
        e.last_used = clock_;
        found = e.mat;
      }
    }
    // Buffers of a shape no longer asked for (a resolution change) go back to the system.
    for (size_t i = entries_.size(); i-- > 0;) {
      if (free(entries_[i]) && clock_ - entries_[i].last_used > kIdleTakes)
        entries_.erase(entries_.begin() + static_cast<std::ptrdiff_t>(i));
    }
    if (!found.empty()) return found;
    entries_.push_back({cv::Mat(static_cast<int>(sizes.size()), sizes.data(), type), clock_});
    return entries_.back().mat;
  }

  /// take() for the shape and type of `like`.
  cv::Mat takeLike(const cv::Mat& like) { return take(shapeOf(like), like.type()); }

  /// Buffers held, free or not (for tests).
  size_t size() const { return entries_.size(); }

 private:
  /// A free buffer not taken for this many take() calls is released.
  static constexpr size_t kIdleTakes = 64;

  struct Entry {
    cv::Mat mat;
    size_t last_used = 0;
  };

  // The count is read atomically (CV_XADD of 0, as OpenCV changes it): a holder on another
  // thread may let go at any time.
  static bool free(const Entry& e) { return e.mat.u && CV_XADD(&e.mat.u->refcount, 0) == 1; }
  static std::vector<int> shapeOf(const cv::Mat& m) {
    return std::vector<int>(m.size.p, m.size.p + m.dims);
  }

  std::vector<Entry> entries_;
  size_t clock_ = 0;
};

}  // namespace jointflow::detail
