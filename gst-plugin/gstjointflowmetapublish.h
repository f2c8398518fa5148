/* jointflowmetapublish: publishes the poses of every frame (the jointflowjsonwriter record) to
 * an MQTT broker, a Kafka topic or a file, from a thread of its own through a bounded queue,
 * passing the video through untouched. */
#ifndef __GST_JOINTFLOW_META_PUBLISH_H__
#define __GST_JOINTFLOW_META_PUBLISH_H__

#include <gst/base/gstbasetransform.h>

G_BEGIN_DECLS

#define GST_TYPE_JOINTFLOW_META_PUBLISH (gst_jointflow_meta_publish_get_type ())
G_DECLARE_FINAL_TYPE (GstJointFlowMetaPublish, gst_jointflow_meta_publish, GST,
    JOINTFLOW_META_PUBLISH, GstBaseTransform)

#define GST_TYPE_JOINTFLOW_PUBLISH_METHOD (gst_jointflow_publish_method_get_type ())
GType gst_jointflow_publish_method_get_type (void);

GST_ELEMENT_REGISTER_DECLARE (jointflowmetapublish);

G_END_DECLS

#endif /* __GST_JOINTFLOW_META_PUBLISH_H__ */
