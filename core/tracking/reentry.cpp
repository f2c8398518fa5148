// Re-entry (steps 6 and 7 of pose_associator.hpp's list, reentry_time): a confirmed track that
// ends is remembered as departed, with its appearance and where its person was last seen; a new
// track born near there that looks like them is not shown until it has been seen long enough to
// be recognised, and then takes the departed person's id back, or a new one; one that took a new
// id may still take a departed person's id back in its first seconds (recogniseLate).
#include <algorithm>
#include <cmath>

#include "track_book.hpp"

namespace jointflow {
using track_book::Track;

namespace {

// The best departed person must lead the next one by this much (two people who left and look
// alike: neither is guessed), and at most this many departed people are kept (the oldest go
// first).
constexpr float kReentryMargin = 0.03f;
constexpr size_t kMaxDeparted = 64;

// A departed person comes back near where they were last seen: within this fraction of the
// view's longer side. Why: a person who walks out on one side and comes back does so on that
// side, and the look of a first view at the border does not tell dark coats apart. On vtest.avi
// a small figure who left at the top left scored 0.94 against the man in the black coat coming
// back on the right 5 s later (his own departed track 0.97); the clip's returns all came back
// within 0.30 of the longer side of where they left, and the two sides are 0.97 of it apart.
constexpr float kReentryReach = 0.4f;

// A new track born near a departed person it resembles by at least reentry_min_similarity minus
// this waits to be recognised (reentry). Why: its first view, half in the view at the border,
// scores lower than the running appearance of its first frames: on vtest.avi the bald man
// coming back scored 0.85 against his departed track on his first frame, 0.92 on his seventh.
constexpr float kReentryDoubt = 0.1f;

// A confirmed track that took a new id keeps comparing its running look with the departed people
// within reach of where it was born for this long (stream seconds), and takes one's id back once
// it clearly is them (recogniseLate). Why: a first view can be too poor even to wait for
// recognition (two people coming back side by side are one pose at the border), and the look
// that decides at confirmation is still mostly that first view (each frame blends in 0.1). On
// vtest.avi the man in the grey coat and the woman beside him came back together: his first view
// scored 0.65 against his departed track, his running look 0.90 (ahead by 0.10) 3.7 s later;
// with recognise's own bounds, per person IDF1 84.2 -> 89.4 (f32: 80.4 -> 86.7, where it also
// gave a second person back, 2.3 s after he was born), with no wrong late decision in either
// (the late bounds below: 94.9, f32 92.1).
constexpr double kLateRecognitionTime = 10.0;

// The late test, against recognise's: a running look of seconds says more than one of 7 frames,
// so it may score kLateEase below reentry_min_similarity, but it must lead the next departed
// person by kLateMargin, not kReentryMargin; and the track may be born farther from where its
// person came in, within kLateReach of the view's longer side. Why: the woman who came back with
// the man in the grey coat was one pose with him until she stepped aside, mid-view, 0.47 of the
// longer side from where she had left; her running look reached 0.88 against her departed track,
// 0.13 ahead of the next. vtest.avi per person IDF1 89.4 -> 94.9 (f32 86.7 -> 92.1), no wrong
// decision; Bonn, its slow-engine cases and bench-outages unchanged with the default (auto).
constexpr float kLateEase = 0.05f;
constexpr float kLateMargin = 0.08f;
constexpr float kLateReach = 0.5f;

}  // namespace

// A track that ends: a confirmed, reported one is kept for reentry_time as departed (one entry
// per output id, the newest appearance); a revived track that ends tentative gives its entry
// back.
void PoseAssociator::Impl::depart(const Track& t) {
  if (!reentry()) return;
  Departed d;
  if (confirmed(t) && t.output_id >= 0) {
    d.output_id = t.output_id;
    d.appearance = t.appearance;
    d.time = time;
    d.last_seen = t.last_time;
    d.exit = t.motion.lastSeenCentre();
  } else if (t.revived) {
    d = *t.revived;
  } else {
    return;
  }
  departed.erase(std::remove_if(departed.begin(), departed.end(),
                                [&](const Departed& e) { return e.output_id == d.output_id; }),
                 departed.end());
  departed.push_back(std::move(d));
  if (departed.size() > kMaxDeparted) departed.erase(departed.begin());
}

// Step 3, for the departed: those older than reentry_time are forgotten; where the others were
// last seen follows the camera, as the tracks do.
void PoseAssociator::Impl::followDeparted() {
  departed.erase(
      std::remove_if(departed.begin(), departed.end(),
                     [&](const Departed& e) { return time - e.time > settings.reentry_time; }),
      departed.end());
  for (Departed& d : departed) d.exit = applyMotion(camera, d.exit);
}

// The departed people last seen before `t` was born, within reach of where it was born
// (`reach_share` of the view `view`'s longer side; everyone where the view is not known), whom its
// look resembles most and second most. (Someone seen after `t` was born is someone else: a person
// is not in two places. On vtest.avi a passer-by's track took, late, the id of the man whose track
// had been lost, not yet ended, when it was born.)
PoseAssociator::Impl::DepartedMatch PoseAssociator::Impl::nearestLook(const Track& t, cv::Size view,
                                                                      float reach_share) const {
  DepartedMatch m;
  const Descriptor& look = t.appearance;
  if (look.empty()) return m;
  const float reach = reach_share * static_cast<float>(std::max(view.width, view.height));
  for (size_t i = 0; i < departed.size(); ++i) {
    if (departed[i].last_seen >= t.start_time) continue;
    const cv::Point2f gap = departed[i].exit - t.born_at;
    if (!view.empty() && std::hypot(gap.x, gap.y) > reach) continue;
    const float v = appearanceSimilarity(departed[i].appearance, look);
    if (v > m.best) {
      m.second = m.best;
      m.best = v;
      m.index = static_cast<int>(i);
    } else {
      m.second = std::max(m.second, v);
    }
  }
  return m;
}

// Step 6, for a newborn track: it waits to be recognised (reentry_pending) where a departed
// person last seen near it comes close to looking like it (kReentryDoubt).
bool PoseAssociator::Impl::mayBeReturning(const Track& t, cv::Size view) const {
  if (!reentry() || departed.empty()) return false;
  return nearestLook(t, view, kReentryReach).best >=
         settings.reentry_min_similarity - kReentryDoubt;
}

// Step 7, for a track waiting to be recognised: once confirmed, or once contested_time has
// passed (a slow inference rate must not hide a person for seconds), its running appearance
// decides: at least reentry_min_similarity and ahead of the next departed person within reach
// by kReentryMargin takes that person's id back (and their entry: given back if the track ends
// tentative); otherwise it is someone new.
void PoseAssociator::Impl::recognise(Track& t, cv::Size view) {
  if (!t.reentry_pending) return;
  if (!confirmed(t) && time - t.start_time < settings.contested_time - 1e-9) return;
  t.reentry_pending = false;
  takeBack(t, view, settings.reentry_min_similarity, kReentryMargin, kReentryReach);
}

// Step 7, for a confirmed track that took a new id within kLateRecognitionTime: recognise's test
// on its running look now, with the late test's bounds; passed, the track is reported under the
// departed person's id from this frame on (its new id is not given out again).
void PoseAssociator::Impl::recogniseLate(Track& t, cv::Size view) {
  if (!reentry() || t.revived || t.output_id < 0 || !confirmed(t) ||
      time - t.start_time > kLateRecognitionTime)
    return;
  const std::int64_t shown = t.output_id;  // assigned when first reported: the id shown so far
  takeBack(t, view, settings.reentry_min_similarity - kLateEase, kLateMargin, kLateReach);
  if (t.output_id != shown) t.shown_before = shown;
}

// Recognition's test: the departed person within `reach_share` whom `t` looks most like, at
// least `min_similarity` and ahead of the next by `margin`, gives `t` their id (and their entry,
// given back should `t` end tentative).
void PoseAssociator::Impl::takeBack(Track& t, cv::Size view, float min_similarity, float margin,
                                    float reach_share) {
  const DepartedMatch m = nearestLook(t, view, reach_share);
  if (m.index < 0 || m.best < min_similarity || m.best - m.second < margin) return;
  t.revived = departed[m.index];
  t.output_id = t.revived->output_id;
  departed.erase(departed.begin() + m.index);
}

}  // namespace jointflow
