// PoseTrack 2017 and 2018 readers (format description in jointflow/posetrack.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "jointflow/error.hpp"
#include "jointflow/posetrack.hpp"
#include "json_fields.hpp"

namespace jointflow::posetrack {

namespace fs = std::filesystem;
using io::Field;

namespace {

int jointId(const Field& f) {
  const std::int64_t id = f.integer();
  if (id < 0 || id >= kNumPoseTrackJoints) f.fail("a PoseTrack joint id in 0..14");
  return static_cast<int>(id);
}

std::optional<double> optionalNumber(const Field& obj, const char* key, bool wrapped) {
  if (!obj.has(key)) return std::nullopt;
  const Field f = obj[key];
  return wrapped ? f.unwrapped().number() : f.number();
}

std::vector<Polygon> readIgnoreRegions2017(const Field& regions) {
  std::vector<Polygon> out;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const Field points = regions[r]["point"];
    Polygon poly;
    for (std::size_t p = 0; p < points.size(); ++p) {
      poly.x.push_back(points[p]["x"].unwrapped().number());
      poly.y.push_back(points[p]["y"].unwrapped().number());
    }
    out.push_back(std::move(poly));
  }
  return out;
}

Person readPerson2017(const Field& rect) {
  Person person;
  if (rect.has("track_id")) person.track_id = rect["track_id"].unwrapped().integer();
  person.score = optionalNumber(rect, "score", true);
  const bool any_box = rect.has("x1") || rect.has("y1") || rect.has("x2") || rect.has("y2");
  if (any_box) {  // all four or none: a partial box is a broken file
    person.head_box = HeadBox{rect["x1"].unwrapped().number(), rect["y1"].unwrapped().number(),
                              rect["x2"].unwrapped().number(), rect["y2"].unwrapped().number()};
  }
  // poseval keeps a person only when "annopoints" is a non-empty list whose first element has
  // "point" (its rectHasPoints); the others are dropped before scoring.
  person.has_annopoints = rect.has("annopoints") && rect["annopoints"].size() > 0 &&
                          rect["annopoints"][std::size_t{0}].has("point");
  if (!person.has_annopoints) return person;
  const Field points = rect["annopoints"][std::size_t{0}]["point"];
  for (std::size_t p = 0; p < points.size(); ++p) {
    const Field point = points[p];
    const int id = jointId(point["id"].unwrapped());
    if (person.joints[id]) continue;  // poseval takes the first point with an id
    PoseTrackPoint pt;
    pt.x = point["x"].unwrapped().number();
    pt.y = point["y"].unwrapped().number();
    pt.score = optionalNumber(point, "score", true);
    if (point.has("is_visible")) pt.visible = point["is_visible"].unwrapped().boolean() ? 1 : 0;
    person.joints[id] = pt;
  }
  return person;
}

Sequence read2017(const Field& root, Sequence seq) {
  seq.format = Format::k2017;
  const Field annolist = root["annolist"];
  for (std::size_t i = 0; i < annolist.size(); ++i) {
    const Field entry = annolist[i];
    Frame frame;
    frame.file_name = entry["image"].unwrapped()["name"].unwrapped().string();
    frame.image_id = static_cast<std::int64_t>(i);
    frame.frame_id =
        entry.has("imgnum") ? entry["imgnum"].unwrapped().integer() : static_cast<std::int64_t>(i);
    const Field rects = entry["annorect"];
    for (std::size_t r = 0; r < rects.size(); ++r) frame.people.push_back(readPerson2017(rects[r]));
    frame.is_labeled =
        entry.has("is_labeled") ? entry["is_labeled"].unwrapped().boolean() : !frame.people.empty();
    if (entry.has("ignore_regions"))
      frame.ignore_regions = readIgnoreRegions2017(entry["ignore_regions"]);
    seq.frames.push_back(std::move(frame));
  }
  return seq;
}

/// Column of each keypoint in a 2018 file -> PoseTrack id (or -1 for the unscored ears).
std::vector<int> readKeypointOrder(const Field& root) {
  const Field categories = root["categories"];
  if (categories.size() == 0) categories.fail("a non-empty list of categories");
  const Field names = categories[std::size_t{0}]["keypoints"];
  const std::size_t n = names.size();
  if (n != 15 && n != 17) names.fail("15 or 17 keypoint names");
  std::vector<int> order(n, -1);
  std::array<bool, kNumPoseTrackJoints> seen{};
  for (std::size_t k = 0; k < n; ++k) {
    const std::string name = names[k].string();
    if (auto id = poseTrackJointFromName(name)) {
      order[k] = *id;
      seen[*id] = true;
    }
  }
  for (int j = 0; j < kNumPoseTrackJoints; ++j) {
    if (!seen[j]) {
      const std::string expected =
          j == kPtNeck ? "head_bottom" : std::string(kPoseTrackJointNames[j]);
      names.fail("the keypoint name \"" + expected + "\" among the names");
    }
  }
  return order;
}

std::vector<Polygon> readIgnoreRegions2018(const Field& image) {
  std::vector<Polygon> out;
  if (!image.has("ignore_regions_x") && !image.has("ignore_regions_y")) return out;
  const Field xs = image["ignore_regions_x"];
  const Field ys = image["ignore_regions_y"];
  if (xs.size() != ys.size()) ys.fail(std::to_string(xs.size()) + " regions like ignore_regions_x");
  for (std::size_t r = 0; r < xs.size(); ++r) {
    const Field rx = xs[r], ry = ys[r];
    if (rx.size() != ry.size()) ry.fail(std::to_string(rx.size()) + " coordinates like its x");
    Polygon poly;
    for (std::size_t p = 0; p < rx.size(); ++p) {
      poly.x.push_back(rx[p].number());
      poly.y.push_back(ry[p].number());
    }
    out.push_back(std::move(poly));
  }
  return out;
}

Person readPerson2018(const Field& ann, const std::vector<int>& order) {
  Person person;
  person.track_id = ann["track_id"].integer();
  person.score = optionalNumber(ann, "score", false);
  if (ann.has("bbox_head")) {
    const Field b = ann["bbox_head"];
    if (b.size() != 4) b.fail("4 numbers (x, y, w, h)");
    auto v = [&](std::size_t i) { return b[i].number(); };
    person.head_box = HeadBox{v(0), v(1), v(0) + v(2), v(1) + v(3)};
    // Each number is finite, but x + w can overflow (1e308 + 1e308): such a box would be written
    // back as null (tests/hardening/fuzz_regressions/head_box_overflow.json).
    if (!std::isfinite(person.head_box->x2) || !std::isfinite(person.head_box->y2))
      b.fail("a box whose corners x + w and y + h are finite numbers");
  }
  const Field kp = ann["keypoints"];
  const std::size_t k = order.size();
  if (kp.size() != 3 * k) {
    kp.reject("expected " + std::to_string(3 * k) + " numbers (" + std::to_string(k) +
              " x 3), got " + std::to_string(kp.size()));
  }
  // poseval uses the scores only when the list is non-empty.
  const bool has_scores = ann.has("scores") && ann["scores"].size() > 0;
  if (has_scores && ann["scores"].size() != k) {
    ann["scores"].reject("expected " + std::to_string(k) + " scores (one per keypoint), got " +
                         std::to_string(ann["scores"].size()));
  }
  for (std::size_t c = 0; c < k; ++c) {
    const double x = kp[3 * c].number(), y = kp[3 * c + 1].number(), v = kp[3 * c + 2].number();
    const int id = order[c];
    if (id < 0) continue;
    // An unannotated keypoint is stored as (0, 0, 0); poseval's converter skips exactly those.
    if (x == 0.0 && y == 0.0 && v == 0.0) continue;
    PoseTrackPoint pt{x, y, std::nullopt, v != 0.0 ? 1 : 0};
    if (has_scores) pt.score = ann["scores"][c].number();
    person.joints[id] = pt;
  }
  return person;
}

Sequence read2018(const Field& root, Sequence seq) {
  seq.format = Format::k2018;
  const std::vector<int> order = readKeypointOrder(root);
  const Field images = root["images"];
  std::unordered_map<std::int64_t, std::size_t> frame_of_image;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const Field image = images[i];
    Frame frame;
    frame.file_name = image["file_name"].string();
    frame.image_id = image["id"].integer();
    frame.frame_id = image.has("frame_id") ? image["frame_id"].integer() : frame.image_id;
    if (image.has("is_labeled")) frame.is_labeled = image["is_labeled"].boolean();
    frame.ignore_regions = readIgnoreRegions2018(image);
    if (seq.vid_id.empty() && image.has("vid_id")) {
      const Field v = image["vid_id"];
      seq.vid_id = v.json().is_string() ? v.string() : std::to_string(v.integer());
    }
    if (!frame_of_image.emplace(frame.image_id, seq.frames.size()).second) {
      image["id"].fail("an image id not used by an earlier image");
    }
    seq.frames.push_back(std::move(frame));
  }
  const Field annotations = root["annotations"];
  for (std::size_t a = 0; a < annotations.size(); ++a) {
    const Field ann = annotations[a];
    const Field image_id = ann["image_id"];
    auto it = frame_of_image.find(image_id.integer());
    if (it == frame_of_image.end()) image_id.fail("the id of an image in \"images\"");
    seq.frames[it->second].people.push_back(readPerson2018(ann, order));
  }
  return seq;
}

}  // namespace

