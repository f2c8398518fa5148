// CPU time for the benchmarks' per-call timings (assoc_sim, camera_accuracy).
#pragma once

#include <ctime>

#include <opencv2/core/utility.hpp>

namespace jointflow::bench {

/// CPU time of the calling thread in ms: the time on one core, whatever else the machine runs.
inline double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

/// OpenCV on one thread while it lives, so that the calling thread's CPU time is all the work:
/// OpenCV's pool runs parts of Lucas-Kanade and of resizes on other threads, which threadCpuMs
/// does not see. The thread count before is restored.
class OneOpenCvThread {
 public:
  OneOpenCvThread() : threads_(cv::getNumThreads()) { cv::setNumThreads(1); }
  ~OneOpenCvThread() { cv::setNumThreads(threads_); }
  OneOpenCvThread(const OneOpenCvThread&) = delete;
  OneOpenCvThread& operator=(const OneOpenCvThread&) = delete;

 private:
  int threads_;
};

}  // namespace jointflow::bench
