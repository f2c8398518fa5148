"""For each contact episode (contacts.py's lines on stdin: A B FIRST LAST ...), two rows of crops
of ids A and B from a few frames before to a few after: if the rows exchange looks, the ids swap.
   contacts.py BOXES | pairs.py BOXES OUT.png [--cells 12]"""
import argparse
import sys
import cv2
import numpy as np
import vlab

a = argparse.ArgumentParser()
a.add_argument("boxes")
a.add_argument("out")
a.add_argument("--cells", type=int, default=12)
a.add_argument("--height", type=int, default=80)
a.add_argument("--margin", type=int, default=8)
args = a.parse_args()
boxes = vlab.read_mot(args.boxes)
H, CW = args.height, args.height * 3 // 4
rows = []
for line in sys.stdin:
    w = line.split()
    i, j, f1, f2 = (int(v) for v in w[:4])
    lo, hi = f1 - args.margin, f2 + args.margin
    n = args.cells
    frames = sorted(set(int(round(lo + k * (hi - lo) / (n - 1))) for k in range(n)))
    for who in (i, j):
        row = np.zeros((H + 14, 60 + n * CW, 3), np.uint8)
        cv2.putText(row, "%d" % who, (2, 30), 0, 0.7, vlab.colour(who), 2)
        cv2.putText(row, "%d-%d" % (f1, f2), (2, 60), 0, 0.35, (255, 255, 255), 1)
        for k, f in enumerate(frames):
            b = boxes.get(f, {}).get(who)
            if b is None:
                continue
            img = vlab.frame(f)
            x, y, bw, bh = b
            pad = 0.1 * bh
            x0, y0 = int(max(x - pad, 0)), int(max(y - pad, 0))
            x1, y1 = int(min(x + bw + pad, vlab.W)), int(min(y + bh + pad, vlab.H))
            c = img[y0:y1, x0:x1]
            if c.size == 0:
                continue
            c = cv2.resize(c, (min(CW, max(1, int(c.shape[1] * H / c.shape[0]))), H))
            row[:H, 60 + k * CW:60 + k * CW + c.shape[1]] = c
            cv2.putText(row, str(f), (60 + k * CW, H + 12), 0, 0.35, (255, 255, 255), 1)
        rows.append(row)
    rows.append(np.full((4, rows[-1].shape[1], 3), 160, np.uint8))
cv2.imwrite(args.out, np.vstack(rows))
