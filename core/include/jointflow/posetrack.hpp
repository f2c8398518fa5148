// Reading and writing PoseTrack files: one JSON file per video sequence, in either format.
//
//   PoseTrack 2017 ("annolist"): {"annolist": [{"image": [{"name": ...}], "annorect": [{"track_id":
//     [t], "x1": [..], "y1", "x2", "y2" (head box), "score": [s], "annopoints": [{"point": [{"id":
//     [j], "x": [..], "y": [..], "score": [..], "is_visible": [..]}]}]}], "ignore_regions":
//     [{"point":
//     [{"x": [..], "y": [..]}]}]}]}. Every value is wrapped in a one-element list.
//   PoseTrack 2018 (COCO-like): {"images": [{"file_name", "id", "frame_id", "vid_id", "nframes",
//     "is_labeled", "ignore_regions_x", "ignore_regions_y"}], "annotations": [{"image_id",
//     "track_id", "keypoints" (x, y, v per keypoint), "scores", "bbox", "bbox_head" (x, y, w, h)}],
//     "categories": [{"name": "person", "keypoints": [names]}]}.
//
// Both are read into one Sequence, with the points in PoseTrack joint ids (posetrack_joints.hpp),
// exactly as poseval reads them: a 2018 keypoint is absent when x, y and v are all 0 (a point with
// v = 0 but coordinates is kept, as poseval keeps it); the ears are dropped. Reading is strict: a
// missing field or a value of the wrong type throws jointflow::Error naming the file and the
// field's path (e.g. "seq.json: annotations[3].keypoints: expected 51 numbers (17 x 3), got 48").
// For 2017 files a bare value is accepted where a one-element list is expected.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "jointflow/posetrack_joints.hpp"

namespace jointflow::posetrack {

enum class Format { k2017, k2018 };

/// A head box as PoseTrack stores it (2017: x1, y1, x2, y2; 2018 bbox_head is converted).
struct HeadBox {
  double x1 = 0.0;
  double y1 = 0.0;
  double x2 = 0.0;
  double y2 = 0.0;
};

struct Person {
  std::optional<std::int64_t> track_id;  ///< required by tracking evaluation
  PoseTrackJoints joints;                ///< by PoseTrack id; absent joints are empty
  std::optional<HeadBox> head_box;       ///< ground truth: defines the head size of PCKh
  std::optional<double> score;           ///< person score (predictions, optional)
  /// False for a 2017 "annorect" without "annopoints": poseval drops such a person entirely.
  bool has_annopoints = true;
};

/// A closed polygon (frame pixels) whose inside poseval ignores.
struct Polygon {
  std::vector<double> x;
  std::vector<double> y;
};

struct Frame {
  std::string file_name;  ///< "images/val/<seq>/000012.jpg" (2018) or the 2017 image name
  std::int64_t image_id = 0;
  std::int64_t frame_id = 0;
  bool is_labeled = true;
  std::vector<Person> people;
  std::vector<Polygon> ignore_regions;
};

struct Sequence {
  std::string name;    ///< file name without ".json": how ground truth and predictions pair up
  std::string source;  ///< the path it was read from (for messages)
  std::string vid_id;  ///< 2018 "vid_id"; empty when unknown
  Format format = Format::k2018;
  std::vector<Frame> frames;  ///< in file order; predictions pair with ground truth by position
};

/// Reads one sequence file, either format (detected by the "annolist" key). Throws
/// jointflow::Error naming the file and the field at fault.
Sequence readSequence(const std::string& path);

/// Parses a sequence from JSON text; `source` names it in error messages and gives the name.
Sequence parseSequence(const std::string& json_text, const std::string& source);

/// The sequence files at `path`: the file itself, or every "*.json" directly in a folder, sorted
/// by name. Throws jointflow::Error when the path does not exist or a folder holds no JSON file.
std::vector<std::string> listSequenceFiles(const std::string& path);

/// Serialises a sequence. 2018 files get image ids, vid_id and nframes from the frames (set
/// them from the ground truth for a submission); predicted joints write their scores, absent
/// joints are written as (0, 0, 0) with score 0. Throws jointflow::Error for a person without a
/// track id or an id outside 0..999, or for two people with one id in a frame (poseval's checks).
std::string toJson(const Sequence& sequence, Format format);

/// Writes toJson(sequence, format) to `path`; throws jointflow::Error when it cannot be written.
void writeSequence(const Sequence& sequence, const std::string& path, Format format);

}  // namespace jointflow::posetrack
