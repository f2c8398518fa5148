#include "net_spatial_model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "jointflow/error.hpp"
#include "tensor.hpp"

namespace jointflow::detail {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void checkOptions(const SpatialOptions& o) {
  if (o.scales.empty()) throw Error("spatial options: the list of inference scales is empty");
  for (float s : o.scales) {
    if (!(s > 0.f) || !std::isfinite(s) || s > 8.f) {
      throw Error("spatial options: inference scale " + std::to_string(s) + " is not in (0, 8]");
    }
  }
  if (o.max_persons < 1) {
    throw Error("spatial options: max_persons must be >= 1, got " + std::to_string(o.max_persons));
  }
  auto unit = [](float v, const char* name) {
    if (!(v >= 0.f && v <= 1.f)) {
      throw Error(std::string("spatial options: ") + name + " must be in [0, 1], got " +
                  std::to_string(v));
    }
  };
  unit(o.person_threshold, "person_threshold");
  unit(o.keypoint_threshold, "keypoint_threshold");
  unit(o.nms_threshold, "nms_threshold");
  unit(o.part_threshold, "part_threshold");
  if (!(o.nms_radius >= 0.f)) throw Error("spatial options: nms_radius must be >= 0");
}

void checkImage(const cv::Mat& image) {
  if (image.empty()) throw Error("spatial model: the image is empty");
  if (image.depth() != CV_8U || image.channels() != 3) {
    std::ostringstream msg;
    msg << "spatial model: expected an 8-bit 3-channel image (BGR or RGB), got " << image.channels()
        << " channel(s) of depth " << image.depth() << " (CV_8U = 0)";
    throw Error(msg.str());
  }
  if (image.dims != 2) throw Error("spatial model: expected a 2-D image");
}

}  // namespace

NetSpatialModel::NetSpatialModel(NetSpec spec, SpatialOptions options)
    : spec_(std::move(spec)), options_(std::move(options)) {
  checkOptions(options_);
  for (const auto& h : spec_.heads) names_.push_back(h.name);
  std::vector<std::string> required = names_;
  if (!spec_.features.empty()) required.push_back(spec_.features);
  net_ = openNetwork(options_.model_path, spec_.what, required, options_.dnn);
  if (!spec_.features.empty() &&
      std::find(names_.begin(), names_.end(), spec_.features) == names_.end()) {
    names_.push_back(spec_.features);
  }
  // One small forward pass: proves the network runs here and gives the feature channel count.
  const int side = spec_.rule.validAtLeast(64);
  const cv::Mat probe(side, side, CV_8UC3, cv::Scalar::all(0));
  try {
    Frame f;
    startScale(f, probe, PixelOrder::kRGB, 1.f);
    finishScale(f);
    const ScaleOutput& out = f.scales.front();
    feature_channels_ =
        channels(out.tensors.at(spec_.features.empty() ? names_.front() : spec_.features));
  } catch (const std::exception& e) {
    throw Error("model file " + options_.model_path + " fails to run a " + std::to_string(side) +
                "x" + std::to_string(side) + " input: " + e.what());
  }
}

cv::Mat NetSpatialModel::inputImage(Frame& f, const cv::Mat& image, float scale) {
  const auto t0 = std::chrono::steady_clock::now();
  f.box = computeLetterbox(image.size(), options_.input_size, scale, spec_.rule);
  // An image that is the network's input as it is (native size, no padding) is not copied where
  // the engine is done with it before submit() returns (cv::dnn); an asynchronous engine keeps
  // its input until the run ends, and the caller's image may be gone by then.
  const bool as_is = f.box.input == image.size() && f.box.content == cv::Rect({0, 0}, image.size());
  cv::Mat input = image;
  if (!as_is || net_->asynchronous()) {
    input = images_.take({f.box.input.height, f.box.input.width}, image.type());
    applyLetterbox(image, f.box, input);
  }
  f.timings.preprocess_ms += msSince(t0);
  return input;
}

