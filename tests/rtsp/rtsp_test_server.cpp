// jointflow-rtsp-test-server: an RTSP camera for the tests (gst-rtsp-server). It serves a video
// file (vtest.avi by default) looped as live H.264 at the file's own pace, over RTP on UDP or
// interleaved in the RTSP connection (TCP), whichever the client asks for, optionally behind
// Basic authentication:
//
//   jointflow-rtsp-test-server --port 8554 [--user U --password P] [--epoch T] [--start-frame F]
//     [--fps N]
//     -> rtsp://127.0.0.1:8554/stream
//
// The scene runs on the wall clock, not on the server's uptime: the frame on air at Unix time t is
// start-frame + (t - epoch) x frame rate, modulo the file's length. A server killed and started
// again with the same --epoch therefore goes on where the scene would be had it kept running, as a
// camera that reboots shows the people where they walked meanwhile. That is what an outage test
// needs: a restart from frame 0 would make everyone jump.
//
// Prints "ready rtsp://..." on stdout once it listens. Exit status 77 (meson's SKIP) when no
// H.264 encoder is installed (x264enc, from gstreamer1.0-plugins-ugly, or openh264enc, from
// gstreamer1.0-plugins-bad), 1 on other failures; SIGTERM and SIGINT end it cleanly.
#include <glib-unix.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <gst/rtsp-server/rtsp-server.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

namespace {

constexpr int kExitSkip = 77;

struct Options {
  int port = 8554;
  std::string path = "/stream";
  std::string user, password;
  std::string video = "/usr/share/doc/opencv-doc/examples/data/vtest.avi";
  double epoch = 0;  ///< Unix time at which start_frame is on air; 0 = when the server starts
  int start_frame = 0;
  int key_interval = 10;  ///< frames between keyframes: how long a new client waits for a picture
  double fps = 0;         ///< frames per second on air; 0 = the file's own rate
};

double unixNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// One media's frames: decodes the file with OpenCV and hands appsrc the frame that is on air,
// sleeping until it is due, so that the stream runs in real time whatever the client does.
class Feeder {
 public:
  Feeder(const Options& options) : options_(options), capture_(options.video) {
    fps_ = options.fps > 0 ? options.fps : capture_.get(cv::CAP_PROP_FPS);
    if (!(fps_ > 0 && fps_ < 1000)) fps_ = 25;
    count_ = static_cast<long>(capture_.get(cv::CAP_PROP_FRAME_COUNT));
    width_ = static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_WIDTH));
    height_ = static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_HEIGHT));
  }
  bool ok() const { return capture_.isOpened() && count_ > 0 && width_ > 0 && height_ > 0; }

  GstCaps* caps() const {
    const int fps_milli = static_cast<int>(std::lround(fps_ * 1000));
    return gst_caps_new_simple("video/x-raw", "format", G_TYPE_STRING, "BGR", "width", G_TYPE_INT,
                               width_, "height", G_TYPE_INT, height_, "framerate",
                               GST_TYPE_FRACTION, fps_milli, 1000, nullptr);
  }

  // appsrc's need-data, on its streaming thread.
  void push(GstAppSrc* src) {
    const double now = unixNow();
    // The frame number on the scene's clock: the next one after the last pushed, or the one now
    // on air when we fell behind (or at the first call), so the picture never lags the clock.
    const long on_air = static_cast<long>(std::floor((now - options_.epoch) * fps_));
    long n = next_ < 0 || on_air > next_ + 1 ? on_air : next_;
    const double due = options_.epoch + static_cast<double>(n) / fps_;
    if (due > now) std::this_thread::sleep_for(std::chrono::duration<double>(due - now));
    const long index = ((options_.start_frame + n) % count_ + count_) % count_;
    if (index != position_) capture_.set(cv::CAP_PROP_POS_FRAMES, static_cast<double>(index));
    cv::Mat frame;
    if (!capture_.read(frame) || frame.cols != width_ || frame.rows != height_) {
      gst_app_src_end_of_stream(src);
      return;
    }
    position_ = index + 1;
    next_ = n + 1;
    const size_t size = frame.total() * frame.elemSize();
    GstBuffer* buffer = gst_buffer_new_allocate(nullptr, size, nullptr);
    gst_buffer_fill(buffer, 0, frame.isContinuous() ? frame.data : frame.clone().data, size);
    GST_BUFFER_DURATION(buffer) = static_cast<GstClockTime>(GST_SECOND / fps_);
    gst_app_src_push_buffer(src, buffer);  // do-timestamp stamps it with the running time
  }

 private:
  const Options& options_;
  cv::VideoCapture capture_;
  double fps_ = 25;
  long count_ = 0;
  int width_ = 0, height_ = 0;
  long next_ = -1;     ///< scene frame number of the next frame to push; -1 before the first
  long position_ = 0;  ///< the file's frame the capture reads next
};

