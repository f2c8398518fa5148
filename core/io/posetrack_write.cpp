// PoseTrack 2017 and 2018 writers (format description in jointflow/posetrack.hpp).
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "jointflow/error.hpp"
#include "jointflow/posetrack.hpp"

namespace jointflow::posetrack {

using nlohmann::json;

namespace {

/// PoseTrack 2018 skeleton (1-based keypoint indices), as the official files list it.
const json kSkeleton18 = json::parse(
    "[[16,14],[14,12],[17,15],[15,13],[12,13],[6,12],[7,13],[6,7],[6,8],[7,9],[8,10],[9,11],"
    "[2,3],[1,2],[1,3],[2,4],[3,5],[4,6],[5,7]]");

/// poseval refuses files whose track ids are missing, outside 0..999 or repeated in a frame.
void checkTrackIds(const Sequence& seq) {
  for (std::size_t f = 0; f < seq.frames.size(); ++f) {
    std::set<std::int64_t> seen;
    for (const Person& p : seq.frames[f].people) {
      const std::string where = seq.name + " frame " + std::to_string(f) + ": ";
      if (!p.track_id) throw Error(where + "a person has no track id (PoseTrack needs one)");
      if (*p.track_id < 0 || *p.track_id > 999) {
        throw Error(where + "track id " + std::to_string(*p.track_id) +
                    " is outside 0..999 (use TrackIdMap)");
      }
      if (!seen.insert(*p.track_id).second) {
        throw Error(where + "track id " + std::to_string(*p.track_id) + " appears twice");
      }
    }
  }
}

bool anyScore(const Person& p) {
  for (const auto& j : p.joints) {
    if (j && j->score) return true;
  }
  return false;
}

json annolist2017(const Sequence& seq) {
  json annolist = json::array();
  for (const Frame& frame : seq.frames) {
    json rects = json::array();
    for (const Person& p : frame.people) {
      json rect;
      rect["track_id"] = {*p.track_id};
      if (p.head_box) {
        rect["x1"] = {p.head_box->x1};
        rect["y1"] = {p.head_box->y1};
        rect["x2"] = {p.head_box->x2};
        rect["y2"] = {p.head_box->y2};
      }
      if (p.score) rect["score"] = {*p.score};
      if (p.has_annopoints) {
        json points = json::array();
        for (int j = 0; j < kNumPoseTrackJoints; ++j) {
          if (!p.joints[j]) continue;
          const PoseTrackPoint& pt = *p.joints[j];
          json point = {{"id", {j}}, {"x", {pt.x}}, {"y", {pt.y}}, {"is_visible", {pt.visible}}};
          if (pt.score) point["score"] = {*pt.score};
          points.push_back(point);
        }
        rect["annopoints"] = json::array({json{{"point", points}}});
      }
      rects.push_back(rect);
    }
    json entry = {{"image", json::array({json{{"name", frame.file_name}}})},
                  {"imgnum", {frame.frame_id}},
                  {"is_labeled", {frame.is_labeled ? 1 : 0}},
                  {"annorect", rects}};
    if (!frame.ignore_regions.empty()) {
      json regions = json::array();
      for (const Polygon& poly : frame.ignore_regions) {
        json pts = json::array();
        for (std::size_t i = 0; i < poly.x.size(); ++i) {
          pts.push_back({{"x", {poly.x[i]}}, {"y", {poly.y[i]}}});
        }
        regions.push_back({{"point", pts}});
      }
      entry["ignore_regions"] = regions;
    }
    annolist.push_back(entry);
  }
  return json{{"annolist", annolist}};
}

json coco2018(const Sequence& seq) {
  json images = json::array(), annotations = json::array();
  for (const Frame& frame : seq.frames) {
    json image = {{"file_name", frame.file_name}, {"id", frame.image_id},
                  {"frame_id", frame.frame_id},   {"vid_id", seq.vid_id},
                  {"nframes", seq.frames.size()}, {"is_labeled", frame.is_labeled}};
    if (!frame.ignore_regions.empty()) {
      json xs = json::array(), ys = json::array();
      for (const Polygon& poly : frame.ignore_regions) {
        xs.push_back(poly.x);
        ys.push_back(poly.y);
      }
      image["ignore_regions_x"] = xs;
      image["ignore_regions_y"] = ys;
    }
    images.push_back(image);
    for (std::size_t i = 0; i < frame.people.size(); ++i) {
      const Person& p = frame.people[i];
      const bool scores = anyScore(p);
      json keypoints = json::array(), score_list = json::array();
      for (std::string_view name : kPoseTrack18KeypointNames) {
        const std::optional<int> id = poseTrackJointFromName(name);
        const bool present = id && p.joints[*id];
        const PoseTrackPoint pt = present ? *p.joints[*id] : PoseTrackPoint{0.0, 0.0, 0.0, 0};
        keypoints.push_back(pt.x);
        keypoints.push_back(pt.y);
        keypoints.push_back(present ? pt.visible : 0);
        if (scores) score_list.push_back(pt.score.value_or(0.0));
      }
      json ann = {{"id", frame.image_id * 100 + static_cast<std::int64_t>(i)},
                  {"image_id", frame.image_id},
                  {"category_id", 1},
                  {"track_id", *p.track_id},
                  {"keypoints", keypoints},
                  {"scores", score_list}};
      if (p.head_box) {
        const HeadBox& b = *p.head_box;
        ann["bbox_head"] = {b.x1, b.y1, b.x2 - b.x1, b.y2 - b.y1};
      }
      if (p.score) ann["score"] = *p.score;
      annotations.push_back(ann);
    }
  }
  json category = {{"supercategory", "person"},
                   {"id", 1},
                   {"name", "person"},
                   {"keypoints", kPoseTrack18KeypointNames},
                   {"skeleton", kSkeleton18}};
  return json{
      {"images", images}, {"annotations", annotations}, {"categories", json::array({category})}};
}

}  // namespace

std::string toJson(const Sequence& sequence, Format format) {
  checkTrackIds(sequence);
  const json doc = format == Format::k2017 ? annolist2017(sequence) : coco2018(sequence);
  return doc.dump();
}

void writeSequence(const Sequence& sequence, const std::string& path, Format format) {
  const std::string text = toJson(sequence, format);
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error(path + ": cannot create the PoseTrack file");
  out << text;
  if (!out.flush()) throw Error(path + ": writing the PoseTrack file failed");
}

}  // namespace jointflow::posetrack
