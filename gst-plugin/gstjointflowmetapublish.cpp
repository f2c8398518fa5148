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

#include "file_transport.hpp"
#include "kafka_transport.hpp"
#include "mqtt_transport.hpp"
#include "pose_json.hpp"
#include "publish_address.hpp"
#include "publish_config.hpp"
#include "publish_worker.hpp"

GST_DEBUG_CATEGORY_STATIC(gst_jointflow_meta_publish_debug);
#define GST_CAT_DEFAULT gst_jointflow_meta_publish_debug

using jointflow::gst::PublishMethod;

namespace {

enum {
  PROP_0,
  PROP_METHOD,
  PROP_ADDRESS,
  PROP_TOPIC,
  PROP_CLIENT_ID,
  PROP_SOURCE_ID,
  PROP_CONFIG_FILE,
  PROP_MAX_CONNECT_ATTEMPTS,
  PROP_MAX_RECONNECT_INTERVAL,
  PROP_CONNECT_TIMEOUT,
  PROP_MAX_QUEUE_SIZE,
  PROP_MAX_MESSAGE_SIZE,
  PROP_FLUSH_TIMEOUT,
  PROP_MESSAGES_PUBLISHED,
  PROP_MESSAGES_DROPPED,
  PROP_MESSAGES_REFUSED,
  PROP_QUEUE_DEPTH,
};

constexpr PublishMethod DEFAULT_METHOD = PublishMethod::File;
constexpr guint DEFAULT_MAX_CONNECT_ATTEMPTS = 5;
constexpr guint DEFAULT_MAX_RECONNECT_INTERVAL_MS = 30000;
constexpr guint DEFAULT_CONNECT_TIMEOUT_MS = 5000;
constexpr guint DEFAULT_MAX_QUEUE_SIZE = 300;        // 10 s of 30 fps video
constexpr guint DEFAULT_MAX_MESSAGE_SIZE = 1000000;  // librdkafka's and Kafka's default limit
constexpr guint DEFAULT_FLUSH_TIMEOUT_MS = 5000;

}  // namespace

GType gst_jointflow_publish_method_get_type(void) {
  static gsize type = 0;
  if (g_once_init_enter(&type)) {
    static const GEnumValue values[] = {
        {static_cast<gint>(PublishMethod::File), "JSON Lines to a file (address: path, - = stdout)",
         "file"},
        {static_cast<gint>(PublishMethod::Mqtt), "MQTT broker (address: host:port)", "mqtt"},
        {static_cast<gint>(PublishMethod::Kafka),
         "Kafka cluster (address: bootstrap host:port[,host:port...])", "kafka"},
        {0, nullptr, nullptr}};
    g_once_init_leave(&type, g_enum_register_static("GstJointFlowPublishMethod", values));
  }
  return static_cast<GType>(type);
}

struct _GstJointFlowMetaPublish {
  GstBaseTransform parent;

