/* jointflowtrack: estimates and tracks the 2D poses of every person in the video (JointFlow,
 * BMVC 2018) and attaches them to each buffer as GstJointFlowMeta (jointflowmeta.h), plus one
 * GstVideoRegionOfInterestMeta per person. */
#ifndef __GST_JOINTFLOW_TRACK_H__
#define __GST_JOINTFLOW_TRACK_H__

#include <gst/video/gstvideofilter.h>

G_BEGIN_DECLS

#define GST_TYPE_JOINTFLOW_TRACK (gst_jointflow_track_get_type())
G_DECLARE_FINAL_TYPE(GstJointFlowTrack, gst_jointflow_track, GST, JOINTFLOW_TRACK, GstVideoFilter)

GST_ELEMENT_REGISTER_DECLARE(jointflowtrack);

G_END_DECLS

#endif /* __GST_JOINTFLOW_TRACK_H__ */
