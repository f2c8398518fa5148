// Which frame of the source a buffer at the tracker is. Decoders keep the timestamps of the frames
// they output and drop the frames they cannot decode, so the PTS (in stream time, times the frame
// rate) names the source frame even after a gap; counting the buffers would shift every name
// after the first undecodable frame.
#pragma once

#include <gst/gst.h>

#include <cstdint>

namespace jointflow::cli {

class FrameIndexer {
 public:
  /// The source index of `buffer`, seen on `pad` (whose caps and segment are read). Falls back to
  /// the count of buffers seen when the stream has no PTS or no frame rate, saying so once.
  std::int64_t index(GstPad* pad, GstBuffer* buffer);

 private:
  std::int64_t count_ = 0;
  bool warned_ = false;
};

/// The timestamps given to the files of a folder of frames (`data` of stampFolderFrames).
struct FolderClock {
  GstClockTime frame_duration = 0;
  guint64 stamped = 0;  ///< files stamped so far
};

/// A probe for multifilesrc's source pad: multifilesrc leaves PTS unset (the parser after it
/// counts frames, so an undecodable file would shift the later ones), so each file's buffer is
/// stamped with its position in the folder, as if the folder were a video.
GstPadProbeReturn stampFolderFrames(GstPad* pad, GstPadProbeInfo* info, gpointer clock);

}  // namespace jointflow::cli
