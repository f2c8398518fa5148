// jointflowtrack in a real-time paced pipeline, as on a live camera: the source runs at the
// video's own rate whether or not the tracker keeps up, and a leaky queue in front of the tracker
// drops what it cannot take (docs/gstreamer.md, live sources). Every drop makes the next buffer
// DISCONT; the tracks must live through them: the live run tracks exactly as an offline run fed
// the same frames with the same timestamps. How many frames the tracker gets to see depends on
// the machine and its load, so that comparison, not a count of ids, is what this test can hold
// to; bench/identity measures the ids of a live run against the offline run of every frame
// (issue 11's 1.5x target) on an idle machine.
#include <catch2/catch.hpp>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <opencv2/videoio.hpp>

#include "gst_test_util.hpp"
#include "test_env.hpp"

namespace fs = std::filesystem;
using namespace jointflow::test;

namespace {

struct RunIds {
  std::set<gint64> ids;
  std::vector<std::vector<gint64>> frame_ids;    ///< per buffer out of the tracker, in order
  std::set<GstClockTime> pts_in;                 ///< of the buffers into the tracker
  const std::set<GstClockTime>* only = nullptr;  ///< when set, other buffers are dropped
  int frames = 0;                                ///< buffers out of the tracker
  int inferred = 0;                              ///< of which the networks ran on
  int discont = 0;                               ///< buffers into the tracker flagged DISCONT
};

GstPadProbeReturn countIn(GstPad*, GstPadProbeInfo* info, gpointer data) {
  auto* run = static_cast<RunIds*>(data);
  GstBuffer* buffer = GST_PAD_PROBE_INFO_BUFFER(info);
  if (run->only && !run->only->count(GST_BUFFER_PTS(buffer))) return GST_PAD_PROBE_DROP;
  if (GST_BUFFER_FLAG_IS_SET(buffer, GST_BUFFER_FLAG_DISCONT)) ++run->discont;
  run->pts_in.insert(GST_BUFFER_PTS(buffer));
  return GST_PAD_PROBE_OK;
}

GstPadProbeReturn countOut(GstPad*, GstPadProbeInfo* info, gpointer data) {
  auto* run = static_cast<RunIds*>(data);
  const GstJointFlowMeta* meta = gst_buffer_get_jointflow_meta(GST_PAD_PROBE_INFO_BUFFER(info));
  ++run->frames;
  if (meta && !meta->predicted) ++run->inferred;
  run->frame_ids.emplace_back();
  for (guint i = 0; meta && i < gst_jointflow_meta_get_n_persons(meta); ++i) {
    run->ids.insert(gst_jointflow_meta_get_person(meta, i)->track_id);
    run->frame_ids.back().push_back(gst_jointflow_meta_get_person(meta, i)->track_id);
  }
  return GST_PAD_PROBE_OK;
}

RunIds run(const std::string& description, const std::set<GstClockTime>* only = nullptr) {
  GError* error = nullptr;
  GstElement* pipeline = gst_parse_launch(description.c_str(), &error);
  INFO(description);
  REQUIRE(pipeline != nullptr);
  RunIds ids;
  ids.only = only;
  GstElement* track = gst_bin_get_by_name(GST_BIN(pipeline), "track");
  GstPad* sink = gst_element_get_static_pad(track, "sink");
  GstPad* src = gst_element_get_static_pad(track, "src");
  gst_pad_add_probe(sink, GST_PAD_PROBE_TYPE_BUFFER, countIn, &ids, nullptr);
  gst_pad_add_probe(src, GST_PAD_PROBE_TYPE_BUFFER, countOut, &ids, nullptr);
  gst_object_unref(sink);
  gst_object_unref(src);
  gst_object_unref(track);
  REQUIRE(playToEos(pipeline, 300));
  return ids;
}

}  // namespace

TEST_CASE("a real-time paced pipeline with a leaky queue tracks as offline on the same frames",
          "[plugin][live]") {
  initGst();
  if (!fs::exists(vtestPath())) {
    skipReasons().push_back(vtestPath() + " is absent (install opencv-doc)");
    return;
  }
  // 100 frames of vtest.avi (10 s at its 10 frames/s) as a clip of our own.
  const fs::path clip = fs::temp_directory_path() / "jointflow-live-test.avi";
  {
    cv::VideoCapture in(vtestPath());
    cv::Mat frame;
    REQUIRE(in.read(frame));
    cv::VideoWriter out(clip.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10,
                        frame.size());
    REQUIRE(out.isOpened());
    for (int i = 0; i < 100 && in.read(frame); ++i) out.write(frame);
  }
  const std::string source = "filesrc location=" + clip.string() + " ! decodebin ! videoconvert";
  const std::string offline_pipeline =
      source + " ! jointflowtrack name=track ! fakesink sync=false";
  const RunIds offline = run(offline_pipeline);
  const RunIds live = run(source +
                          " ! identity sync=true ! queue leaky=downstream max-size-buffers=1 "
                          "max-size-bytes=0 max-size-time=0 ! jointflowtrack name=track ! "
                          "fakesink sync=false");
  // The frames the live run's tracker got, offline: the others dropped before the tracker, with
  // no DISCONT flag.
  const RunIds same_frames = run(offline_pipeline, &live.pts_in);
  fs::remove(clip);
  WARN("offline: " << offline.frames << " frames, " << offline.ids.size()
                   << " ids; live: " << live.frames << " frames (" << live.discont
                   << " after a drop), " << live.ids.size() << " ids");
  REQUIRE(offline.frames == 100);
  REQUIRE(live.frames > 10);
  REQUIRE(same_frames.frames == live.frames);
  if (live.discont == 0)
    WARN("this machine took every frame: no DISCONT buffer came, so the drops went untested");
  // Frame by frame the same ids. Before, every drop reset the tracks: about one new id per person
  // and frame.
  CHECK(live.frame_ids == same_frames.frame_ids);
  CHECK(live.inferred == live.frames);
}
