/* jointflowoverlay: draws the tracked poses of GstJointFlowMeta (or GstVideoRegionOfInterestMeta
 * boxes when a frame has no JointFlow meta) onto the video. */
#ifndef __GST_JOINTFLOW_OVERLAY_H__
#define __GST_JOINTFLOW_OVERLAY_H__

#include <gst/video/gstvideofilter.h>

G_BEGIN_DECLS

#define GST_TYPE_JOINTFLOW_OVERLAY (gst_jointflow_overlay_get_type())
G_DECLARE_FINAL_TYPE(GstJointFlowOverlay, gst_jointflow_overlay, GST, JOINTFLOW_OVERLAY,
                     GstVideoFilter)

GST_ELEMENT_REGISTER_DECLARE(jointflowoverlay);

G_END_DECLS

#endif /* __GST_JOINTFLOW_OVERLAY_H__ */
