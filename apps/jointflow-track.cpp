// jointflow-track: tracks the poses of every person in a video, a URI or a folder of numbered
// frames, headless, on the same GStreamer elements a pipeline would use:
//
//   source ! decodebin ! videoconvert ! jointflowtrack [! jointflowjsonwriter]
//          [! jointflowoverlay ! videoconvert ! x264enc ! mp4mux|matroskamux ! filesink | fakesink]
//
// The options that configure the tracker are made from jointflowtrack's own properties (same
// names, documentation and defaults, validated by the element), so the command line and the
// element cannot drift apart. PoseTrack 2018 output uses the core's writer (posetrack.hpp).
#include <gst/gst.h>
#include <gst/video/video.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "jointflow/error.hpp"
#include "jointflow/posetrack.hpp"
#include "jointflow/posetrack_joints.hpp"
#include "jointflowmeta.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// ---------------------------------------------------------------------------------------------
// Finding the plugin: the registry first (GST_PLUGIN_PATH, installed plugins), then the build
// tree this binary was built in, then the install folder.

bool findPlugin() {
  if (GstElementFactory* f = gst_element_factory_find("jointflowtrack")) {
    gst_object_unref(f);
    return true;
  }
  for (const char* dir : {JOINTFLOW_PLUGIN_BUILD_DIR, JOINTFLOW_PLUGIN_INSTALL_DIR}) {
    if (!fs::is_directory(dir)) continue;
    gst_registry_scan_path(gst_registry_get(), dir);
    if (GstElementFactory* f = gst_element_factory_find("jointflowtrack")) {
      gst_object_unref(f);
      return true;
    }
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
// Input: a video file, a URI, a printf pattern of frames, or a folder of numbered frames.

struct FrameSequence {
  std::string pattern;  ///< printf pattern for multifilesrc
  int first = 0;
  int last = 0;
  std::string caps;                ///< image/jpeg or image/png
  std::vector<std::string> names;  ///< file names in order
};

// The frames of a folder: image files whose names differ only in one number, consecutive.
FrameSequence numberedFrames(const fs::path& folder) {
  static const std::regex numbered(R"(^(.*?)(\d+)(\.(jpe?g|png))$)", std::regex::icase);
  struct Entry {
    std::string prefix, digits, suffix;
    long number;
  };
  std::vector<Entry> entries;
  for (const auto& e : fs::directory_iterator(folder)) {
    std::smatch m;
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && std::regex_match(name, m, numbered))
      entries.push_back({m[1], m[2], m[3], std::stol(m[2])});
  }
  if (entries.empty())
    throw jointflow::Error(folder.string() +
                           ": no numbered .jpg or .png frames (expected e.g. 000000.jpg, "
                           "000001.jpg, ...)");
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.number < b.number; });
  const Entry& f = entries.front();
  const bool fixed_width = std::all_of(entries.begin(), entries.end(), [&](const Entry& e) {
    return e.digits.size() == f.digits.size();
  });
  FrameSequence seq;
  for (size_t i = 0; i < entries.size(); ++i) {
    const Entry& e = entries[i];
    if (e.prefix != f.prefix || e.suffix != f.suffix)
      throw jointflow::Error(folder.string() + ": frames \"" + f.prefix + f.digits + f.suffix +
                             "\" and \"" + e.prefix + e.digits + e.suffix +
                             "\" are not named alike; expected one numbered sequence");
    if (e.number != f.number + static_cast<long>(i))
      throw jointflow::Error(folder.string() + ": frame " + std::to_string(f.number + i) +
                             " is missing (the numbers must be consecutive)");
    seq.names.push_back(e.prefix + e.digits + e.suffix);
  }
  std::string number = fixed_width ? "%0" + std::to_string(f.digits.size()) + "d" : "%d";
  std::string prefix = f.prefix;
  // multifilesrc runs the pattern through printf: a literal '%' must be doubled.
  prefix = std::regex_replace(prefix, std::regex("%"), "%%");
  seq.pattern = (folder / (prefix + number + f.suffix)).string();
  seq.first = static_cast<int>(f.number);
  seq.last = static_cast<int>(entries.back().number);
  const std::string ext = f.suffix;
  seq.caps = (ext == ".png" || ext == ".PNG") ? "image/png" : "image/jpeg";
  return seq;
}

