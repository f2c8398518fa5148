#include "visit_sheet.hpp"

#include <algorithm>
#include <cstdio>
#include <map>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "jointflow/error.hpp"

namespace jointflow::bench {
namespace {

constexpr int kTileHeight = 120;  // px of a crop on the sheet
constexpr int kLabel = 30;        // px of the two label lines above a crop
constexpr int kMaxTiles = 8;      // visits shown per id

struct Visit {
  int first = 0, last = 0;  ///< frames
  int shown = 0;            ///< the frame cropped
};

// A visit is cropped a few frames after it starts (a person coming in is cut by the border on
// their first frames), or in its middle where it is short.
int shownFrame(const Visit& v) {
  return std::min(v.first + 8, (v.first + v.last) / 2);
}

}  // namespace

void writeVisitSheet(const std::string& video, const std::vector<std::vector<TrackedPose>>& frames,
                     double fps, const std::string& path) {
  const int gap = std::max(1, static_cast<int>(fps + 0.5));  // frames: a second
  std::map<std::int64_t, std::vector<Visit>> visits;
  for (int f = 0; f < static_cast<int>(frames.size()); ++f)
    for (const TrackedPose& p : frames[f]) {
      auto& v = visits[p.track_id];
      if (v.empty() || f - v.back().last > gap) v.push_back({f, f, 0});
      v.back().last = f;
    }
  std::map<int, std::vector<std::pair<std::int64_t, int>>> wanted;  // frame -> (id, visit)
  for (auto& [id, list] : visits)
    for (size_t i = 0; i < list.size(); ++i) {
      list[i].shown = shownFrame(list[i]);
      wanted[list[i].shown].push_back({id, static_cast<int>(i)});
    }
  std::map<std::pair<std::int64_t, int>, cv::Mat> crops;
  cv::VideoCapture capture(video);
  if (!capture.isOpened()) throw Error(video + ": cannot open the video for the visit sheet");
  cv::Mat frame;
  for (int f = 0; f < static_cast<int>(frames.size()) && capture.read(frame); ++f) {
    const auto it = wanted.find(f);
    if (it == wanted.end()) continue;
    for (const auto& [id, i] : it->second) {
      Box b;  // of the person on that frame
      for (const TrackedPose& p : frames[f])
        if (p.track_id == id) b = p.pose.keypointBox(0.2f);
      // The keypoints' box, widened by a tenth of its height each side (heads and feet).
      const int m = static_cast<int>(0.1f * b.h);
      const cv::Rect r = cv::Rect(static_cast<int>(b.x) - m, static_cast<int>(b.y) - m,
                                  static_cast<int>(b.w) + 2 * m, static_cast<int>(b.h) + 2 * m) &
                         cv::Rect(0, 0, frame.cols, frame.rows);
      if (r.area() == 0) continue;
      cv::Mat crop;
      cv::resize(frame(r), crop,
                 {std::max(1, r.width * kTileHeight / std::max(1, r.height)), kTileHeight});
      crops[{id, i}] = crop;
    }
  }
  // Ids are labelled from 1 in the order they were first shown (the order of the ids themselves):
  // a tracker reused across runs keeps counting, and the sheet should read like a fresh one.
  std::vector<cv::Mat> rows;
  for (const auto& [id, list] : visits) {
    const int label = static_cast<int>(rows.size()) + 1;
    std::vector<cv::Mat> tiles;
    for (int i = 0; i < std::min<int>(kMaxTiles, static_cast<int>(list.size())); ++i) {
      const auto c = crops.find({id, i});
      const int w = std::max(72, c == crops.end() ? 0 : c->second.cols);
      cv::Mat tile(kTileHeight + kLabel, w + 4, CV_8UC3, cv::Scalar(255, 255, 255));
      if (c != crops.end())
        c->second.copyTo(tile(cv::Rect(0, kLabel, c->second.cols, kTileHeight)));
      char when[32];
      std::snprintf(when, sizeof when, "%.1f-%.1f s", list[i].first / fps, list[i].last / fps);
      cv::putText(tile, "id " + std::to_string(label), {2, 12}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
                  {0, 0, 0}, 1, cv::LINE_AA);
      cv::putText(tile, when, {2, kLabel - 5}, cv::FONT_HERSHEY_SIMPLEX, 0.35, {0, 0, 0}, 1,
                  cv::LINE_AA);
      tiles.push_back(tile);
    }
    cv::Mat row;
    cv::hconcat(tiles, row);
    rows.push_back(row);
  }
  if (rows.empty()) throw Error("visit sheet: no tracks to draw");
  int width = 0;
  for (const cv::Mat& r : rows) width = std::max(width, r.cols);
  for (cv::Mat& r : rows)
    cv::copyMakeBorder(r, r, 0, 2, 0, width - r.cols, cv::BORDER_CONSTANT, {255, 255, 255});
  cv::Mat sheet;
  cv::vconcat(rows, sheet);
  if (!cv::imwrite(path, sheet)) throw Error(path + ": cannot write the visit sheet");
}

}  // namespace jointflow::bench
