// TemporalFlowModel: runs the TFF network on the engine of EngineOptions and keeps the one-frame
// state.
#include "jointflow/tff_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "../engine/mat_pool.hpp"
#include "../engine/network.hpp"
#include "jointflow/error.hpp"

namespace jointflow {
namespace {

std::string shapeText(const cv::Mat& m) {
  std::string s = "{";
  for (int i = 0; i < m.dims; ++i) s += (i ? ", " : "") + std::to_string(m.size[i]);
  return s + "}";
}

// Plane c of a {1, C, H, W} blob, as an H x W image sharing its memory.
cv::Mat plane(const cv::Mat& blob, int c) {
  const int h = blob.size[2], w = blob.size[3];
  return cv::Mat(h, w, CV_32F, const_cast<float*>(blob.ptr<float>()) + size_t(c) * h * w);
}

// Copies a {1, n, H, W} map into channels [first, first + n) of a {1, N, H, W} blob.
void copyChannels(const cv::Mat& src, cv::Mat& dst, int first) {
  const cv::Mat s = src.isContinuous() ? src : src.clone();
  const size_t plane_size = static_cast<size_t>(dst.size[2]) * dst.size[3];
  std::memcpy(dst.ptr<float>() + plane_size * first, s.ptr<float>(),
              plane_size * s.size[1] * sizeof(float));
}

// Resizes every channel of a {1, C, H, W} blob into channels [first, first + C) of dst, whose
// planes are the target size (cv::resize per plane: OpenCV has no resize of 4-D blobs). The planes
// run in parallel: each is too small for cv::resize's own row split to pay (41 planes of 160x120
// pooled to 80x60: 0.085 ms one by one, 0.055 ms in parallel on 2 threads).
void resizeChannels(const cv::Mat& src, cv::Mat& dst, int first, int interpolation) {
  const cv::Mat s = src.isContinuous() ? src : src.clone();
  cv::parallel_for_(cv::Range(0, s.size[1]), [&](const cv::Range& range) {
    for (int c = range.start; c < range.end; ++c) {
      cv::Mat to = plane(dst, first + c);
      cv::resize(plane(s, c), to, to.size(), 0, 0, interpolation);
    }
  });
}

// Moves channels [src_first, src_first + count) of a {1, C, H, W} blob by the 2x3 motion m
// (source -> destination cells) into channels [dst_first, dst_first + count) of dst: bilinear, 0
// where the source has nothing (outside the previous frame's view). The planes are warped four at
// a time as one 4-channel image: OpenCV then computes each cell's source coordinates once for four
// planes, which with the merge and split costs ~60 % of warping the 41 planes of MoveNet's maps
// one by one (1.5 against 2.5 ms at a 160x120 grid, measured here). The groups run in parallel
// (cv::parallel_for_; warpAffine's own row split then runs inside each): the merges and splits
// are serial otherwise, and one call per group leaves the threads waiting between calls (160x120:
// 1.4 -> 0.8 ms, 192x144: 2.0 -> 1.2-1.5 ms on 2 cores, the same output).
void warpChannels(const cv::Mat& src, int src_first, int count, const cv::Matx23f& m, cv::Mat& dst,
                  int dst_first) {
  const int groups = (count + 3) / 4;
  cv::parallel_for_(cv::Range(0, groups), [&](const cv::Range& range) {
    for (int g = range.start; g < range.end; ++g) {
      const int first = 4 * g, n = std::min(4, count - first);
      std::vector<cv::Mat> planes, moved;
      for (int c = first; c < first + n; ++c) planes.push_back(plane(src, src_first + c));
      cv::Mat group, warped;
      cv::merge(planes, group);
      cv::warpAffine(group, warped, m, group.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
      for (int c = first; c < first + n; ++c) moved.push_back(plane(dst, dst_first + c));
      cv::split(warped, moved);  // into dst's planes (same size and type: no reallocation)
    }
  });
}

}  // namespace

cv::Matx23f cameraMotionOnGrid(const cv::Matx23f& m, const GridTransform& g) {
  // grid -> frame: p = S q + o; in grid cells the motion is q' = S^-1 (A (S q + o) + t - o).
  const float sx = g.scale_x, sy = g.scale_y, ox = g.offset_x, oy = g.offset_y;
  const cv::Point2f t(m(0, 0) * ox + m(0, 1) * oy + m(0, 2) - ox,
                      m(1, 0) * ox + m(1, 1) * oy + m(1, 2) - oy);
  return {m(0, 0), m(0, 1) * sy / sx, t.x / sx, m(1, 0) * sx / sy, m(1, 1), t.y / sy};
}

struct TemporalFlowModel::Impl {
  std::unique_ptr<detail::Network> net;
  std::string path;
  int feature_channels = 0;
  int max_grid_side = 0;
  /// The network's own stride: 1 when its field comes on its input's grid, 2 when it takes the
  /// maps averaged over 2x2 cells and returns the field on the maps' grid (the shipped model: its
  /// layers run on the coarser grid). Found by the trial run in the constructor. Pooling here,
  /// rather than in the graph, lets the camera warp move a quarter of the cells and hands the
  /// engine a quarter of the input (predict() with a camera motion, OpenVINO at max:640: 8.4 ->
  /// 6.6 and 6.0 -> 4.6 ms in two A/B runs of the same weights; models/README.md).
  int stride = 1;
  /// The last network input {1, 2 (C+17), h, w}: its second half holds features(t-1) then
  /// beliefs(t-1), at network scale (the one-frame state; kept in place, not copied out).
  cv::Mat previous;
  cv::Size previous_grid;  ///< the grid previous came on (before resampling)
  /// The network inputs: this frame's is written while the one before is kept as `previous`.
  detail::MatPool inputs;