// Sources that produce frames at their own pace whether or not we keep up.
bool isLiveUri(const std::string& uri) {
  gchar* scheme = gst_uri_get_protocol(uri.c_str());
  const std::string s = scheme ? scheme : "";
  g_free(scheme);
  return s == "rtsp" || s == "rtsps" || s == "rtspt" || s == "rtspu" || s == "udp" || s == "srt" ||
         s == "rtmp" || s == "v4l2";
}

struct Input {
  std::string description;    ///< for messages
  std::string sequence_name;  ///< PoseTrack sequence name
  std::string file_prefix;    ///< PoseTrack file_name prefix ("images/val/<seq>/")
  std::optional<FrameSequence> frames;
  std::string uri;
};

Input resolveInput(const std::string& text) {
  Input in;
  in.description = text;
  if (gst_uri_is_valid(text.c_str())) {
    in.uri = text;
    gchar* location = gst_uri_get_location(text.c_str());
    const fs::path p(location ? location : text);
    g_free(location);
    in.sequence_name = p.stem().string();
    in.file_prefix = in.sequence_name + "/";
    return in;
  }
  const fs::path path(text);
  if (fs::is_directory(path)) {
    in.frames = numberedFrames(path);
    const fs::path canonical = fs::weakly_canonical(path);
    in.sequence_name = canonical.filename().string();
    // PoseTrack ground truth names frames "images/<split>/<sequence>/000000.jpg".
    const fs::path split = canonical.parent_path();
    in.file_prefix = split.parent_path().filename() == "images"
                         ? "images/" + split.filename().string() + "/" + in.sequence_name + "/"
                         : in.sequence_name + "/";
    return in;
  }
  if (!fs::exists(path))
    throw jointflow::Error(text +
                           ": no such file or folder (expected a video file, a URI or a "
                           "folder of numbered frames)");
  GError* error = nullptr;
  gchar* uri = gst_filename_to_uri(text.c_str(), &error);
  if (!uri) {
    const std::string message = error ? error->message : "invalid file name";
    g_clear_error(&error);
    throw jointflow::Error(text + ": " + message);
  }
  in.uri = uri;
  g_free(uri);
  in.sequence_name = path.stem().string();
  in.file_prefix = in.sequence_name + "/";
  return in;
}

// ---------------------------------------------------------------------------------------------
// Options made from jointflowtrack's properties.

struct PropertyOption {
  std::string name;
  std::string value;
  bool given = false;
};

std::string defaultText(GParamSpec* spec) {
  const GValue* def = g_param_spec_get_default_value(spec);
  if (G_VALUE_HOLDS_FLOAT(def)) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", g_value_get_float(def));
    return text;
  }
  gchar* s = gst_value_serialize(def);
  std::string text = s ? s : "";
  g_free(s);
  return text.empty() ? "none" : text;
}

// What --help shows as the option's value.
std::string typeName(GParamSpec* spec) {
  switch (G_TYPE_FUNDAMENTAL(spec->value_type)) {
    case G_TYPE_INT:
    case G_TYPE_UINT:
      return "INT";
    case G_TYPE_FLOAT:
    case G_TYPE_DOUBLE:
      return "FLOAT";
    case G_TYPE_BOOLEAN:
      return "true|false";
    case G_TYPE_ENUM:
      return "NAME";
    default:
      return "TEXT";
  }
}

std::string allowedValues(GParamSpec* spec) {
  if (!G_IS_PARAM_SPEC_ENUM(spec)) return "";
  std::string text;
  GEnumClass* klass = G_PARAM_SPEC_ENUM(spec)->enum_class;
  for (guint i = 0; i < klass->n_values; ++i)
    text += std::string(i ? "|" : "") + klass->values[i].value_nick;
  return " [" + text + "]";
}