void NetSpatialModel::launch(Frame& f, const cv::Mat& input, PixelOrder order) {
  const auto t0 = std::chrono::steady_clock::now();
  net_->setImage(input, {order == PixelOrder::kBGR, spec_.input_scale, spec_.input_mean});
  f.timings.preprocess_ms += msSince(t0);  // the blob, where the engine makes one on the CPU
  f.started = std::chrono::steady_clock::now();
  net_->start();
  f.in_flight = true;
}

Letterbox NetSpatialModel::startScale(Frame& f, const cv::Mat& image, PixelOrder order,
                                      float scale) {
  launch(f, inputImage(f, image, scale), order);
  return f.box;
}

void NetSpatialModel::finishScale(Frame& f) {
  std::vector<cv::Mat> outs = net_->wait(names_);
  f.in_flight = false;
  // Time on the engine, from the start of the run to its outputs in hand: with an asynchronous
  // engine it includes whatever ran meanwhile.
  f.timings.forward_ms += msSince(f.started);
  f.scales.push_back(readOutputs(f.box, std::move(outs), f));
}

NetSpatialModel::ScaleOutput NetSpatialModel::readOutputs(const Letterbox& box,
                                                          std::vector<cv::Mat> outs, Frame& f) {
  const auto t0 = std::chrono::steady_clock::now();
  ScaleOutput out;
  for (size_t i = 0; i < names_.size(); ++i) out.tensors[names_[i]] = std::move(outs[i]);

  const cv::Mat& first = out.tensors.at(names_.front());
  checkTensor(first, "output " + names_.front() + " of " + options_.model_path, -1, 1, {});
  out.grid = {cols(first), rows(first)};
  if (spec_.grid_of_input) {
    const cv::Size expected(spec_.grid_of_input(box.input.width),
                            spec_.grid_of_input(box.input.height));
    if (expected != out.grid) {
      std::ostringstream msg;
      msg << "model file " << options_.model_path << ": output " << names_.front() << " is "
          << out.grid.height << "x" << out.grid.width << " for a " << box.input.height << "x"
          << box.input.width << " input, expected " << expected.height << "x" << expected.width;
      throw Error(msg.str());
    }
  }
  for (const auto& [name, t] : out.tensors) {
    checkTensor(t, "output " + name + " of " + options_.model_path, -1, 1, out.grid);
  }
  out.stride =
      spec_.stride > 0.f ? spec_.stride : static_cast<float>(box.input.height) / out.grid.height;
  out.grid_to_frame = box.gridToFrame(out.stride);
  prepare(out.tensors);
  f.timings.decode_ms += msSince(t0);
  return out;
}

void NetSpatialModel::drain(Frame& f) {
  if (!f.in_flight) return;
  f.in_flight = false;
  try {
    net_->wait(names_);
  } catch (...) {
    // The frame is dropped with the error that brought us here.
  }
}

int NetSpatialModel::pending() const {
  return static_cast<int>(frames_.size());
}

void NetSpatialModel::submit(const cv::Mat& image, PixelOrder order) {
  checkImage(image);
  if (frames_.size() >= 2)
    throw Error("spatial model " + options_.model_path +
                ": submit() with two frames pending; collect() one first");
  Frame f;
  f.size = image.size();
  auto failed = [&](const cv::Exception& e) {
    return Error("spatial model " + options_.model_path + " failed on a " +
                 std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                 " image: " + e.what());
  };
  // The first scale's letterbox is made before the previous frame's run is waited for: on an
  // asynchronous engine it overlaps that run.
  cv::Mat input;
  try {
    input = inputImage(f, image, options_.scales.front());
  } catch (const cv::Exception& e) {
    throw failed(e);
  }
  // Where the engine takes two runs of a stream (OpenVINO) and the frame has one scale, this
  // frame starts now, queued behind the previous frame's run, whose outputs collect() reads while
  // this one runs. Else the previous frame's outputs are fetched first (kept until collect()).
  // Why: reading them (MoveNet's 114 maps turned planar, 1.3 ms at max:640) between two runs left
  // the engine idle; docs/benchmarks.md, the element's overhead.
  const bool queued = net_->maxRuns() >= 2 && options_.scales.size() == 1;
  if (!queued && !frames_.empty() && frames_.back().in_flight) finishScale(frames_.back());
  try {
    // All scales but the last run here; the last one is left running on the engine.
    for (size_t i = 0; i < options_.scales.size(); ++i) {
      if (i > 0) input = inputImage(f, image, options_.scales[i]);
      launch(f, input, order);
      if (i + 1 < options_.scales.size()) finishScale(f);
    }
  } catch (const cv::Exception& e) {
    drain(f);
    throw failed(e);
  } catch (...) {
    drain(f);
    throw;
  }
  frames_.push_back(std::move(f));
}

