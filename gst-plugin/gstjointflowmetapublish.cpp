/**
 * SECTION:element-jointflowmetapublish
 * @title: jointflowmetapublish
 *
 * Publishes the poses `jointflowtrack` attached to each frame, one message per frame, to an MQTT
 * broker (libmosquitto), a Kafka topic (librdkafka) or a file. The message is exactly the record
 * `jointflowjsonwriter` writes for the frame (one serializer for both), without the newline;
 * with `source-id` set it carries `"source_id"`, and on Kafka the source id is also the message
 * key, so that one camera's frames stay in order in one partition.
 *
 * The video passes through untouched and is never held up by the network: the streaming thread
 * serializes the frame and queues the message; a thread of the element's own connects, sends
 * and reconnects. The queue holds at most `max-queue-size` messages: when the broker is slow or
 * gone, the oldest are dropped and counted (`messages-dropped`, and a warning at most once a
 * second). At EOS the element waits up to `flush-timeout` for what is queued to be delivered.
 *
 * The first connection is tried `max-connect-attempts` times (0: without end), waiting
 * 100 ms, 200 ms, ... up to `max-reconnect-interval` in between; then the element posts an
 * error. A connection lost later is retried for as long as the element runs, with the same
 * backoff, while the queue keeps the most recent messages. MQTT messages go out at QoS 1 and a
 * new connection is a new session: the few messages in flight when a connection breaks are
 * counted dropped, not sent twice. Kafka's producer is idempotent: librdkafka holds up to
 * `max-queue-size` more messages through an outage and delivers them in order, once.
 *
 * ## Example launch lines
 * |[
 * gst-launch-1.0 -e filesrc location=vtest.avi ! decodebin ! videoconvert ! jointflowtrack !
 *     jointflowmetapublish method=mqtt address=localhost:1883 topic=poses/camera1
 *     source-id=camera1 ! fakesink
 * gst-launch-1.0 -e v4l2src ! videoconvert ! jointflowtrack ! jointflowmetapublish
 *     method=kafka address=kafka1:9092,kafka2:9092 topic=poses source-id=camera1 ! fakesink
 * ]|
 */
#include "gstjointflowmetapublish.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "output_properties.hpp"
#include "pose_json.hpp"
#include "publish/config.hpp"
#include "publish/transports.hpp"
#include "publish/worker.hpp"
#include "setting_enum_types.h"
#include "setting_properties.hpp"

GST_DEBUG_CATEGORY_STATIC(gst_jointflow_meta_publish_debug);
#define GST_CAT_DEFAULT gst_jointflow_meta_publish_debug

namespace {

// The read-only counters, after the settings rows' ids (1 to publishProperties().size()).
enum Counter { kPublished = 1, kDropped, kRefused, kQueueDepth };

guint counterId(Counter counter) {
  return static_cast<guint>(jointflow::gst::publishProperties().size()) + counter;
}

}  // namespace

// One value per row of the transport table, the row's index its value.
GType gst_jointflow_publish_method_get_type(void) {
  static gsize type = 0;
  if (g_once_init_enter(&type)) {
    static std::vector<GEnumValue> values;
    g_once_init_leave(
        &type, jointflow::gst::registerEnumType("GstJointFlowPublishMethod",
                                                jointflow::gst::publishMethodView(), values));
  }
  return static_cast<GType>(type);
}

struct _GstJointFlowMetaPublish {
  GstBaseTransform parent;

  jointflow::gst::PublishElementSettings* settings;  // the properties, under the object lock

  // Between start and stop; the worker pointer is read under the object lock by get_property.
  jointflow::gst::PublishWorker* worker;
  jointflow::gst::FrameRecorder* recorder;
  guint64 published, dropped, refused;  // the totals of the last run, after stop
  gint64 last_refused_warning;          // monotonic µs, streaming thread only
  guint64 refused_since_warning;
};

G_DEFINE_TYPE(GstJointFlowMetaPublish, gst_jointflow_meta_publish, GST_TYPE_BASE_TRANSFORM);
GST_ELEMENT_REGISTER_DEFINE(jointflowmetapublish, "jointflowmetapublish", GST_RANK_NONE,
                            GST_TYPE_JOINTFLOW_META_PUBLISH);

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS("video/x-raw(ANY)"));
static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS("video/x-raw(ANY)"));