// Sets a property from text the way gst-launch does, refusing what the element refuses.
void setProperty(GstElement* element, const std::string& name, const std::string& text) {
  GParamSpec* spec = g_object_class_find_property(G_OBJECT_GET_CLASS(element), name.c_str());
  GValue value = G_VALUE_INIT;
  g_value_init(&value, spec->value_type);
  if (!gst_value_deserialize(&value, text.c_str())) {
    g_value_unset(&value);
    throw jointflow::Error("--" + name + ": \"" + text + "\" is not a valid value" +
                           allowedValues(spec));
  }
  if (g_param_value_validate(spec, &value)) {  // TRUE when the value had to be changed
    g_value_unset(&value);
    throw jointflow::Error("--" + name + ": " + text + " is out of range (see --help)");
  }
  // The element validates what a GParamSpec cannot (input-size, scales) and warns: make that an
  // error here.
  std::string refused;
  const guint handler = g_log_set_handler(
      nullptr, static_cast<GLogLevelFlags>(G_LOG_LEVEL_WARNING | G_LOG_LEVEL_CRITICAL),
      [](const gchar*, GLogLevelFlags, const gchar* message, gpointer data) {
        *static_cast<std::string*>(data) = message;
      },
      &refused);
  g_object_set_property(G_OBJECT(element), name.c_str(), &value);
  g_log_remove_handler(nullptr, handler);
  g_value_unset(&value);
  if (!refused.empty()) throw jointflow::Error("--" + name + ": " + refused);
}

// ---------------------------------------------------------------------------------------------
// What the run saw: counted in the streaming thread, read by the main loop.

struct Statistics {
  std::mutex mutex;
  guint64 frames = 0;
  guint64 detections = 0;
  std::set<gint64> tracks;
  std::set<gint64> confirmed;
  std::optional<jointflow::posetrack::Sequence> posetrack;
  jointflow::posetrack::TrackIdMap posetrack_ids;
  float posetrack_joint_threshold = 0.2f;
  std::vector<std::string> frame_names;
  std::string file_prefix;
};

jointflow::Pose toPose(const JointFlowPerson& p) {
  jointflow::Pose pose;
  pose.score = p.score;
  pose.box = {p.x, p.y, p.width, p.height};
  for (int j = 0; j < JOINTFLOW_N_KEYPOINTS; ++j)
    pose.keypoints[j] = {p.keypoints[j].x, p.keypoints[j].y, p.keypoints[j].score};
  return pose;
}

void recordFrame(Statistics& stats, const GstJointFlowMeta* meta) {
  std::lock_guard<std::mutex> lock(stats.mutex);
  const guint n = meta ? gst_jointflow_meta_get_n_persons(meta) : 0;
  const guint64 index = stats.frames++;
  stats.detections += n;
  std::vector<std::int64_t> ids;
  for (guint i = 0; i < n; ++i) {
    const JointFlowPerson* p = gst_jointflow_meta_get_person(meta, i);
    stats.tracks.insert(p->track_id);
    if (!p->tentative) stats.confirmed.insert(p->track_id);
    ids.push_back(p->track_id);
  }
  if (!stats.posetrack) return;
  jointflow::posetrack::Frame frame;
  char number[32];
  std::snprintf(number, sizeof number, "%06llu.jpg", static_cast<unsigned long long>(index));
  frame.file_name = stats.file_prefix + (index < stats.frame_names.size() ? stats.frame_names[index]
                                                                          : std::string(number));
  frame.image_id = static_cast<std::int64_t>(index);
  frame.frame_id = static_cast<std::int64_t>(index);
  const std::vector<int> numbers = stats.posetrack_ids.assign(ids);
  for (guint i = 0; i < n; ++i) {
    const JointFlowPerson* p = gst_jointflow_meta_get_person(meta, i);
    jointflow::posetrack::Person person;
    person.track_id = numbers[i];
    person.joints =
        jointflow::posetrack::toPoseTrackJoints(toPose(*p), stats.posetrack_joint_threshold);
    person.score = p->score;
    frame.people.push_back(std::move(person));
  }
  stats.posetrack->frames.push_back(std::move(frame));
}

// ---------------------------------------------------------------------------------------------
// The pipeline.

struct Run {
  GstElement* pipeline = nullptr;
  GstElement* entry = nullptr;  ///< where the decoder's video pad is linked
  GMainLoop* loop = nullptr;
  Statistics stats;
  guint64 max_frames = 0;    ///< 0 = all
  guint64 frames_in = 0;     ///< frames that reached the tracker's input (streaming thread)
  guint64 total_frames = 0;  ///< estimate for the progress bar; 0 = unknown
  std::string error;
  bool progress = false;
  Clock::time_point start;
};