  // The grid the field is computed on for an H x W grid of maps: at most max_grid_side a side,
  // and even sizes for a network of stride 2.
  cv::Size fieldGrid(int h, int w) const {
    auto even = [](double v) { return std::max(2, 2 * static_cast<int>(std::lround(v / 2))); };
    if (max_grid_side <= 0 || std::max(h, w) <= max_grid_side)
      return stride == 1 ? cv::Size(w, h) : cv::Size(even(w), even(h));
    const double s = static_cast<double>(max_grid_side) / std::max(h, w);
    return {even(w * s), even(h * s)};
  }

  int inputChannels() const { return 2 * (feature_channels + kNumJoints); }

  // Runs the network on an input blob and checks the output against the contract. The first
  // run (the constructor's trial) also sets the stride from the output's grid.
  cv::Mat forward(const cv::Mat& input, bool find_stride = false) {
    cv::Mat out;
    try {
      out = net->run(input, {"tff"}).front();
    } catch (const std::exception& e) {
      throw Error("TFF model " + path + ": forward failed on input " + shapeText(input) +
                  " (expected input \"input\" with " + std::to_string(inputChannels()) +
                  " channels = 2 x (" + std::to_string(feature_channels) +
                  " features + 17 beliefs), output \"tff\"): " + e.what());
    }
    if (find_stride && out.dims == 4 && out.size[2] == 2 * input.size[2] &&
        out.size[3] == 2 * input.size[3])
      stride = 2;
    if (out.dims != 4 || out.size[0] != 1 || out.size[1] != 2 * kNumJoints ||
        out.size[2] != stride * input.size[2] || out.size[3] != stride * input.size[3])
      throw Error("TFF model " + path + ": output \"tff\" has shape " + shapeText(out) +
                  ", expected {1, 34, " + std::to_string(stride * input.size[2]) + ", " +
                  std::to_string(stride * input.size[3]) +
                  "} (2 channels per COCO joint, on the input's grid" +
                  (stride == 1 ? ")" : " times its stride 2)"));
    return out;  // a copy: the engine reuses its output buffers
  }
};

TemporalFlowModel::TemporalFlowModel(const std::string& onnx_path, int feature_channels,
                                     const EngineOptions& dnn, int max_grid_side)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = onnx_path;
  impl_->feature_channels = feature_channels;
  if (max_grid_side < 0)
    throw Error("TFF model " + onnx_path +
                ": max_grid_side must be >= 0 (0 = no resampling), got " +
                std::to_string(max_grid_side));
  impl_->max_grid_side = max_grid_side;
  if (feature_channels < 1)
    throw Error("TFF model " + onnx_path +
                ": the spatial model's feature channel count must be "
                ">= 1, got " +
                std::to_string(feature_channels));
  if (onnx_path.empty() || !std::filesystem::is_regular_file(onnx_path))
    throw Error("TFF model '" + onnx_path + "' does not exist or is not a file");
  impl_->net = detail::openNetwork(onnx_path, "TFF", {"tff"}, dnn);

