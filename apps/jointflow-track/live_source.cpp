// Reconnection of a live input (live_source.hpp).
#include "live_source.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

namespace jointflow::cli {
namespace {

// The watchdog's period: how soon an end of stream or a silent source is noticed.
constexpr guint kTickMs = 100;

std::chrono::milliseconds toMs(double seconds) {
  return std::chrono::milliseconds(static_cast<std::int64_t>(std::llround(seconds * 1000)));
}

// Whether @event's segment and the one @pad holds both give each PTS as its running time (time
// format, rate 1, base = start), so that either may stand for the other.
bool sameRunningTime(GstPad* pad, GstEvent* event) {
  auto identity = [](const GstSegment* s) {
    return s->format == GST_FORMAT_TIME && s->rate == 1.0 && s->applied_rate == 1.0 &&
           s->base == s->start && s->offset == 0;
  };
  const GstSegment* incoming = nullptr;
  gst_event_parse_segment(event, &incoming);
  GstEvent* current = gst_pad_get_sticky_event(pad, GST_EVENT_SEGMENT, 0);
  if (!current) return false;
  const GstSegment* held = nullptr;
  gst_event_parse_segment(current, &held);
  const bool same = identity(incoming) && identity(held);
  gst_event_unref(current);
  return same;
}

}  // namespace

void addReconnectOptions(CLI::App& app, ReconnectOptions& options) {
  app.add_option("--reconnect-attempts", options.attempts,
                 "Live inputs (rtsp://, udp://, ...): attempts in a row that bring no frame before "
                 "giving up with exit status 3 (0 = never give up)")
      ->capture_default_str();
  app.add_option("--reconnect-delay", options.delay,
                 "Seconds before the second attempt to reach a lost live input; the wait doubles "
                 "after each failed attempt (the first comes at once)")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 3600.0));
  app.add_option("--reconnect-max-delay", options.max_delay,
                 "The longest wait in seconds between two attempts to reach a live input")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 3600.0));
  app.add_option("--source-timeout", options.source_timeout,
                 "Seconds without a frame after which a live input counts as lost, and that an "
                 "attempt to reach it may take to bring its first frame")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 3600.0));
}

LiveSource::LiveSource(GstElement* pipeline, GstElement* entry, std::function<GstElement*()> make,
                       std::string description, const ReconnectOptions& options, double lost_time)
    : pipeline_(pipeline),
      entry_sink_(gst_element_get_static_pad(entry, "sink")),
      make_(std::move(make)),
      description_(std::move(description)),
      options_(options),
      lost_time_(lost_time),
      backoff_(toMs(options.delay), toMs(options.max_delay)) {
  event_probe_ = gst_pad_add_probe(entry_sink_, GST_PAD_PROBE_TYPE_EVENT_DOWNSTREAM, onEntryEvent,
                                   this, nullptr);
  buffer_probe_ =
      gst_pad_add_probe(entry_sink_, GST_PAD_PROBE_TYPE_BUFFER, onEntryBuffer, this, nullptr);
  tick_ = g_timeout_add(kTickMs, onTick, this);
}

LiveSource::~LiveSource() {
  if (tick_) g_source_remove(tick_);
  if (retry_) g_source_remove(retry_);
  gst_pad_remove_probe(entry_sink_, event_probe_);
  gst_pad_remove_probe(entry_sink_, buffer_probe_);
  gst_object_unref(entry_sink_);
}

void LiveSource::addFirst() {
  source_ = make_();
  gst_bin_add(GST_BIN(pipeline_), source_);
  // The clock of the first attempt starts at the first tick of the main loop, after the
  // pipeline's state change, which loads the models first.
  attempt_start_us_ = 0;
}