GstElement* make(const char* factory, const char* name = nullptr) {
  GstElement* e = gst_element_factory_make(factory, name);
  if (!e)
    throw jointflow::Error(std::string("GStreamer element \"") + factory +
                           "\" is missing (install the GStreamer plugins listed in "
                           "scripts/install-deps.sh)");
  return e;
}

void onPadAdded(GstElement*, GstPad* pad, gpointer data) {
  auto* run = static_cast<Run*>(data);
  GstCaps* caps = gst_pad_get_current_caps(pad);
  if (!caps) caps = gst_pad_query_caps(pad, nullptr);
  const bool video =
      caps && gst_caps_get_size(caps) > 0 &&
      g_str_has_prefix(gst_structure_get_name(gst_caps_get_structure(caps, 0)), "video/");
  if (caps) gst_caps_unref(caps);
  if (!video) return;  // audio and other streams stay unlinked
  GstPad* sink = gst_element_get_static_pad(run->entry, "sink");
  if (!gst_pad_is_linked(sink) && gst_pad_link(pad, sink) != GST_PAD_LINK_OK)
    g_printerr("jointflow-track: could not link the decoded video\n");
  gst_object_unref(sink);
}

// On the tracker's input: after --max-frames frames the stream ends there (EOS downstream; the
// pad then refuses further data, which stops the decoder), so no further frame is inferred.
GstPadProbeReturn limitFrames(GstPad* pad, GstPadProbeInfo*, gpointer data) {
  auto* run = static_cast<Run*>(data);
  if (run->max_frames == 0 || ++run->frames_in <= run->max_frames) return GST_PAD_PROBE_OK;
  if (run->frames_in == run->max_frames + 1) gst_pad_send_event(pad, gst_event_new_eos());
  return GST_PAD_PROBE_DROP;
}

// On the tracker's output: statistics and PoseTrack frames.
GstPadProbeReturn recordOutput(GstPad*, GstPadProbeInfo* info, gpointer data) {
  auto* run = static_cast<Run*>(data);
  recordFrame(run->stats, gst_buffer_get_jointflow_meta(GST_PAD_PROBE_INFO_BUFFER(info)));
  return GST_PAD_PROBE_OK;
}

struct Outputs {
  std::string json;
  std::string posetrack_dir;
  std::string video;
  bool draw_boxes = false;
};

