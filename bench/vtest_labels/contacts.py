"""Episodes where two ids' boxes overlap (IoU above a threshold): where ids can swap, to be
checked by eye. Prints: ID_A ID_B FIRST LAST MAX_IOU.
   contacts.py BOXES.txt [--iou 0.2] [--gap 3]"""
import argparse
import vlab
from motfile import iou

a = argparse.ArgumentParser()
a.add_argument("boxes")
a.add_argument("--iou", type=float, default=0.2)
a.add_argument("--gap", type=int, default=3)
args = a.parse_args()


episodes = {}
for f, row in sorted(vlab.read_mot(args.boxes).items()):
    ids = sorted(row)
    for k, i in enumerate(ids):
        for j in ids[k + 1:]:
            v = iou(row[i], row[j])
            if v < args.iou:
                continue
            eps = episodes.setdefault((i, j), [])
            if eps and f - eps[-1][1] <= args.gap:
                eps[-1][1] = f
                eps[-1][2] = max(eps[-1][2], v)
            else:
                eps.append([f, f, v])
for (i, j), eps in sorted(episodes.items(), key=lambda e: e[1][0][0]):
    for f1, f2, v in eps:
        print("%d %d %d %d %.2f" % (i, j, f1, f2, v))
