/* JointFlow GStreamer metadata: the tracked poses of one video frame.
 *
 * `jointflowtrack` attaches one GstJointFlowMeta to every buffer it outputs (also to frames
 * without people, with n_persons = 0). It holds every pose of the frame: 17 keypoints in COCO
 * order (names via jointflow_keypoint_name()), each with a score (0 = not detected), the track
 * id, whether the track is still tentative, the person box and the person score. Coordinates are
 * in pixels of the frame the meta is attached to (x right, y down); the meta is scaled when the
 * frame is scaled (videoscale) and copied along by elements that copy metadata.
 *
 * Reading it, from a pad probe or an appsink:
 *
 *   GstJointFlowMeta *meta = gst_buffer_get_jointflow_meta (buffer);
 *   for (guint i = 0; meta && i < gst_jointflow_meta_get_n_persons (meta); i++) {
 *     const JointFlowPerson *p = gst_jointflow_meta_get_person (meta, i);
 *     const JointFlowKeypoint *nose = &p->keypoints[JOINTFLOW_KEYPOINT_NOSE];
 *     g_print ("track %" G_GINT64_FORMAT " nose %.1f,%.1f\n", p->track_id, nose->x, nose->y);
 *   }
 *
 * The header is plain C; link the `gstjointflowmeta` library (see gst-plugin/meson.build).
 */
#ifndef __GST_JOINTFLOW_META_H__
#define __GST_JOINTFLOW_META_H__

#include <gst/gst.h>

G_BEGIN_DECLS

/* Number of keypoints per person: the COCO-17 joint set. */
#define JOINTFLOW_N_KEYPOINTS 17

/* COCO-17 keypoint indices (the order of JointFlowPerson.keypoints). */
typedef enum {
  JOINTFLOW_KEYPOINT_NOSE = 0,
  JOINTFLOW_KEYPOINT_LEFT_EYE,
  JOINTFLOW_KEYPOINT_RIGHT_EYE,
  JOINTFLOW_KEYPOINT_LEFT_EAR,
  JOINTFLOW_KEYPOINT_RIGHT_EAR,
  JOINTFLOW_KEYPOINT_LEFT_SHOULDER,
  JOINTFLOW_KEYPOINT_RIGHT_SHOULDER,
  JOINTFLOW_KEYPOINT_LEFT_ELBOW,
  JOINTFLOW_KEYPOINT_RIGHT_ELBOW,
  JOINTFLOW_KEYPOINT_LEFT_WRIST,
  JOINTFLOW_KEYPOINT_RIGHT_WRIST,
  JOINTFLOW_KEYPOINT_LEFT_HIP,
  JOINTFLOW_KEYPOINT_RIGHT_HIP,
  JOINTFLOW_KEYPOINT_LEFT_KNEE,
  JOINTFLOW_KEYPOINT_RIGHT_KNEE,
  JOINTFLOW_KEYPOINT_LEFT_ANKLE,
  JOINTFLOW_KEYPOINT_RIGHT_ANKLE
} JointFlowKeypointIndex;

typedef struct {
  gfloat x;     /* pixels */
  gfloat y;     /* pixels */
  gfloat score; /* [0, 1]; 0 = not detected */
} JointFlowKeypoint;

typedef struct {
  gint64 track_id;    /* unique within the stream, counts up from 1, never reused */
  gboolean tentative; /* the track is shorter than jointflowtrack's min-track-length so far */
  gint age;           /* inferred frames since the track started */
  gfloat score;       /* person score in [0, 1] */
  gfloat x, y, width, height; /* person box in pixels (left, top, size) */
  JointFlowKeypoint keypoints[JOINTFLOW_N_KEYPOINTS];
  gfloat age_seconds; /* stream time since the track's first detection, seconds */
  gint64 previous_track_id; /* a person recognised late as someone who had left (reentry-time):
                             * the id they were shown under until then, on every frame from the
                             * change on; 0 = none */
} JointFlowPerson;

typedef struct {
  GstMeta meta;
  guint width; /* size of the frame the coordinates refer to */
  guint height;
  gboolean predicted; /* TRUE when the networks did not run on this frame (inference-interval,
                       * late frame): the poses were moved on from the last inferred frame */
  guint n_persons;
  JointFlowPerson* persons; /* n_persons entries; use the functions below */
} GstJointFlowMeta;

GType gst_jointflow_meta_api_get_type(void);
#define GST_JOINTFLOW_META_API_TYPE (gst_jointflow_meta_api_get_type())

const GstMetaInfo* gst_jointflow_meta_get_info(void);
#define GST_JOINTFLOW_META_INFO (gst_jointflow_meta_get_info())

/* The meta of @buffer, or NULL when it has none. */
GstJointFlowMeta* gst_buffer_get_jointflow_meta(GstBuffer* buffer);

/* Attaches an empty meta for a frame of @width x @height pixels; @buffer must be writable. */
GstJointFlowMeta* gst_buffer_add_jointflow_meta(GstBuffer* buffer, guint width, guint height);

guint gst_jointflow_meta_get_n_persons(const GstJointFlowMeta* meta);

/* The @index-th person (0 <= index < n_persons), or NULL when out of range. */
const JointFlowPerson* gst_jointflow_meta_get_person(const GstJointFlowMeta* meta, guint index);

/* Appends a person (copied) and returns the stored copy. */
JointFlowPerson* gst_jointflow_meta_add_person(GstJointFlowMeta* meta,
                                               const JointFlowPerson* person);

/* COCO name of keypoint @index ("nose", "left_eye", ...), or NULL when out of range. */
const gchar* jointflow_keypoint_name(guint index);

/* Index of the keypoint called @name, or -1. */
gint jointflow_keypoint_from_name(const gchar* name);

/* The COCO skeleton: limb @index joins keypoints *a and *b. FALSE when @index is out of range. */
guint jointflow_skeleton_get_n_limbs(void);
gboolean jointflow_skeleton_get_limb(guint index, guint* a, guint* b);

G_END_DECLS

#endif /* __GST_JOINTFLOW_META_H__ */