// Builds source ! decode ! videoconvert ! jointflowtrack ! [jsonwriter] ! tail.
GstElement* buildPipeline(Run& run, const Input& input, const Outputs& out, GstElement* track,
                          int framerate) {
  GstElement* pipeline = gst_pipeline_new("jointflow-track");
  GstElement* decode;
  if (input.frames) {
    GstElement* src = make("multifilesrc");
    g_object_set(src, "location", input.frames->pattern.c_str(), "start-index", input.frames->first,
                 "stop-index", input.frames->last, "index", input.frames->first, nullptr);
    const std::string caps = input.frames->caps + ",framerate=" + std::to_string(framerate) + "/1";
    gst_util_set_object_arg(G_OBJECT(src), "caps", caps.c_str());
    decode = make("decodebin");
    gst_bin_add_many(GST_BIN(pipeline), src, decode, nullptr);
    gst_element_link(src, decode);
  } else {
    decode = make("uridecodebin");
    g_object_set(decode, "uri", input.uri.c_str(), nullptr);
    gst_bin_add(GST_BIN(pipeline), decode);
  }
  std::vector<GstElement*> chain;
  if (isLiveUri(input.uri)) {
    // A live source does not wait for us: keep only the newest frame while the tracker is busy,
    // so the delay stays one inference long (docs/gstreamer.md, live sources).
    GstElement* queue = make("queue");
    gst_util_set_object_arg(G_OBJECT(queue), "leaky", "downstream");
    g_object_set(queue, "max-size-buffers", 1u, "max-size-bytes", 0u, "max-size-time", guint64{0},
                 nullptr);
    chain.push_back(queue);
  }
  chain.push_back(make("videoconvert"));
  chain.push_back(track);
  for (GstElement* e : chain) gst_bin_add(GST_BIN(pipeline), e);
  run.entry = chain.front();
  g_signal_connect(decode, "pad-added", G_CALLBACK(onPadAdded), &run);
  const size_t first_new = chain.size();
  if (!out.json.empty()) {
    GstElement* writer = make("jointflowjsonwriter");
    g_object_set(writer, "location", out.json.c_str(), nullptr);
    chain.push_back(writer);
  }
  if (!out.video.empty()) {
    const std::string ext = fs::path(out.video).extension().string();
    if (ext != ".mp4" && ext != ".mkv")
      throw jointflow::Error("--output-video " + out.video + ": expected a .mp4 or .mkv file");
    GstElement* overlay = make("jointflowoverlay");
    g_object_set(overlay, "draw-boxes", out.draw_boxes, nullptr);
    GstElement* convert = make("videoconvert");
    GstElement* filter = make("capsfilter");
    // 4:2:0 is what players expect from H.264 (x264enc would pick 4:4:4 from RGB otherwise).
    GstCaps* i420 = gst_caps_from_string("video/x-raw,format=I420");
    g_object_set(filter, "caps", i420, nullptr);
    gst_caps_unref(i420);
    GstElement* encoder = make("x264enc");
    gst_util_set_object_arg(G_OBJECT(encoder), "speed-preset", "veryfast");
    GstElement* mux = make(ext == ".mp4" ? "mp4mux" : "matroskamux");
    GstElement* sink = make("filesink");
    g_object_set(sink, "location", out.video.c_str(), nullptr);
    chain.insert(chain.end(), {overlay, convert, filter, encoder, mux, sink});
  } else {
    GstElement* sink = make("fakesink");
    g_object_set(sink, "sync", FALSE, nullptr);
    chain.push_back(sink);
  }
  for (size_t i = first_new; i < chain.size(); ++i) gst_bin_add(GST_BIN(pipeline), chain[i]);
  for (size_t i = 0; i + 1 < chain.size(); ++i)
    if (!gst_element_link(chain[i], chain[i + 1]))
      throw jointflow::Error(std::string("could not link ") + GST_ELEMENT_NAME(chain[i]) + " to " +
                             GST_ELEMENT_NAME(chain[i + 1]));

  GstPad* in = gst_element_get_static_pad(track, "sink");
  gst_pad_add_probe(in, GST_PAD_PROBE_TYPE_BUFFER, limitFrames, &run, nullptr);
  gst_object_unref(in);
  GstPad* outpad = gst_element_get_static_pad(track, "src");
  gst_pad_add_probe(outpad, GST_PAD_PROBE_TYPE_BUFFER, recordOutput, &run, nullptr);
  gst_object_unref(outpad);
  return pipeline;
}

// ---------------------------------------------------------------------------------------------
// Progress and summary.

std::string clockText(double seconds) {
  const long s = static_cast<long>(seconds + 0.5);
  char text[32];
  std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  return text;
}

void estimateTotal(Run& run) {
  if (run.total_frames > 0) return;
  gint64 duration = 0;
  GstElement* track = gst_bin_get_by_name(GST_BIN(run.pipeline), "track");
  GstPad* pad = gst_element_get_static_pad(track, "sink");
  GstCaps* caps = gst_pad_get_current_caps(pad);
  gint num = 0, den = 1;
  if (caps &&
      gst_structure_get_fraction(gst_caps_get_structure(caps, 0), "framerate", &num, &den) &&
      num > 0 && gst_element_query_duration(run.pipeline, GST_FORMAT_TIME, &duration) &&
      duration > 0)
    run.total_frames = gst_util_uint64_scale(duration, num, static_cast<guint64>(den) * GST_SECOND);
  if (caps) gst_caps_unref(caps);
  gst_object_unref(pad);
  gst_object_unref(track);
  if (run.max_frames > 0 && (run.total_frames == 0 || run.total_frames > run.max_frames))
    run.total_frames = run.max_frames;
}

