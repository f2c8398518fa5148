#include "net_spatial_model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "jointflow/error.hpp"
#include "jointflow/tiling.hpp"
#include "tensor.hpp"

namespace jointflow::detail {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
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

NetSpatialModel::NetSpatialModel(NetSpec spec, SpatialOptions options, const EngineOptions& engine)
    : spec_(std::move(spec)), options_(std::move(options)) {
  validateSpatialOptions(options_);
  for (const auto& h : spec_.heads) names_.push_back(h.name);
  std::vector<std::string> required = names_;
  if (!spec_.features.empty()) required.push_back(spec_.features);
  net_ = openNetwork(options_.model_path, spec_.what, required, engine);
  if (!spec_.features.empty() &&
      std::find(names_.begin(), names_.end(), spec_.features) == names_.end()) {
    names_.push_back(spec_.features);
  }
  // One small forward pass: proves the network runs here and gives the feature channel count.
  const int side = spec_.rule.validAtLeast(64);
  const cv::Mat probe(side, side, CV_8UC3, cv::Scalar::all(0));
  try {
    Frame f;
    launch(f, inputImage(f, probe, {{0, 0, side, side}, options_.input_size, 1.f}),
           PixelOrder::kRGB);
    finishScale(f);
    const ScaleOutput& out = f.scales.front();
    feature_channels_ =
        channels(out.tensors.at(spec_.features.empty() ? names_.front() : spec_.features));
  } catch (const std::exception& e) {
    throw Error("model file " + options_.model_path + " fails to run a " + std::to_string(side) +
                "x" + std::to_string(side) + " input: " + e.what());
  }
}

bool NetSpatialModel::tiledAt(cv::Size size) const {
  const TileOptions& tiles = options_.tiles;
  if (!tiles.enabled()) return false;
  if (!tiles.full_frame) return true;
  const std::vector<cv::Rect> layout = tileLayout(size, tiles.size, tiles.overlap);
  if (layout.size() != 1 || layout.front() != cv::Rect({0, 0}, size)) return true;
  const Letterbox whole = computeLetterbox(size, options_.input_size, 1.f, spec_.rule);
  return static_cast<float>(whole.content.width) < tiles.scale * static_cast<float>(size.width);
}

std::vector<NetSpatialModel::View> NetSpatialModel::views(cv::Size size, bool tiled) const {
  const cv::Rect whole({0, 0}, size);
  std::vector<View> views;
  const TileOptions& tiles = options_.tiles;
  if (!tiled) {
    for (float s : options_.scales) views.push_back({whole, options_.input_size, s});
    return views;
  }
  if (tiles.full_frame) views.push_back({whole, options_.input_size, 1.f});
  InputSize native;
  native.mode = InputSize::Mode::kNative;
  for (const cv::Rect& t : tileLayout(size, tiles.size, tiles.overlap))
    views.push_back({t, native, tiles.scale});
  return views;
}

cv::Mat NetSpatialModel::inputImage(Frame& f, const cv::Mat& image, const View& view) {
  const auto t0 = std::chrono::steady_clock::now();
  const cv::Mat part = view.crop == cv::Rect({0, 0}, image.size()) ? image : image(view.crop);
  f.box = computeLetterbox(part.size(), view.policy, view.scale, spec_.rule);
  f.crop = view.crop;
  // An image that is the network's input as it is (native size, no padding) is not copied where
  // the engine is done with it before submit() returns (cv::dnn); an asynchronous engine keeps
  // its input until the run ends, and the caller's image may be gone by then. A tile is a view
  // into the frame, not a continuous image: always copied.
  const bool as_is = part.data == image.data && part.size() == image.size() &&
                     f.box.input == image.size() && f.box.content == cv::Rect({0, 0}, image.size());
  cv::Mat input = image;
  if (!as_is || net_->asynchronous()) {
    input = images_.take({f.box.input.height, f.box.input.width}, image.type());
    applyLetterbox(part, f.box, input);
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
  // A tile's grid maps to the tile; the tile lies at its crop's corner in the frame.
  out.grid_to_frame.offset_x += static_cast<float>(f.crop.x);
  out.grid_to_frame.offset_y += static_cast<float>(f.crop.y);
  out.crop = f.crop;
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
  f.tiled = tiledAt(f.size);
  const std::vector<View> runs = views(f.size, f.tiled);
  f.timings.runs = static_cast<int>(runs.size());
  auto failed = [&](const cv::Exception& e) {
    return Error("spatial model " + options_.model_path + " failed on a " +
                 std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                 " image: " + e.what());
  };
  // The first view's letterbox is made before the previous frame's run is waited for: on an
  // asynchronous engine it overlaps that run.
  cv::Mat input;
  try {
    input = inputImage(f, image, runs.front());
  } catch (const cv::Exception& e) {
    throw failed(e);
  }
  // Where the engine takes two runs of a stream (OpenVINO) and the frame has one scale, this
  // frame starts now, queued behind the previous frame's run, whose outputs collect() reads while
  // this one runs. Else the previous frame's outputs are fetched first (kept until collect()).
  // Why: reading them (MoveNet's 114 maps turned planar, 1.3 ms at max:640) between two runs left
  // the engine idle; docs/benchmarks.md, the element's overhead.
  const bool queued = net_->maxRuns() >= 2 && runs.size() == 1;
  if (!queued && !frames_.empty() && frames_.back().in_flight) finishScale(frames_.back());
  try {
    // All views but the last run here; the last one is left running on the engine.
    for (size_t i = 0; i < runs.size(); ++i) {
      if (i > 0) input = inputImage(f, image, runs[i]);
      launch(f, input, order);
      if (i + 1 < runs.size()) finishScale(f);
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

Poses NetSpatialModel::toFrame(Poses poses, const GridTransform& t) const {
  Poses out;
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
    out.push_back(pose);
  }
  return out;
}

SpatialResult NetSpatialModel::fuse(Frame& f) {
  if (f.tiled) return fuseTiles(f);
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

  result.poses = toFrame(decode(fused, r.stride), r.grid_to_frame);
  std::stable_sort(result.poses.begin(), result.poses.end(),
                   [](const Pose& a, const Pose& b) { return a.score > b.score; });
  f.timings.decode_ms += msSince(t0);
  timings_ = f.timings;
  if (static_cast<int>(result.poses.size()) > options_.max_persons)
    result.poses.resize(options_.max_persons);
  return result;
}

SpatialResult NetSpatialModel::fuseTiles(Frame& f) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<TileRun> runs;
  const ScaleOutput* whole = nullptr;
  for (const ScaleOutput& o : f.scales) {
    runs.push_back(
        {o.crop, o.grid_to_frame.scale_x, toFrame(decode(o.tensors, o.stride), o.grid_to_frame)});
    if (o.crop == cv::Rect({0, 0}, f.size) && options_.tiles.full_frame && !whole) whole = &o;
  }
  TileMergeOptions merge;
  merge.max_persons = options_.max_persons;
  SpatialResult result;
  result.frame_size = f.size;
  result.poses = mergeTileRuns(runs, f.size, merge);
  // The maps of the TFF network and of re-identification: the whole frame's, on the grid and at
  // the scale of people the TFF network was trained on; without that pass the tiles' maps
  // stitched onto one grid over the frame.
  if (whole) {
    result.grid_to_frame = whole->grid_to_frame;
    result.features = spec_.features.empty() ? cv::Mat() : whole->tensors.at(spec_.features);
    result.beliefs = beliefs(whole->tensors);
  } else {
    stitchMaps(f, result);
  }
  f.timings.decode_ms += msSince(t0);
  timings_ = f.timings;
  return result;
}

void NetSpatialModel::stitchMaps(const Frame& f, SpatialResult& result) const {
  std::vector<cv::Rect> tiles;
  std::vector<GridTransform> grids;
  std::vector<cv::Mat> features, beliefs_of;
  for (const ScaleOutput& o : f.scales) {
    tiles.push_back(o.crop);
    grids.push_back(o.grid_to_frame);
    if (!spec_.features.empty()) features.push_back(o.tensors.at(spec_.features));
    beliefs_of.push_back(beliefs(o.tensors));
  }
  InputSize native;
  native.mode = InputSize::Mode::kNative;
  const Letterbox whole = computeLetterbox(f.size, native, options_.tiles.scale, spec_.rule);
  const float stride = f.scales.front().stride;
  const cv::Size grid = spec_.grid_of_input
                            ? cv::Size(spec_.grid_of_input(whole.input.width),
                                       spec_.grid_of_input(whole.input.height))
                            : cv::Size(static_cast<int>(whole.input.width / stride),
                                       static_cast<int>(whole.input.height / stride));
  result.grid_to_frame = whole.gridToFrame(stride);
  if (!features.empty())
    result.features = stitchTileMaps(features, grids, tiles, result.grid_to_frame, grid);
  result.beliefs = stitchTileMaps(beliefs_of, grids, tiles, result.grid_to_frame, grid);
}

}  // namespace jointflow::detail
