/* The JointFlow GStreamer plugin: jointflowtrack, jointflowoverlay, jointflowjsonwriter and
 * jointflowmetapublish. */
#include <gst/gst.h>

#include "gstjointflowjsonwriter.h"
#include "gstjointflowmetapublish.h"
#include "gstjointflowoverlay.h"
#include "gstjointflowtrack.h"
#include "jointflowmeta.h"

#ifndef PACKAGE
#define PACKAGE "jointflow"
#endif

static gboolean plugin_init(GstPlugin* plugin) {
  // Registering the meta here makes it known before the first buffer carries it.
  gst_jointflow_meta_get_info();
  gboolean ok = GST_ELEMENT_REGISTER(jointflowtrack, plugin);
  ok &= GST_ELEMENT_REGISTER(jointflowoverlay, plugin);
  ok &= GST_ELEMENT_REGISTER(jointflowjsonwriter, plugin);
  ok &= GST_ELEMENT_REGISTER(jointflowmetapublish, plugin);
  return ok;
}

GST_PLUGIN_DEFINE(GST_VERSION_MAJOR, GST_VERSION_MINOR, jointflow,
                  "JointFlow: online multi-person pose estimation and tracking", plugin_init,
                  JOINTFLOW_VERSION, "MIT", "JointFlow", "https://github.com/jointflow/jointflow")
