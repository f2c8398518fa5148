/* jointflowjsonwriter: writes the poses of every frame as one JSON object per line (JSON Lines)
 * to a file or to stdout, passing the video through untouched. */
#ifndef __GST_JOINTFLOW_JSON_WRITER_H__
#define __GST_JOINTFLOW_JSON_WRITER_H__

#include <gst/base/gstbasetransform.h>

G_BEGIN_DECLS

#define GST_TYPE_JOINTFLOW_JSON_WRITER (gst_jointflow_json_writer_get_type())
G_DECLARE_FINAL_TYPE(GstJointFlowJsonWriter, gst_jointflow_json_writer, GST, JOINTFLOW_JSON_WRITER,
                     GstBaseTransform)

GST_ELEMENT_REGISTER_DECLARE(jointflowjsonwriter);

G_END_DECLS

#endif /* __GST_JOINTFLOW_JSON_WRITER_H__ */