static void gst_jointflow_meta_publish_set_property(GObject* object, guint prop_id,
                                                    const GValue* value, GParamSpec* pspec) {
  jointflow::gst::setSettingProperty(object, *GST_JOINTFLOW_META_PUBLISH(object)->settings,
                                     jointflow::gst::publishProperties(), prop_id, value, pspec);
}

static void gst_jointflow_meta_publish_get_property(GObject* object, guint prop_id, GValue* value,
                                                    GParamSpec* pspec) {
  auto* self = GST_JOINTFLOW_META_PUBLISH(object);
  if (prop_id < counterId(kPublished)) {
    jointflow::gst::getSettingProperty(object, *self->settings, jointflow::gst::publishProperties(),
                                       prop_id, value, pspec);
    return;
  }
  GST_OBJECT_LOCK(self);
  const jointflow::gst::PublishWorker* w = self->worker;
  if (prop_id == counterId(kPublished))
    g_value_set_uint64(value, w ? w->delivered() : self->published);
  else if (prop_id == counterId(kDropped))
    g_value_set_uint64(value, w ? w->dropped() : self->dropped);
  else if (prop_id == counterId(kRefused))
    g_value_set_uint64(value, w ? w->refused() : self->refused);
  else if (prop_id == counterId(kQueueDepth))
    g_value_set_uint(value, w ? static_cast<guint>(w->queued()) : 0u);
  else
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, prop_id, pspec);
  GST_OBJECT_UNLOCK(self);
}

// A client id that two pipelines on one host, or two elements in one process, do not share (an
// MQTT broker disconnects the older of two clients with the same id).
static std::string defaultClientId(const std::string& source_id) {
  static std::atomic<unsigned> counter{0};
  return "jointflow-" + (source_id.empty() ? std::string(g_get_host_name()) : source_id) + "-" +
         std::to_string(getpid()) + "-" + std::to_string(counter++);
}

static gboolean gst_jointflow_meta_publish_start(GstBaseTransform* trans) {
  using namespace jointflow::gst;
  auto* self = GST_JOINTFLOW_META_PUBLISH(trans);
  GST_OBJECT_LOCK(self);
  const PublishElementSettings p = *self->settings;
  GST_OBJECT_UNLOCK(self);
  const TransportRow& transport_row = publishTransports().at(p.method);
  const std::string& address = p.address;
  const std::string& topic = p.topic;
  const std::string& source_id = p.source_id;
  std::string client_id = p.client_id;
  const std::string& config_file = p.config_file;
  PublishWorkerSettings settings;
  settings.max_connect_attempts = p.max_connect_attempts;
  settings.max_reconnect_interval = std::chrono::milliseconds(p.max_reconnect_interval_ms);
  settings.connect_timeout = std::chrono::milliseconds(p.connect_timeout_ms);
  settings.queue_capacity = p.max_queue_size;
  settings.max_message_size = p.max_message_size;
  if (client_id.empty()) client_id = defaultClientId(source_id);

  auto fail = [&](const std::string& text) {
    GST_ELEMENT_ERROR(self, RESOURCE, SETTINGS, ("%s", text.c_str()),
                      ("method=%s address=\"%s\" topic=\"%s\"", transport_row.name, address.c_str(),
                       topic.c_str()));
    return FALSE;
  };

  PublishConfig config;
  if (!config_file.empty()) {
    std::string error;
    auto loaded = loadPublishConfig(config_file, &error);
    if (!loaded) return fail(error + " (property config-file)");
    config = std::move(*loaded);
  }
  auto counters = std::make_shared<PublishCounters>();
  PublishLog log = [self](GstDebugLevel level, const std::string& text) {
    GST_CAT_LEVEL_LOG(GST_CAT_DEFAULT, level, self, "%s", text.c_str());
  };
  TransportRequest request;
  request.address = address;
  request.topic = topic;
  request.client_id = client_id;
  request.source_id = source_id;
  request.config = std::move(config);
  request.queue_capacity = settings.queue_capacity;
  request.max_reconnect_interval = settings.max_reconnect_interval;
  request.counters = counters;
  request.log = log;
  std::string error;
  std::unique_ptr<PublishTransport> transport =
      makeTransport(transport_row, std::move(request), &error);
  if (!transport) return fail(error);
  error = transport->prepare();
  if (!error.empty()) {
    if (!transport_row.broker()) {  // the file could not be opened
      GST_ELEMENT_ERROR(self, RESOURCE, OPEN_WRITE, ("%s (property address)", error.c_str()),
                        (nullptr));
      return FALSE;
    }
    return fail(error);
  }

  const std::string where =
      std::string(transport_row.name) + " " + address + (topic.empty() ? "" : " topic " + topic);
  auto on_fatal = [self, where](const std::string& why) {
    GST_ELEMENT_ERROR(self, RESOURCE, OPEN_WRITE,
                      ("Could not publish to %s: %s", where.c_str(), why.c_str()), (nullptr));
  };
  auto* worker = new PublishWorker(std::move(transport), counters, settings, log, on_fatal);
  GST_OBJECT_LOCK(self);
  self->worker = worker;
  self->recorder->reset(source_id);
  self->published = self->dropped = self->refused = 0;
  self->last_refused_warning = 0;
  self->refused_since_warning = 0;
  GST_OBJECT_UNLOCK(self);
  GST_INFO_OBJECT(self, "publishing to %s as client %s", where.c_str(), client_id.c_str());
  return TRUE;
}