void onNeedData(GstAppSrc* src, guint, gpointer data) {
  static_cast<Feeder*>(data)->push(src);
}

void onMediaConfigure(GstRTSPMediaFactory*, GstRTSPMedia* media, gpointer data) {
  const auto* options = static_cast<const Options*>(data);
  GstElement* bin = gst_rtsp_media_get_element(media);
  GstElement* src = gst_bin_get_by_name(GST_BIN(bin), "src");
  auto* feeder = new Feeder(*options);
  GstCaps* caps = feeder->caps();
  g_object_set(src, "caps", caps, nullptr);
  gst_caps_unref(caps);
  GstAppSrcCallbacks callbacks{};
  callbacks.need_data = onNeedData;
  // The feeder lives as long as appsrc's callbacks: appsrc deletes it with them.
  gst_app_src_set_callbacks(GST_APP_SRC(src), &callbacks, feeder,
                            [](gpointer f) { delete static_cast<Feeder*>(f); });
  gst_object_unref(src);
  gst_object_unref(bin);
}

const char* h264Encoder() {
  for (const char* name : {"x264enc", "openh264enc"})
    if (GstElementFactory* f = gst_element_factory_find(name)) {
      gst_object_unref(f);
      return name;
    }
  return nullptr;
}

gboolean onStop(gpointer loop) {
  g_main_loop_quit(static_cast<GMainLoop*>(loop));
  return G_SOURCE_REMOVE;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  gchar *user = nullptr, *password = nullptr, *video = nullptr, *path = nullptr;
  const GOptionEntry entries[] = {
      {"port", 0, 0, G_OPTION_ARG_INT, &options.port, "TCP port on 127.0.0.1 (8554)", "PORT"},
      {"path", 0, 0, G_OPTION_ARG_STRING, &path, "Mount point (/stream)", "PATH"},
      {"user", 0, 0, G_OPTION_ARG_STRING, &user, "Require Basic authentication as USER", "USER"},
      {"password", 0, 0, G_OPTION_ARG_STRING, &password, "The user's password", "PASSWORD"},
      {"video", 0, 0, G_OPTION_ARG_FILENAME, &video, "Video file to loop (vtest.avi)", "FILE"},
      {"epoch", 0, 0, G_OPTION_ARG_DOUBLE, &options.epoch,
       "Unix time at which --start-frame is on air (default: now)", "SECONDS"},
      {"start-frame", 0, 0, G_OPTION_ARG_INT, &options.start_frame,
       "Frame of the file on air at --epoch (0)", "N"},
      {"key-interval", 0, 0, G_OPTION_ARG_INT, &options.key_interval,
       "Frames between keyframes (10)", "N"},
      {"fps", 0, 0, G_OPTION_ARG_DOUBLE, &options.fps,
       "Frames per second on air, the file's frames shown faster or slower (default: the "
       "file's rate); a camera faster than the tracker for bench/latency.sh",
       "FPS"},
      {nullptr, 0, 0, G_OPTION_ARG_NONE, nullptr, nullptr, nullptr}};
  GOptionContext* context = g_option_context_new("- an RTSP camera for the JointFlow tests");
  g_option_context_add_main_entries(context, entries, nullptr);
  g_option_context_add_group(context, gst_init_get_option_group());
  GError* error = nullptr;
  if (!g_option_context_parse(context, &argc, &argv, &error)) {
    std::fprintf(stderr, "jointflow-rtsp-test-server: %s\n", error->message);
    return 1;
  }
  g_option_context_free(context);
  if (user) options.user = user;
  if (password) options.password = password;
  if (video) options.video = video;
  if (path) options.path = path;
  g_free(user);
  g_free(password);
  g_free(video);
  g_free(path);
  if (options.epoch <= 0) options.epoch = unixNow();
  if (options.key_interval < 1) options.key_interval = 1;

  const char* encoder = h264Encoder();
  if (!encoder) {
    std::printf(
        "jointflow-rtsp-test-server: no H.264 encoder (x264enc from gstreamer1.0-plugins-ugly, "
        "or openh264enc from gstreamer1.0-plugins-bad)\n");
    return kExitSkip;
  }
  if (!Feeder(options).ok()) {
    std::fprintf(stderr, "jointflow-rtsp-test-server: cannot read %s\n", options.video.c_str());
    return 1;
  }

  // Baseline profile without B-frames at zero latency: each frame leaves the encoder as it comes
  // in, as from a camera; a keyframe every key_interval frames bounds a joining client's wait.
  const std::string key = std::to_string(options.key_interval);
  const std::string encode =
      std::string(encoder) == "x264enc"
          ? "x264enc tune=zerolatency speed-preset=ultrafast key-int-max=" + key +
                " ! video/x-h264,profile=constrained-baseline"
          : "openh264enc gop-size=" + key + " complexity=low";
  const std::string launch =
      "( appsrc name=src is-live=true format=time do-timestamp=true "
      "max-buffers=2 ! videoconvert ! video/x-raw,format=I420 ! " +
      encode + " ! rtph264pay name=pay0 pt=96 config-interval=-1 )";

  GstRTSPServer* server = gst_rtsp_server_new();
  gst_rtsp_server_set_address(server, "127.0.0.1");
  gst_rtsp_server_set_service(server, std::to_string(options.port).c_str());
  GstRTSPMediaFactory* factory = gst_rtsp_media_factory_new();
  gst_rtsp_media_factory_set_launch(factory, launch.c_str());
  // One media for every client, as a camera has one encoder.
  gst_rtsp_media_factory_set_shared(factory, TRUE);
  g_signal_connect(factory, "media-configure", G_CALLBACK(onMediaConfigure), &options);
  if (!options.user.empty()) {
    GstRTSPAuth* auth = gst_rtsp_auth_new();
    GstRTSPToken* token =
        gst_rtsp_token_new(GST_RTSP_TOKEN_MEDIA_FACTORY_ROLE, G_TYPE_STRING, "user", nullptr);
    gchar* basic = gst_rtsp_auth_make_basic(options.user.c_str(), options.password.c_str());
    gst_rtsp_auth_add_basic(auth, basic, token);
    g_free(basic);
    gst_rtsp_token_unref(token);
    gst_rtsp_server_set_auth(server, auth);
    g_object_unref(auth);
    gst_rtsp_media_factory_add_role(factory, "user", GST_RTSP_PERM_MEDIA_FACTORY_ACCESS,
                                    G_TYPE_BOOLEAN, TRUE, GST_RTSP_PERM_MEDIA_FACTORY_CONSTRUCT,
                                    G_TYPE_BOOLEAN, TRUE, nullptr);
  }
  GstRTSPMountPoints* mounts = gst_rtsp_server_get_mount_points(server);
  gst_rtsp_mount_points_add_factory(mounts, options.path.c_str(), factory);
  g_object_unref(mounts);

  // The socket is bound with SO_REUSEADDR, so a restarted server gets the same port at once.
  if (gst_rtsp_server_attach(server, nullptr) == 0) {
    std::fprintf(stderr, "jointflow-rtsp-test-server: cannot listen on 127.0.0.1:%d\n",
                 options.port);
    g_object_unref(server);
    return 1;
  }
  std::printf("ready rtsp://127.0.0.1:%d%s (%s)\n", options.port, options.path.c_str(), encoder);
  std::fflush(stdout);

  GMainLoop* loop = g_main_loop_new(nullptr, FALSE);
  g_unix_signal_add(SIGTERM, onStop, loop);
  g_unix_signal_add(SIGINT, onStop, loop);
  g_main_loop_run(loop);
  g_main_loop_unref(loop);
  g_object_unref(server);
  return 0;
}