GstPadProbeReturn LiveSource::onEntryEvent(GstPad* pad, GstPadProbeInfo* info, gpointer data) {
  auto* self = static_cast<LiveSource*>(data);
  GstEvent* event = GST_PAD_PROBE_INFO_EVENT(info);
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_EOS:
      // The source's end is an outage, not the end of the run: the watchdog reconnects. Only the
      // EOS of a stop goes on, to finish the outputs.
      if (self->stopping_) return GST_PAD_PROBE_OK;
      self->ended_ = true;
      return GST_PAD_PROBE_DROP;
    case GST_EVENT_SEGMENT:
      // A reconnected source's segment maps its frames' PTS to the same running time as the
      // one before (both identity maps, as live sources stamp running time): dropped, since an
      // encoder downstream (--output-video's x264enc) loses the frames it still holds (2-3) on
      // a new segment. Any other segment goes on.
      return self->stream_starts_ > 1 && sameRunningTime(pad, event) ? GST_PAD_PROBE_DROP
                                                                     : GST_PAD_PROBE_OK;
    case GST_EVENT_STREAM_START: {
      // A rebuilt source starts a new stream. For the tracker it is the same camera: its tracks
      // live through an outage up to lost-time long (a STREAM_START would reset them); after a
      // longer one they start over. The first frame comes right after this event (a keyframe
      // at most a GOP later), so the outage is measured here.
      if (++self->stream_starts_ == 1) return GST_PAD_PROBE_OK;
      const double outage = self->secondsSince(self->last_frame_us_);
      self->tracks_reset_ = outage > self->lost_time_;
      return self->tracks_reset_ ? GST_PAD_PROBE_OK : GST_PAD_PROBE_DROP;
    }
    default:
      return GST_PAD_PROBE_OK;
  }
}

GstPadProbeReturn LiveSource::onEntryBuffer(GstPad*, GstPadProbeInfo*, gpointer data) {
  auto* self = static_cast<LiveSource*>(data);
  self->last_frame_us_ = g_get_monotonic_time();
  ++self->frames_;
  return GST_PAD_PROBE_OK;
}

double LiveSource::secondsSince(std::int64_t monotonic_us) const {
  return static_cast<double>(g_get_monotonic_time() - monotonic_us) / G_USEC_PER_SEC;
}

gboolean LiveSource::onTick(gpointer data) {
  auto* self = static_cast<LiveSource*>(data);
  if (self->state_ == State::kStopped) {
    self->tick_ = 0;
    return G_SOURCE_REMOVE;
  }
  if (self->state_ == State::kWaiting) return G_SOURCE_CONTINUE;
  if (self->attempt_start_us_ == 0) self->attempt_start_us_ = g_get_monotonic_time();
  if (self->ended_) {
    self->lost("the stream ended (the server closed it)");
    return G_SOURCE_CONTINUE;
  }
  const std::int64_t last = self->last_frame_us_;
  if (self->state_ == State::kConnecting) {
    if (self->frames_ > self->frames_at_attempt_) {
      self->state_ = State::kStreaming;
      self->failures_ = 0;
      if (self->lost_at_us_ != 0) {
        ++self->reconnections_;
        g_printerr("jointflow-track: %s: frames again after %.1f s without; %s\n",
                   self->description_.c_str(),
                   static_cast<double>(last - self->lost_at_us_) / G_USEC_PER_SEC,
                   self->tracks_reset_ ? "longer than lost-time: new tracks" : "the tracks go on");
      }
    } else if (self->secondsSince(self->attempt_start_us_) > self->options_.source_timeout) {
      char reason[96];
      std::snprintf(reason, sizeof reason, "no frame within %.1f s of connecting",
                    self->options_.source_timeout);
      self->lost(reason);
    }
  } else if (self->secondsSince(last) > self->options_.source_timeout) {
    char reason[64];
    std::snprintf(reason, sizeof reason, "no frame for %.1f s", self->options_.source_timeout);
    self->lost(reason);
  }
  return G_SOURCE_CONTINUE;
}

gboolean LiveSource::onRetry(gpointer data) {
  auto* self = static_cast<LiveSource*>(data);
  self->retry_ = 0;
  self->start();
  return G_SOURCE_REMOVE;
}