static gboolean gst_jointflow_meta_publish_stop(GstBaseTransform* trans) {
  auto* self = GST_JOINTFLOW_META_PUBLISH(trans);
  GST_OBJECT_LOCK(self);
  jointflow::gst::PublishWorker* worker = self->worker;
  GST_OBJECT_UNLOCK(self);
  if (!worker) return TRUE;
  worker->stop();  // outside the lock: get_property may be called meanwhile
  GST_OBJECT_LOCK(self);
  self->published = worker->delivered();
  self->dropped = worker->dropped();
  self->refused = worker->refused();
  self->worker = nullptr;
  GST_OBJECT_UNLOCK(self);
  GST_INFO_OBJECT(self,
                  "%" G_GUINT64_FORMAT " frames: %" G_GUINT64_FORMAT
                  " published, %" G_GUINT64_FORMAT " dropped, %" G_GUINT64_FORMAT " refused",
                  self->recorder->frames(), self->published, self->dropped, self->refused);
  delete worker;
  return TRUE;
}

static gboolean gst_jointflow_meta_publish_set_caps(GstBaseTransform* trans, GstCaps* incaps,
                                                    GstCaps*) {
  GST_JOINTFLOW_META_PUBLISH(trans)->recorder->setCaps(incaps);
  return TRUE;
}

static GstFlowReturn gst_jointflow_meta_publish_transform_ip(GstBaseTransform* trans,
                                                             GstBuffer* buffer) {
  using Offer = jointflow::gst::PublishWorker::Offer;
  auto* self = GST_JOINTFLOW_META_PUBLISH(trans);
  const guint64 frame = self->recorder->frames();
  std::string message = self->recorder->next(buffer);
  const std::size_t size = message.size();
  const Offer offer = self->worker->offer(std::move(message));
  if (offer == Offer::Failed) return GST_FLOW_ERROR;  // the error is on the bus already
  if (offer == Offer::Refused) {
    // On the bus at most once a second, with the count, so that a stream of huge frames does
    // not flood the application.
    self->refused_since_warning++;
    const gint64 now = g_get_monotonic_time();
    if (self->last_refused_warning == 0 || now - self->last_refused_warning >= G_USEC_PER_SEC) {
      GST_ELEMENT_WARNING(self, RESOURCE, WRITE,
                          ("Frame %" G_GUINT64_FORMAT ": the message of %zu bytes is larger than "
                           "max-message-size (%u bytes) and was not published (%" G_GUINT64_FORMAT
                           " refused since the last warning)",
                           frame, size, static_cast<guint>(self->worker->maxMessageSize()),
                           self->refused_since_warning),
                          (nullptr));
      self->last_refused_warning = now;
      self->refused_since_warning = 0;
    }
  }
  return GST_FLOW_OK;
}