Sequence parseSequence(const std::string& json_text, const std::string& source) {
  const nlohmann::json doc = io::parseJson(json_text, source);
  const Field root(doc, source, "");
  if (!doc.is_object()) root.fail("an object with \"annolist\" (2017) or \"images\" (2018)");
  Sequence seq;
  seq.source = source;
  seq.name = fs::path(source).stem().string();
  if (doc.contains("annolist")) return read2017(root, std::move(seq));
  if (doc.contains("images")) return read2018(root, std::move(seq));
  throw Error(source + ": neither \"annolist\" (PoseTrack 2017) nor \"images\" (PoseTrack 2018) " +
              "at the top level: not a PoseTrack file");
}

Sequence readSequence(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the PoseTrack file");
  std::ostringstream text;
  text << in.rdbuf();
  return parseSequence(text.str(), path);
}

std::vector<std::string> listSequenceFiles(const std::string& path) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return {path};
  if (!fs::is_directory(path, ec)) {
    throw Error(path + ": no such PoseTrack file or folder");
  }
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(path)) {
    if (entry.is_regular_file() && entry.path().extension() == ".json") {
      files.push_back(entry.path().string());
    }
  }
  if (files.empty()) throw Error(path + ": folder holds no PoseTrack sequence file (*.json)");
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace jointflow::posetrack
