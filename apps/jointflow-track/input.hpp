// What jointflow-track reads: a video file, a URI, or a folder of numbered frames, resolved into
// what the pipeline needs (a URI or a multifilesrc pattern) and how PoseTrack output names it.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace jointflow::cli {

/// The frames of a folder: image files whose names differ only in one consecutive number.
struct FrameSequence {
  std::string pattern;  ///< printf pattern for multifilesrc
  int first = 0;
  int last = 0;
  std::string caps;                ///< image/jpeg or image/png
  std::vector<std::string> names;  ///< file names in order: names[k] is frame first + k
};

struct Input {
  std::string description;    ///< for messages (a URI's password left out)
  std::string sequence_name;  ///< PoseTrack sequence name
  std::string file_prefix;    ///< PoseTrack file_name prefix ("images/val/<seq>/")
  std::optional<FrameSequence> frames;
  std::string uri;
};

/// Throws jointflow::Error naming the path and what was expected when it is none of the three, or
/// an rtsp:// address without a host or with a port out of range.
Input resolveInput(const std::string& text);

/// Sources that produce frames at their own pace whether or not we keep up (rtsp, udp, ...).
bool isLiveUri(const std::string& uri);

/// The URI with the password of its user part (user:password@) replaced by "***", for messages.
std::string redactUri(const std::string& uri);

}  // namespace jointflow::cli