gboolean showProgress(gpointer data) {
  auto* run = static_cast<Run*>(data);
  estimateTotal(*run);
  guint64 done;
  {
    std::lock_guard<std::mutex> lock(run->stats.mutex);
    done = run->stats.frames;
  }
  const double elapsed = std::chrono::duration<double>(Clock::now() - run->start).count();
  const double fps = elapsed > 0 ? done / elapsed : 0;
  constexpr int kWidth = 30;
  std::string line;
  if (run->total_frames > 0) {
    const double f = std::min(1.0, static_cast<double>(done) / run->total_frames);
    const int filled = static_cast<int>(f * kWidth);
    line = "[" + std::string(filled, '#') + std::string(kWidth - filled, '.') + "] " +
           std::to_string(done) + "/" + std::to_string(run->total_frames) + " frames";
  } else {
    line = std::to_string(done) + " frames";
  }
  char rate[96];
  std::snprintf(rate, sizeof rate, "  %.1f frames/s", fps);
  line += rate;
  if (run->total_frames > done && fps > 0)
    line += "  ETA " + clockText((run->total_frames - done) / fps);
  g_printerr("\r%-90s", line.c_str());
  return G_SOURCE_CONTINUE;
}

gboolean onBusMessage(GstBus*, GstMessage* msg, gpointer data) {
  auto* run = static_cast<Run*>(data);
  switch (GST_MESSAGE_TYPE(msg)) {
    case GST_MESSAGE_ERROR: {
      GError* err = nullptr;
      gchar* debug = nullptr;
      gst_message_parse_error(msg, &err, &debug);
      if (run->error.empty()) {
        run->error = std::string(GST_OBJECT_NAME(GST_MESSAGE_SRC(msg))) + ": " + err->message;
        if (debug && g_getenv("JOINTFLOW_DEBUG")) run->error += std::string("\n  ") + debug;
      }
      g_clear_error(&err);
      g_free(debug);
      g_main_loop_quit(run->loop);
      break;
    }
    case GST_MESSAGE_EOS:
      g_main_loop_quit(run->loop);
      break;
    default:
      break;
  }
  return TRUE;
}

}  // namespace

