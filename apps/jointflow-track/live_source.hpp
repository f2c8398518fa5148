// Reconnection of a live network input (rtsp://, udp://, srt://, ...): when the source part of
// the pipeline fails (an error, an end of stream, or no frame for --source-timeout), it is taken
// down and built again after a wait that doubles from --reconnect-delay up to
// --reconnect-max-delay, while the rest of the pipeline (tracker, writers, publisher) keeps
// PLAYING. The tracker's time (the running time of each frame's PTS, on the pipeline clock) goes
// on through the outage: the first frame after it is stamped later by the outage's length.
// An outage no longer than the tracker's lost-time keeps the tracks (the new connection's
// STREAM_START, which would reset them, is dropped); after a longer one the tracks start over
// (it goes through): a track unseen for longer than lost-time is not kept, and the tracker
// would otherwise match its last pose to whoever stands near it however long the gap.
//
// Why not GStreamer's own: rtspsrc (1.22) retries only within one session (UDP -> TCP after
// `timeout`, `retry` for port allocation) and ends the stream when the server goes away;
// urisourcebin and uridecodebin3 do not reconnect; fallbacksrc, which does, is in gst-plugins-rs,
// which Debian bookworm does not package. rtspsrc's `tcp-timeout` bounds each connection attempt
// (set to --source-timeout).
#pragma once

#include <gst/gst.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "publish/reconnect_backoff.hpp"

namespace jointflow::cli {

struct ReconnectOptions {
  std::uint32_t attempts = 30;   ///< failed attempts in a row before giving up; 0 = forever
  double delay = 0.5;            ///< seconds before the second attempt; doubles after each failure
  double max_delay = 2.0;        ///< seconds: the longest wait between attempts
  double source_timeout = 10.0;  ///< seconds without a frame (or to the first) = source lost
};

void addReconnectOptions(CLI::App& app, ReconnectOptions& options);

/// Exit status of a run that gave up on its live source after the configured attempts: the camera
/// or the network is at fault, and a restart (systemd's Restart=on-failure) may find it back.
constexpr int kExitSourceLost = 3;

/// The live source of a pipeline and its reconnection. Runs on the main loop's thread, apart from
/// the pad probe on the entry (the streaming thread), which shares only atomics with it.
class LiveSource {
 public:
  /// @make builds a new source element (floating) whose video pad links to @entry's sink pad
  /// (the pad-added handler is @make's business); @description names the input in messages.
  /// @lost_time is the tracker's (seconds): an outage longer than that starts new tracks.
  LiveSource(GstElement* pipeline, GstElement* entry, std::function<GstElement*()> make,
             std::string description, const ReconnectOptions& options, double lost_time);
  ~LiveSource();
  LiveSource(const LiveSource&) = delete;
  LiveSource& operator=(const LiveSource&) = delete;

  /// Adds the first source to the pipeline (not started: the pipeline's PLAYING starts it).
  void addFirst();

  /// An error on the bus: true when it was the source's (or a torn-down source's) and is handled
  /// here (a reconnection), false when the run must end on it. A refusal of the credentials is not
  /// retried: the run ends with it, and @fatal holds the message to end it with.
  bool handleError(GstMessage* message, std::string* fatal);

  /// A stop was asked for: no further attempt, and the EOS that ends the run goes straight into
  /// the entry, so that it arrives whether or not a source is there and answering. False when the
  /// entry refused it (the pipeline is not running): end the run at once then.
  bool stop();

  /// Set when the attempts ran out: the message for the run's error (then exit kExitSourceLost).
  const std::string& gaveUp() const { return gave_up_; }

  /// Reconnections that brought frames again.
  std::uint32_t reconnections() const { return reconnections_; }

  /// Called when the attempts ran out (after gaveUp() is set): the run ends.
  std::function<void()> on_give_up;

 private:
  enum class State { kConnecting, kStreaming, kWaiting, kStopped };

  static GstPadProbeReturn onEntryEvent(GstPad*, GstPadProbeInfo* info, gpointer data);
  static GstPadProbeReturn onEntryBuffer(GstPad*, GstPadProbeInfo*, gpointer data);
  static gboolean onTick(gpointer data);
  static gboolean onRetry(gpointer data);

  void start();
  void lost(const std::string& reason);
  void tearDown();
  double secondsSince(std::int64_t monotonic_us) const;

  GstElement* pipeline_;
  GstPad* entry_sink_;
  std::function<GstElement*()> make_;
  std::string description_;
  ReconnectOptions options_;
  double lost_time_;
  gst::ReconnectBackoff backoff_;

  GstElement* source_ = nullptr;  ///< owned by the pipeline while it is in it
  State state_ = State::kConnecting;
  std::uint32_t failures_ = 0;  ///< attempts in a row that brought no frame
  std::uint32_t reconnections_ = 0;
  std::int64_t attempt_start_us_ = 0;
  std::uint64_t frames_at_attempt_ = 0;  ///< frames_ when the attempt started
  std::int64_t lost_at_us_ = 0;          ///< when the last frame before an outage came
  std::string gave_up_;
  guint tick_ = 0, retry_ = 0;
  gulong event_probe_ = 0, buffer_probe_ = 0;

  // Shared with the streaming thread.
  std::atomic<std::int64_t> last_frame_us_{0};  ///< g_get_monotonic_time() of the latest frame
  std::atomic<std::uint64_t> frames_{0};        ///< frames into the entry, all sources
  std::atomic<bool> ended_{false};              ///< the source sent EOS (dropped at the entry)
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint32_t> stream_starts_{0};
  std::atomic<bool> tracks_reset_{false};  ///< the last reconnection let the tracker start over
};

}  // namespace jointflow::cli