bool LiveSource::handleError(GstMessage* message, std::string* fatal) {
  GstObject* src = GST_MESSAGE_SRC(message);
  // A source already taken down posted it before it went: nothing more to do.
  if (!gst_object_has_as_ancestor(src, GST_OBJECT(pipeline_))) return true;
  if (!source_ || !gst_object_has_as_ancestor(src, GST_OBJECT(source_))) return false;
  if (stopping_) return true;  // the run is ending anyway
  GError* error = nullptr;
  gchar* debug = nullptr;
  gst_message_parse_error(message, &error, &debug);
  // rtspsrc's message is generic ("Could not read from resource."); the last line of its debug
  // text says what happened ("Could not receive message. (Timeout while waiting for server
  // response)"); the lines before it name source files and elements.
  std::string text = error->message;
  const char* detail = debug ? std::strrchr(debug, '\n') : nullptr;
  // ("Unauthorized" has the detail "Unauthorized (401)": the detail alone then.)
  if (detail && detail[1])
    text = g_str_has_prefix(detail + 1, error->message) ? std::string(detail + 1)
                                                        : text + " " + (detail + 1);
  g_free(debug);
  const bool refused =
      g_error_matches(error, GST_RESOURCE_ERROR, GST_RESOURCE_ERROR_NOT_AUTHORIZED);
  g_clear_error(&error);
  if (refused) {
    // Wrong credentials do not get better by asking again (and a camera may lock the account).
    GstUri* uri = gst_uri_from_string(description_.c_str());
    const bool has_user = uri && gst_uri_get_userinfo(uri);
    if (uri) gst_uri_unref(uri);
    *fatal = description_ + ": " + text +
             (has_user ? " (the server refused the user name or password)"
                       : " (the server asks for a user name and password: "
                         "rtsp://USER:PASSWORD@host/...)");
    return false;
  }
  lost(text);
  return true;
}

void LiveSource::lost(const std::string& reason) {
  if (state_ == State::kWaiting || state_ == State::kStopped) return;
  const bool was_streaming = state_ == State::kStreaming;
  tearDown();
  if (was_streaming) {
    lost_at_us_ = last_frame_us_;
    failures_ = 0;
  } else {
    ++failures_;
  }
  if (options_.attempts != 0 && failures_ >= options_.attempts) {
    state_ = State::kStopped;
    gave_up_ = description_ + ": no frames after " + std::to_string(failures_) + " attempt" +
               (failures_ == 1 ? "" : "s") + " (last: " + reason + ")";
    if (on_give_up) on_give_up();
    return;
  }
  state_ = State::kWaiting;
  // A stream that was flowing is asked for again at once (a dropped connection may come back in
  // an instant); then the waits double, each drawn in [1/2, 1] of its nominal value so that
  // cameras that failed together do not all come back in the same instant.
  static thread_local std::mt19937 random{std::random_device{}()};
  const auto delay =
      failures_ == 0 ? std::chrono::milliseconds(0)
                     : backoff_.delay(failures_, std::uniform_real_distribution<>(0, 1)(random));
  if (was_streaming)
    g_printerr("jointflow-track: %s: lost: %s; reconnecting\n", description_.c_str(),
               reason.c_str());
  else
    g_printerr("jointflow-track: %s: attempt %u%s failed: %s; next in %.1f s\n",
               description_.c_str(), failures_,
               options_.attempts ? (" of " + std::to_string(options_.attempts)).c_str() : "",
               reason.c_str(), static_cast<double>(delay.count()) / 1000);
  retry_ = g_timeout_add(static_cast<guint>(delay.count()), onRetry, this);
}

void LiveSource::start() {
  if (state_ == State::kStopped) return;
  source_ = make_();
  gst_bin_add(GST_BIN(pipeline_), source_);
  state_ = State::kConnecting;
  attempt_start_us_ = g_get_monotonic_time();
  frames_at_attempt_ = frames_;
  // Joins the running pipeline: its clock and base time, so that the new frames' running time
  // continues from the old ones' by the wall time in between.
  if (!gst_element_sync_state_with_parent(source_)) lost("could not start the source");
}

void LiveSource::tearDown() {
  if (!source_) return;
  gst_element_set_state(source_, GST_STATE_NULL);
  gst_bin_remove(GST_BIN(pipeline_), source_);
  source_ = nullptr;
  // Its EOS, if it sent one, was dropped; what comes next is the new source's.
  ended_ = false;
}

bool LiveSource::stop() {
  stopping_ = true;
  state_ = State::kStopped;
  if (retry_) g_source_remove(retry_);
  retry_ = 0;
  return gst_pad_send_event(entry_sink_, gst_event_new_eos());
}

}  // namespace jointflow::cli