  // Properties (under the object lock).
  PublishMethod method;
  gchar* address;
  gchar* topic;
  gchar* client_id;
  gchar* source_id;
  gchar* config_file;
  guint max_connect_attempts;
  guint max_reconnect_interval;
  guint connect_timeout;
  guint max_queue_size;
  guint max_message_size;
  guint flush_timeout;

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

static std::string str(const gchar* s) {
  return s ? s : "";
}

static void replaceString(gchar** field, const GValue* value) {
  g_free(*field);
  *field = g_value_dup_string(value);
}

static void gst_jointflow_meta_publish_set_property(GObject* object, guint prop_id,
                                                    const GValue* value, GParamSpec* pspec) {
  auto* self = GST_JOINTFLOW_META_PUBLISH(object);
  GST_OBJECT_LOCK(self);
  switch (prop_id) {
    case PROP_METHOD:
      self->method = static_cast<PublishMethod>(g_value_get_enum(value));
      break;
    case PROP_ADDRESS:
      replaceString(&self->address, value);
      break;
    case PROP_TOPIC:
      replaceString(&self->topic, value);
      break;
    case PROP_CLIENT_ID:
      replaceString(&self->client_id, value);
      break;
    case PROP_SOURCE_ID:
      replaceString(&self->source_id, value);
      break;
    case PROP_CONFIG_FILE:
      replaceString(&self->config_file, value);
      break;
    case PROP_MAX_CONNECT_ATTEMPTS:
      self->max_connect_attempts = g_value_get_uint(value);
      break;
    case PROP_MAX_RECONNECT_INTERVAL:
      self->max_reconnect_interval = g_value_get_uint(value);
      break;
    case PROP_CONNECT_TIMEOUT:
      self->connect_timeout = g_value_get_uint(value);
      break;
    case PROP_MAX_QUEUE_SIZE:
      self->max_queue_size = g_value_get_uint(value);
      break;
    case PROP_MAX_MESSAGE_SIZE:
      self->max_message_size = g_value_get_uint(value);
      break;
    case PROP_FLUSH_TIMEOUT:
      self->flush_timeout = g_value_get_uint(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, prop_id, pspec);
      break;
  }
  GST_OBJECT_UNLOCK(self);
}

static void gst_jointflow_meta_publish_get_property(GObject* object, guint prop_id, GValue* value,
                                                    GParamSpec* pspec) {
  auto* self = GST_JOINTFLOW_META_PUBLISH(object);
  GST_OBJECT_LOCK(self);
  switch (prop_id) {
    case PROP_METHOD:
      g_value_set_enum(value, static_cast<gint>(self->method));
      break;
    case PROP_ADDRESS:
      g_value_set_string(value, self->address);
      break;
    case PROP_TOPIC:
      g_value_set_string(value, self->topic);
      break;
    case PROP_CLIENT_ID:
      g_value_set_string(value, self->client_id);
      break;
    case PROP_SOURCE_ID:
      g_value_set_string(value, self->source_id);
      break;
    case PROP_CONFIG_FILE:
      g_value_set_string(value, self->config_file);
      break;
    case PROP_MAX_CONNECT_ATTEMPTS:
      g_value_set_uint(value, self->max_connect_attempts);
      break;
    case PROP_MAX_RECONNECT_INTERVAL:
      g_value_set_uint(value, self->max_reconnect_interval);
      break;
    case PROP_CONNECT_TIMEOUT:
      g_value_set_uint(value, self->connect_timeout);
      break;
    case PROP_MAX_QUEUE_SIZE:
      g_value_set_uint(value, self->max_queue_size);
      break;
    case PROP_MAX_MESSAGE_SIZE:
      g_value_set_uint(value, self->max_message_size);
      break;
    case PROP_FLUSH_TIMEOUT:
      g_value_set_uint(value, self->flush_timeout);
      break;
    case PROP_MESSAGES_PUBLISHED:
      g_value_set_uint64(value, self->worker ? self->worker->delivered() : self->published);
      break;
    case PROP_MESSAGES_DROPPED:
      g_value_set_uint64(value, self->worker ? self->worker->dropped() : self->dropped);
      break;
    case PROP_MESSAGES_REFUSED:
      g_value_set_uint64(value, self->worker ? self->worker->refused() : self->refused);
      break;
    case PROP_QUEUE_DEPTH:
      g_value_set_uint(value, self->worker ? static_cast<guint>(self->worker->queued()) : 0u);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, prop_id, pspec);
      break;
  }
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
  const PublishMethod method = self->method;
  const std::string address = str(self->address);
  const std::string topic = str(self->topic);
  const std::string source_id = str(self->source_id);
  std::string client_id = str(self->client_id);
  const std::string config_file = str(self->config_file);
  PublishWorkerSettings settings;
  settings.max_connect_attempts = self->max_connect_attempts;
  settings.max_reconnect_interval = std::chrono::milliseconds(self->max_reconnect_interval);
  settings.connect_timeout = std::chrono::milliseconds(self->connect_timeout);
  settings.queue_capacity = self->max_queue_size;
  settings.max_message_size = self->max_message_size;
  GST_OBJECT_UNLOCK(self);
  if (client_id.empty()) client_id = defaultClientId(source_id);