static gboolean gst_jointflow_meta_publish_sink_event(GstBaseTransform* trans, GstEvent* event) {
  auto* self = GST_JOINTFLOW_META_PUBLISH(trans);
  if (GST_EVENT_TYPE(event) == GST_EVENT_EOS && self->worker) {
    GST_OBJECT_LOCK(self);
    const guint timeout = self->settings->flush_timeout_ms;
    GST_OBJECT_UNLOCK(self);
    const guint64 left = self->worker->flush(std::chrono::milliseconds(timeout));
    if (left > 0)
      GST_ELEMENT_WARNING(self, RESOURCE, WRITE,
                          ("At EOS, %" G_GUINT64_FORMAT " message(s) were not published within "
                           "flush-timeout (%u ms); they are counted dropped",
                           left, timeout),
                          (nullptr));
    else
      GST_DEBUG_OBJECT(self, "EOS: every queued message settled");
  }
  return GST_BASE_TRANSFORM_CLASS(gst_jointflow_meta_publish_parent_class)
      ->sink_event(trans, event);
}

static void gst_jointflow_meta_publish_finalize(GObject* object) {
  auto* self = GST_JOINTFLOW_META_PUBLISH(object);
  delete self->worker;
  delete self->recorder;
  delete self->settings;
  G_OBJECT_CLASS(gst_jointflow_meta_publish_parent_class)->finalize(object);
}

static void gst_jointflow_meta_publish_class_init(GstJointFlowMetaPublishClass* klass) {
  auto* gobject_class = G_OBJECT_CLASS(klass);
  auto* element_class = GST_ELEMENT_CLASS(klass);
  auto* trans_class = GST_BASE_TRANSFORM_CLASS(klass);

  GST_DEBUG_CATEGORY_INIT(gst_jointflow_meta_publish_debug, "jointflowmetapublish", 0,
                          "JointFlow pose publisher (MQTT, Kafka, file)");

  gobject_class->set_property = gst_jointflow_meta_publish_set_property;
  gobject_class->get_property = gst_jointflow_meta_publish_get_property;
  gobject_class->finalize = gst_jointflow_meta_publish_finalize;

  // The settings from their rows (output_properties.cpp), then the counters.
  jointflow::gst::installSettingProperties(gobject_class, jointflow::gst::publishProperties());
  const auto ro = static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, counterId(kPublished),
      g_param_spec_uint64("messages-published", "Messages published",
                          "Messages the broker acknowledged (or written to the file)", 0,
                          G_MAXUINT64, 0, ro));
  g_object_class_install_property(
      gobject_class, counterId(kDropped),
      g_param_spec_uint64("messages-dropped", "Messages dropped",
                          "Messages not delivered: the queue was full, the connection broke with "
                          "them in flight, or they were still queued at stop",
                          0, G_MAXUINT64, 0, ro));
  g_object_class_install_property(
      gobject_class, counterId(kRefused),
      g_param_spec_uint64("messages-refused", "Messages refused",
                          "Messages larger than max-message-size (or than the client takes)", 0,
                          G_MAXUINT64, 0, ro));
  g_object_class_install_property(
      gobject_class, counterId(kQueueDepth),
      g_param_spec_uint("queue-depth", "Queue depth",
                        "Messages waiting in the queue for the broker now (at most "
                        "max-queue-size)",
                        0, G_MAXUINT, 0, ro));

  gst_element_class_set_static_metadata(
      element_class, "JointFlow pose publisher", "Filter/Analyzer/Video",
      "Publishes the tracked poses of every frame (the jointflowjsonwriter record) to MQTT, "
      "Kafka or a file, off the streaming thread",
      "JointFlow developers");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);

  trans_class->start = gst_jointflow_meta_publish_start;
  trans_class->stop = gst_jointflow_meta_publish_stop;
  trans_class->set_caps = gst_jointflow_meta_publish_set_caps;
  trans_class->transform_ip = gst_jointflow_meta_publish_transform_ip;
  trans_class->sink_event = gst_jointflow_meta_publish_sink_event;
  trans_class->transform_ip_on_passthrough = TRUE;
  gst_type_mark_as_plugin_api(GST_TYPE_JOINTFLOW_PUBLISH_METHOD, static_cast<GstPluginAPIFlags>(0));
}

static void gst_jointflow_meta_publish_init(GstJointFlowMetaPublish* self) {
  self->settings = new jointflow::gst::PublishElementSettings();
  self->worker = nullptr;
  self->recorder = new jointflow::gst::FrameRecorder();
  self->published = self->dropped = self->refused = 0;
  self->last_refused_warning = 0;
  self->refused_since_warning = 0;
  gst_base_transform_set_passthrough(GST_BASE_TRANSFORM(self), TRUE);
  gst_base_transform_set_in_place(GST_BASE_TRANSFORM(self), TRUE);
}