int main(int argc, char** argv) {
  gst_init(&argc, &argv);
  if (!findPlugin()) {
    g_printerr(
        "jointflow-track: the JointFlow GStreamer plugin was not found; set "
        "GST_PLUGIN_PATH to the folder holding libgstjointflow.so (build/gst-plugin)\n");
    return 2;
  }
  GstElement* track = gst_element_factory_make("jointflowtrack", "track");
  gst_object_ref_sink(track);

  CLI::App app{
      "Tracks the 2D poses of every person in a video (JointFlow). INPUT is a video "
      "file, a URI (file://, rtsp://, http://, ...) or a folder of numbered frames."};
  std::string input_text;
  Outputs out;
  guint64 max_frames = 0;
  int framerate = 25;
  bool quiet = false;
  float posetrack_threshold = 0.2f;
  app.add_option("INPUT", input_text, "Video file, URI or folder of numbered frames")->required();
  app.add_option("--max-frames", max_frames, "Stop after this many frames (0 = all)");
  app.add_option("--output-json", out.json,
                 "Write the poses as JSON Lines to this file (\"-\" = stdout)");
  app.add_option("--output-posetrack", out.posetrack_dir,
                 "Write PoseTrack 2018 JSON (<sequence>.json) into this folder");
  app.add_option("--output-video", out.video, "Write the video with the poses drawn (.mp4|.mkv)");
  app.add_flag("--draw-boxes", out.draw_boxes, "Draw person boxes in --output-video");
  app.add_option("--framerate", framerate, "Frames per second of a folder of frames")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app.add_option("--posetrack-joint-threshold", posetrack_threshold,
                 "Joints scoring below this are left out of PoseTrack files")
      ->capture_default_str()
      ->check(CLI::Range(0.f, 1.f));
  app.add_flag("-q,--quiet", quiet, "No progress bar and no summary");

  // One option per jointflowtrack property, documented from the property itself.
  std::vector<PropertyOption> props;
  guint n_specs = 0;
  GParamSpec** specs = g_object_class_list_properties(G_OBJECT_GET_CLASS(track), &n_specs);
  for (guint i = 0; i < n_specs; ++i) {
    GParamSpec* spec = specs[i];
    if (spec->owner_type != G_OBJECT_TYPE(track) || !(spec->flags & G_PARAM_WRITABLE)) continue;
    props.push_back({spec->name, "", false});
  }
  for (PropertyOption& p : props) {
    GParamSpec* spec = g_object_class_find_property(G_OBJECT_GET_CLASS(track), p.name.c_str());
    const std::string help = std::string(g_param_spec_get_blurb(spec)) + allowedValues(spec) +
                             " (default: " + defaultText(spec) + ")";
    app.add_option("--" + p.name, p.value, help)->type_name(typeName(spec));
  }
  g_free(specs);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    gst_object_unref(track);
    return app.exit(e);
  }

  Run run;
  int status = 0;
  try {
    for (PropertyOption& p : props)
      if (app.count("--" + p.name) > 0) setProperty(track, p.name, p.value);
    const Input input = resolveInput(input_text);
    if (!out.posetrack_dir.empty()) {
      fs::create_directories(out.posetrack_dir);
      run.stats.posetrack.emplace();
      run.stats.posetrack->name = input.sequence_name;
      run.stats.posetrack_joint_threshold = posetrack_threshold;
      run.stats.file_prefix = input.file_prefix;
      if (input.frames) run.stats.frame_names = input.frames->names;
    }
    for (const std::string& file : {out.json, out.video})
      if (!file.empty() && file != "-" && fs::path(file).has_parent_path())
        fs::create_directories(fs::path(file).parent_path());
    run.max_frames = max_frames;
    if (input.frames) run.total_frames = input.frames->names.size();
    run.pipeline = buildPipeline(run, input, out, track, framerate);
    run.loop = g_main_loop_new(nullptr, FALSE);
    GstBus* bus = gst_element_get_bus(run.pipeline);
    gst_bus_add_watch(bus, onBusMessage, &run);
    gst_object_unref(bus);
    run.progress = !quiet && isatty(STDERR_FILENO);
    guint timer = run.progress ? g_timeout_add(250, showProgress, &run) : 0;
    run.start = Clock::now();
    if (gst_element_set_state(run.pipeline, GST_STATE_PLAYING) != GST_STATE_CHANGE_FAILURE)
      g_main_loop_run(run.loop);
    else if (run.error.empty())
      g_main_loop_run(run.loop);  // the error message follows on the bus
    const double seconds = std::chrono::duration<double>(Clock::now() - run.start).count();
    if (timer) {
      showProgress(&run);
      g_source_remove(timer);
      g_printerr("\n");
    }
    gst_element_set_state(run.pipeline, GST_STATE_NULL);
    if (!run.error.empty()) throw jointflow::Error(run.error);

    Statistics& st = run.stats;
    if (st.posetrack) {
      const std::string path =
          (fs::path(out.posetrack_dir) / (st.posetrack->name + ".json")).string();
      jointflow::posetrack::writeSequence(*st.posetrack, path, jointflow::posetrack::Format::k2018);
    }
    if (!quiet) {
      std::printf("frames:     %llu\n", static_cast<unsigned long long>(st.frames));
      std::printf("people:     %llu detections, %.2f per frame\n",
                  static_cast<unsigned long long>(st.detections),
                  st.frames ? static_cast<double>(st.detections) / st.frames : 0.0);
      std::printf("tracks:     %zu (%zu confirmed)\n", st.tracks.size(), st.confirmed.size());
      std::printf("frames/s:   %.2f (%.1f s)\n", seconds > 0 ? st.frames / seconds : 0.0, seconds);
      for (const auto& [what, file] :
           {std::pair<const char*, std::string>{"json", out.json}, {"video", out.video}})
        if (!file.empty())
          std::printf("%-11s %s\n", (std::string(what) + ":").c_str(), file.c_str());
      if (st.posetrack)
        std::printf("posetrack:  %s\n",
                    (fs::path(out.posetrack_dir) / (st.posetrack->name + ".json")).c_str());
    }
  } catch (const std::exception& e) {
    g_printerr("jointflow-track: error: %s\n", e.what());
    status = 1;
  }
  if (run.pipeline) {
    GstBus* bus = gst_element_get_bus(run.pipeline);
    gst_bus_remove_watch(bus);  // the watch holds a reference to the bus
    gst_object_unref(bus);
    gst_object_unref(run.pipeline);
  }
  if (run.loop) g_main_loop_unref(run.loop);
  gst_object_unref(track);
  gst_deinit();  // lets GST_TRACERS=leaks report what was not released
  return status;
}
