/* jointflowmeta.h is plain C: this file is compiled as C and uses the whole reading API. */
#include <string.h>

#include "jointflowmeta.h"

#define EXPECT(cond)                                      \
  do {                                                    \
    if (!(cond)) {                                        \
      g_printerr ("%s:%d: failed: %s\n", __FILE__, __LINE__, #cond); \
      return 1;                                           \
    }                                                     \
  } while (0)

int
main (int argc, char **argv)
{
  GstBuffer *buffer;
  GstJointFlowMeta *meta;
  JointFlowPerson person;
  const JointFlowPerson *read;
  guint a = 0, b = 0;

  gst_init (&argc, &argv);
  buffer = gst_buffer_new ();
  meta = gst_buffer_add_jointflow_meta (buffer, 320, 240);
  memset (&person, 0, sizeof person);
  person.track_id = 42;
  person.tentative = TRUE;
  person.keypoints[JOINTFLOW_KEYPOINT_RIGHT_WRIST].x = 7.5f;
  person.keypoints[JOINTFLOW_KEYPOINT_RIGHT_WRIST].score = 0.5f;
  gst_jointflow_meta_add_person (meta, &person);

  meta = gst_buffer_get_jointflow_meta (buffer);
  EXPECT (meta != NULL && meta->width == 320 && meta->height == 240);
  EXPECT (gst_jointflow_meta_get_n_persons (meta) == 1);
  read = gst_jointflow_meta_get_person (meta, 0);
  EXPECT (read->track_id == 42 && read->tentative);
  EXPECT (read->keypoints[JOINTFLOW_KEYPOINT_RIGHT_WRIST].x == 7.5f);
  EXPECT (gst_jointflow_meta_get_person (meta, 1) == NULL);
  EXPECT (strcmp (jointflow_keypoint_name (JOINTFLOW_KEYPOINT_RIGHT_WRIST), "right_wrist") == 0);
  EXPECT (jointflow_keypoint_from_name ("nose") == JOINTFLOW_KEYPOINT_NOSE);
  EXPECT (jointflow_skeleton_get_n_limbs () == 19);
  EXPECT (jointflow_skeleton_get_limb (0, &a, &b) && a < JOINTFLOW_N_KEYPOINTS);
  gst_buffer_unref (buffer);
  return 0;
}
