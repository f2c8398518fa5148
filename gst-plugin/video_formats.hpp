// The raw video formats every JointFlow element accepts, in one place so that the elements
// negotiate the same set: packed 3-byte and 4-byte RGB orders (wrapped or repacked for the
// networks without a colour conversion) and the two YUV 4:2:0 layouts decoders produce most.
#pragma once

#include <gst/video/video.h>

#define JOINTFLOW_VIDEO_FORMATS "{ RGB, BGR, RGBx, BGRx, xRGB, xBGR, RGBA, BGRA, I420, NV12 }"
#define JOINTFLOW_VIDEO_CAPS GST_VIDEO_CAPS_MAKE(JOINTFLOW_VIDEO_FORMATS)

namespace jointflow::gst {

/// Always-present "sink" and "src" pads of JOINTFLOW_VIDEO_CAPS, for the in-place video elements.
inline void addVideoPadTemplates(GstElementClass* element_class) {
  GstCaps* caps = gst_caps_from_string(JOINTFLOW_VIDEO_CAPS);
  gst_element_class_add_pad_template(
      element_class, gst_pad_template_new("sink", GST_PAD_SINK, GST_PAD_ALWAYS, caps));
  gst_element_class_add_pad_template(
      element_class, gst_pad_template_new("src", GST_PAD_SRC, GST_PAD_ALWAYS, caps));
  gst_caps_unref(caps);
}

}  // namespace jointflow::gst
