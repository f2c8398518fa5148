// A picture of who came back under which id: per output id of a tracked video, one crop per
// visit (a run of frames without a gap of more than a second), for identity-bench's vtest.avi
// run (docs/identity-vtest.jpg). A person's row holding several visits is a re-entry (or a long
// occlusion) the tracker bridged; a person in two rows got a new id. Ids are labelled from 1 in
// the order they were first shown.
#pragma once

#include <string>
#include <vector>

#include "jointflow/tracker.hpp"

namespace jointflow::bench {

/// Reads `video` again and writes the sheet of `frames` (the tracked poses of its first
/// frames.size() frames, `fps` frames per second) to `path` (PNG or JPEG, by its extension).
/// Throws jointflow::Error when the video cannot be read or the file cannot be written.
void writeVisitSheet(const std::string& video, const std::vector<std::vector<TrackedPose>>& frames,
                     double fps, const std::string& path);

}  // namespace jointflow::bench
