// The One-Euro filter (Casiez, Roussel, Vogel, CHI 2012): a first-order low-pass filter whose
// cut-off rises with the signal's speed, so still keypoints stop jittering and fast ones do not
// lag. Written here because it is a dozen lines and no library the core uses (OpenCV, Eigen) has
// it.
#pragma once

namespace jointflow {

class OneEuroFilter {
 public:
  OneEuroFilter(float min_cutoff, float beta, float d_cutoff)
      : min_cutoff_(min_cutoff), beta_(beta), d_cutoff_(d_cutoff) {}

  /// Filters sample x taken dt seconds after the previous one (dt > 0); the first sample passes.
  float filter(float x, float dt);

 private:
  float min_cutoff_, beta_, d_cutoff_;
  bool started_ = false;
  float x_ = 0.f, dx_ = 0.f;
};

}  // namespace jointflow