SpatialResult NetSpatialModel::collect() {
  if (frames_.empty())
    throw Error("spatial model " + options_.model_path + ": collect() without submit()");
  Frame f = std::move(frames_.front());
  frames_.erase(frames_.begin());
  if (f.in_flight) finishScale(f);
  return fuse(f);
}

SpatialResult NetSpatialModel::estimate(const cv::Mat& image, PixelOrder order) {
  if (!frames_.empty())
    throw Error("spatial model " + options_.model_path +
                ": estimate() while frames are pending; collect() them first");
  submit(image, order);
  return collect();
}

SpatialResult NetSpatialModel::fuse(Frame& f) {
  std::vector<ScaleOutput>& scales = f.scales;
  const auto t0 = std::chrono::steady_clock::now();
  // Reference grid: the scale closest to 1 (the larger one on a tie).
  size_t ref = 0;
  for (size_t i = 1; i < scales.size(); ++i) {
    const float di = std::abs(std::log(options_.scales[i])),
                dr = std::abs(std::log(options_.scales[ref]));
    if (di < dr || (di == dr && options_.scales[i] > options_.scales[ref])) ref = i;
  }
  const ScaleOutput& r = scales[ref];

  Tensors fused = r.tensors;
  if (scales.size() > 1) {
    for (const auto& head : spec_.heads) {
      cv::Mat sum = r.tensors.at(head.name).clone();
      for (size_t i = 0; i < scales.size(); ++i) {
        if (i == ref) continue;
        sum += resampleToGrid(scales[i].tensors.at(head.name), scales[i].grid_to_frame,
                              r.grid_to_frame, r.grid, head.displacements);
      }
      fused[head.name] = sum / static_cast<double>(scales.size());
    }
  }

  SpatialResult result;
  result.frame_size = f.size;
  result.grid_to_frame = r.grid_to_frame;
  result.features = spec_.features.empty() ? cv::Mat() : r.tensors.at(spec_.features);
  result.beliefs = beliefs(fused);

  Poses poses = decode(fused, r.stride);
  const GridTransform& t = r.grid_to_frame;
  for (auto& pose : poses) {
    if (pose.score < options_.person_threshold) continue;
    for (auto& k : pose.keypoints) {
      const cv::Point2f p = t.toFrame({k.x, k.y});
      k.x = p.x, k.y = p.y;
      if (k.score < options_.keypoint_threshold) k.score = 0.f;
    }
    const cv::Point2f tl = t.toFrame({pose.box.x, pose.box.y});
    const cv::Point2f br = t.toFrame({pose.box.x + pose.box.w, pose.box.y + pose.box.h});
    pose.box = {tl.x, tl.y, br.x - tl.x, br.y - tl.y};
    result.poses.push_back(pose);
  }
  std::stable_sort(result.poses.begin(), result.poses.end(),
                   [](const Pose& a, const Pose& b) { return a.score > b.score; });
  f.timings.decode_ms += msSince(t0);
  timings_ = f.timings;
  if (static_cast<int>(result.poses.size()) > options_.max_persons)
    result.poses.resize(options_.max_persons);
  return result;
}

}  // namespace jointflow::detail