  const int expected = impl_->inputChannels();
  const int takes = impl_->net->inputChannels();
  if (takes > 0 && takes != expected)
    throw Error("TFF model " + onnx_path + " takes " + std::to_string(takes) +
                " input channels, but the spatial model in use needs " + std::to_string(expected) +
                " = 2 x (" + std::to_string(feature_channels) + " features + 17 beliefs)");
  // A trial run on a small grid checks the input and output names and the output layout, and
  // tells the network's stride: a field on the input's grid (1) or on twice it (2).
  const int probe[] = {1, expected, 16, 16};
  impl_->forward(cv::Mat(4, probe, CV_32F, cv::Scalar(0)), true);
}

TemporalFlowModel::~TemporalFlowModel() = default;
TemporalFlowModel::TemporalFlowModel(TemporalFlowModel&&) noexcept = default;
TemporalFlowModel& TemporalFlowModel::operator=(TemporalFlowModel&&) noexcept = default;

cv::Mat TemporalFlowModel::predict(const cv::Mat& features, const cv::Mat& beliefs,
                                   const cv::Matx23f& camera) {
  return step(features, beliefs, camera, true);
}

void TemporalFlowModel::remember(const cv::Mat& features, const cv::Mat& beliefs) {
  step(features, beliefs, cv::Matx23f(1, 0, 0, 0, 1, 0), false);
}

cv::Mat TemporalFlowModel::step(const cv::Mat& features, const cv::Mat& beliefs,
                                const cv::Matx23f& camera, bool run) {
  const int c = impl_->feature_channels;
  if (features.empty() || features.type() != CV_32F || features.dims != 4 ||
      features.size[0] != 1 || features.size[1] != c)
    throw Error("TFF model " + impl_->path + ": feature map " + shapeText(features) +
                " is not CV_32F {1, " + std::to_string(c) + ", H, W}");
  if (beliefs.empty() || beliefs.type() != CV_32F || beliefs.dims != 4 || beliefs.size[0] != 1 ||
      beliefs.size[1] != kNumJoints || beliefs.size[2] != features.size[2] ||
      beliefs.size[3] != features.size[3])
    throw Error("TFF model " + impl_->path + ": belief map " + shapeText(beliefs) +
                " is not CV_32F {1, 17, " + std::to_string(features.size[2]) + ", " +
                std::to_string(features.size[3]) + "} (the feature map's grid)");

  const int h = features.size[2], w = features.size[3];
  const int half = c + kNumJoints;
  // The field's grid (the maps', or smaller under max_grid_side) and the network's input grid,
  // smaller by its stride.
  const cv::Size field_grid = impl_->fieldGrid(h, w);
  const cv::Size net_grid(field_grid.width / impl_->stride, field_grid.height / impl_->stride);
  const bool resample = net_grid != cv::Size(w, h);
  // This frame's maps go straight into the second half of the network's input, and stay there as
  // the next frame's previous maps: no copy of them in between (at max:640 that saved two
  // copies of 41 planes of 160x120 cells per frame). Area resampling by exactly 2 is the mean of
  // 2x2 cells: the pooling a stride-2 network was trained with.
  cv::Mat input = impl_->inputs.take({1, 2 * half, net_grid.height, net_grid.width}, CV_32F);
  if (resample) {
    resizeChannels(features, input, half, cv::INTER_AREA);
    resizeChannels(beliefs, input, half + c, cv::INTER_AREA);
  } else {
    copyChannels(features, input, half);
    copyChannels(beliefs, input, half + c);
  }

  cv::Mat tff;
  if (run && !impl_->previous.empty() && impl_->previous_grid == cv::Size(w, h)) {
    // The camera motion on the network's input grid (coarser when it is pooled or resampled):
    // network cells map to the maps' cells as grid cells map to frame pixels. cv::resize aligns
    // pixel centres, so network cell q covers maps cell s q + (s - 1) / 2, s = maps / network
    // cells; a zero offset would move zooms and rotations off by (s - 1) / 2 cells times the zoom.
    const float sx = static_cast<float>(w) / net_grid.width,
                sy = static_cast<float>(h) / net_grid.height;
    const GridTransform net_to_maps{sx, sy, (sx - 1.f) / 2.f, (sy - 1.f) / 2.f};
    const cv::Matx23f moved = cameraMotionOnGrid(camera, net_to_maps);
    if (moved == cv::Matx23f(1, 0, 0, 0, 1, 0)) {
      const size_t half_floats = static_cast<size_t>(half) * net_grid.area();
      std::memcpy(input.ptr<float>(), impl_->previous.ptr<float>() + half_floats,
                  half_floats * sizeof(float));
    } else {
      warpChannels(impl_->previous, half, half, moved, input, 0);
    }
    tff = impl_->forward(input);
    if (field_grid != cv::Size(w, h)) {
      const int sizes[] = {1, tff.size[1], h, w};
      cv::Mat back(4, sizes, CV_32F);
      resizeChannels(tff, back, 0, cv::INTER_LINEAR);
      tff = back;
    }
  }
  impl_->previous = input;  // the one-frame state: this frame's maps pair with the next
  impl_->previous_grid = cv::Size(w, h);
  return tff;
}

void TemporalFlowModel::reset() {
  impl_->previous.release();
  impl_->previous_grid = cv::Size();
}
bool TemporalFlowModel::hasPrevious() const {
  return !impl_->previous.empty();
}
int TemporalFlowModel::featureChannels() const {
  return impl_->feature_channels;
}
int TemporalFlowModel::inputChannels() const {
  return impl_->inputChannels();
}
int TemporalFlowModel::maxGridSide() const {
  return impl_->max_grid_side;
}
const std::string& TemporalFlowModel::path() const {
  return impl_->path;
}

}  // namespace jointflow