  auto fail = [&](const std::string& text) {
    GST_ELEMENT_ERROR(self, RESOURCE, SETTINGS, ("%s", text.c_str()),
                      ("method=%s address=\"%s\" topic=\"%s\"", publishMethodName(method),
                       address.c_str(), topic.c_str()));
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
  std::unique_ptr<PublishTransport> transport;
  std::string error;
  if (method == PublishMethod::File) {
    transport = std::make_unique<FileTransport>(address, counters);
  } else {
    auto endpoints = parseBrokerAddress(method, address, &error);
    if (!endpoints) return fail("Invalid address \"" + address + "\" (property address): " + error);
    error =
        method == PublishMethod::Mqtt ? MqttTransport::topicError(topic) : kafkaTopicError(topic);
    if (!error.empty()) return fail("Invalid topic \"" + topic + "\" (property topic): " + error);
    if (method == PublishMethod::Mqtt) {
      transport = std::make_unique<MqttTransport>(endpoints->front(), topic, client_id, config.mqtt,
                                                  counters, log);
    } else {
      KafkaTransport::Options options;
      options.bootstrap_servers = bootstrapServers(*endpoints);
      options.topic = topic;
      options.key = source_id;
      options.client_id = client_id;
      options.queue_limit = settings.queue_capacity;
      options.max_reconnect_interval = settings.max_reconnect_interval;
      options.config = config.kafka;
      transport = std::make_unique<KafkaTransport>(std::move(options), counters, log);
    }
  }
  error = transport->prepare();
  if (!error.empty()) {
    if (method == PublishMethod::File) {
      GST_ELEMENT_ERROR(self, RESOURCE, OPEN_WRITE, ("%s (property address)", error.c_str()),
                        (nullptr));
      return FALSE;
    }
    return fail(error);
  }

  const std::string where = std::string(publishMethodName(method)) + " " + address +
                            (topic.empty() ? "" : " topic " + topic);
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
    const guint timeout = self->flush_timeout;
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
  for (gchar* s : {self->address, self->topic, self->client_id, self->source_id, self->config_file})
    g_free(s);
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

  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
                                           GST_PARAM_MUTABLE_READY);
  const auto ro = static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_METHOD,
      g_param_spec_enum("method", "Method",
                        "Where the messages go: a file, an MQTT broker or Kafka",
                        GST_TYPE_JOINTFLOW_PUBLISH_METHOD, static_cast<gint>(DEFAULT_METHOD), rw));
  g_object_class_install_property(
      gobject_class, PROP_ADDRESS,
      g_param_spec_string("address", "Address",
                          "mqtt: host:port of the broker (default port 1883); kafka: bootstrap "
                          "servers host:port[,host:port...] (default port 9092); file: the path "
                          "(replaced if it exists; unset, empty or \"-\" is stdout)",
                          nullptr, rw));
  g_object_class_install_property(
      gobject_class, PROP_TOPIC,
      g_param_spec_string(
          "topic", "Topic",
          "MQTT topic (levels with '/', no wildcards) or Kafka topic ([a-zA-Z0-9._-], "
          "at most 249 characters); unused by method=file",
          nullptr, rw));
  g_object_class_install_property(
      gobject_class, PROP_CLIENT_ID,
      g_param_spec_string("client-id", "Client id",
                          "Client id given to the broker; unset: jointflow-<source-id or "
                          "host>-<pid>-<n>, unique per element",
                          nullptr, rw));
  g_object_class_install_property(
      gobject_class, PROP_SOURCE_ID,
      g_param_spec_string("source-id", "Source id",
                          "Name of the camera: written into every message as \"source_id\" and "
                          "used as the Kafka message key (one camera, one partition, in order)",
                          nullptr, rw));
  g_object_class_install_property(
      gobject_class, PROP_CONFIG_FILE,
      g_param_spec_string("config-file", "Config file",
                          "Key file with TLS and credentials: [mqtt] username, password, ca-file, "
                          "ca-path, cert-file, key-file, tls-insecure; [kafka] any librdkafka "
                          "property (security.protocol, sasl.*, ssl.*) (docs/gstreamer.md)",
                          nullptr, rw));
  g_object_class_install_property(
      gobject_class, PROP_MAX_CONNECT_ATTEMPTS,
      g_param_spec_uint("max-connect-attempts", "Max connect attempts",
                        "Attempts at the first connection before the element posts an error "
                        "(0: try without end); a connection lost later is always retried",
                        0, G_MAXUINT, DEFAULT_MAX_CONNECT_ATTEMPTS, rw));
  g_object_class_install_property(
      gobject_class, PROP_MAX_RECONNECT_INTERVAL,
      g_param_spec_uint("max-reconnect-interval", "Max reconnect interval",
                        "Longest wait between two connection attempts in ms: waits double from "
                        "100 ms up to this (each drawn in [1/2, 1] of it, so cameras spread)",
                        100, G_MAXUINT, DEFAULT_MAX_RECONNECT_INTERVAL_MS, rw));
  g_object_class_install_property(
      gobject_class, PROP_CONNECT_TIMEOUT,
      g_param_spec_uint("connect-timeout", "Connect timeout",
                        "How long one connection attempt may take, in ms", 100, 600000,
                        DEFAULT_CONNECT_TIMEOUT_MS, rw));
  g_object_class_install_property(
      gobject_class, PROP_MAX_QUEUE_SIZE,
      g_param_spec_uint("max-queue-size", "Max queue size",
                        "Messages held while the broker does not take them; beyond, the oldest "
                        "are dropped and counted (Kafka: librdkafka holds as many again)",
                        1, 1000000, DEFAULT_MAX_QUEUE_SIZE, rw));
  g_object_class_install_property(
      gobject_class, PROP_MAX_MESSAGE_SIZE,
      g_param_spec_uint("max-message-size", "Max message size",
                        "Largest message in bytes; a larger one is not published (counted "
                        "refused, with a warning)",
                        64, G_MAXINT, DEFAULT_MAX_MESSAGE_SIZE, rw));
  g_object_class_install_property(
      gobject_class, PROP_FLUSH_TIMEOUT,
      g_param_spec_uint("flush-timeout", "Flush timeout",
                        "At EOS, how long to wait in ms for the queued messages to be delivered", 0,
                        600000, DEFAULT_FLUSH_TIMEOUT_MS, rw));
  g_object_class_install_property(
      gobject_class, PROP_MESSAGES_PUBLISHED,
      g_param_spec_uint64("messages-published", "Messages published",
                          "Messages the broker acknowledged (or written to the file)", 0,
                          G_MAXUINT64, 0, ro));
  g_object_class_install_property(
      gobject_class, PROP_MESSAGES_DROPPED,
      g_param_spec_uint64("messages-dropped", "Messages dropped",
                          "Messages not delivered: the queue was full, the connection broke with "
                          "them in flight, or they were still queued at stop",
                          0, G_MAXUINT64, 0, ro));
  g_object_class_install_property(
      gobject_class, PROP_MESSAGES_REFUSED,
      g_param_spec_uint64("messages-refused", "Messages refused",
                          "Messages larger than max-message-size (or than the client takes)", 0,
                          G_MAXUINT64, 0, ro));
  g_object_class_install_property(
      gobject_class, PROP_QUEUE_DEPTH,
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
  self->method = DEFAULT_METHOD;
  self->address = nullptr;
  self->topic = nullptr;
  self->client_id = nullptr;
  self->source_id = nullptr;
  self->config_file = nullptr;
  self->max_connect_attempts = DEFAULT_MAX_CONNECT_ATTEMPTS;
  self->max_reconnect_interval = DEFAULT_MAX_RECONNECT_INTERVAL_MS;
  self->connect_timeout = DEFAULT_CONNECT_TIMEOUT_MS;
  self->max_queue_size = DEFAULT_MAX_QUEUE_SIZE;
  self->max_message_size = DEFAULT_MAX_MESSAGE_SIZE;
  self->flush_timeout = DEFAULT_FLUSH_TIMEOUT_MS;
  self->worker = nullptr;
  self->recorder = new jointflow::gst::FrameRecorder();
  self->published = self->dropped = self->refused = 0;
  self->last_refused_warning = 0;
  self->refused_since_warning = 0;
  gst_base_transform_set_passthrough(GST_BASE_TRANSFORM(self), TRUE);
  gst_base_transform_set_in_place(GST_BASE_TRANSFORM(self), TRUE);
}
