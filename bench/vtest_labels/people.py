"""The picture of the labels (docs/vtest-identity-labels.jpg): one row per person, for each of
their visits a few crops spread over it, titled with the visit's id and frames.
   people.py OUT.jpg [--per-visit 4] [--height 72]"""
import argparse
import os
import cv2
import numpy as np
import vlab

a = argparse.ArgumentParser()
a.add_argument("out")
a.add_argument("--per-visit", type=int, default=4)
a.add_argument("--height", type=int, default=72)
args = a.parse_args()
labels = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "data",
                      "vtest-identity")
boxes = vlab.by_id(vlab.read_mot(os.path.join(labels, "visits", "gt", "gt.txt")))
visits = [[int(x) for x in line.split(",")] for line in open(os.path.join(labels, "visits.txt"))
          if not line.startswith("#")]
names = dict(line.strip().split(",", 1) for line in open(os.path.join(labels, "persons.txt"))
             if not line.startswith("#"))
H, CW = args.height, args.height // 2
rows = []
for person in sorted({v[1] for v in visits}):
    cells = []
    for v, p, first, last, *_ in visits:
        if p != person:
            continue
        # Crops spread over the visit, skipping interpolated-looking ends by staying inside.
        picks = [int(round(first + (k + 0.5) * (last - first) / args.per_visit))
                 for k in range(args.per_visit)]
        block = np.zeros((H + 16, args.per_visit * CW + 6, 3), np.uint8)
        cv2.putText(block, "visit %d: %d-%d" % (v, first, last), (1, 11), 0, 0.35,
                    (255, 255, 255), 1)
        for k, f in enumerate(picks):
            x, y, w, h = boxes[v][f]
            c = vlab.frame(f)[int(y):int(y + h), int(x):int(x + w)]
            c = cv2.resize(c, (min(CW - 2, max(1, int(c.shape[1] * H / c.shape[0]))), H),
                           interpolation=cv2.INTER_AREA)
            block[16:, k * CW:k * CW + c.shape[1]] = c
        cells.append(block)
    title = np.zeros((H + 16, 230, 3), np.uint8)
    cv2.putText(title, "person %d" % person, (4, 20), 0, 0.55, (255, 255, 255), 1)
    words, line, y = names[str(person)].split(), "", 38
    for word in words:  # the description, wrapped
        if len(line) + len(word) > 34:
            cv2.putText(title, line, (4, y), 0, 0.35, (200, 200, 200), 1)
            line, y = "", y + 13
        line = (line + " " + word).strip()
    cv2.putText(title, line, (4, y), 0, 0.35, (200, 200, 200), 1)
    rows.append(np.hstack([title] + cells))
width = max(r.shape[1] for r in rows)
sheet = np.vstack([np.pad(r, ((0, 2), (0, width - r.shape[1]), (0, 0))) for r in rows])
cv2.imwrite(args.out, sheet, [cv2.IMWRITE_JPEG_QUALITY, 80])
