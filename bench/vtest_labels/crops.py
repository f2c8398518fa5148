"""Strips of crops: one row per id of a MOT file, a crop every STEP frames (padded, 96 px tall),
the frame number under each, so that an id passing from one person to another shows.
   crops.py BOXES.txt OUT.png [--ids 1,2] [--step 10] [--first 1] [--last 795] [--per-row 24]"""
import cv2
import numpy as np
import vlab

a = vlab.arguments("boxes", "out", "ids")
a.add_argument("--step", type=int, default=10)
a.add_argument("--first", type=int, default=1)
a.add_argument("--last", type=int, default=vlab.N)
a.add_argument("--per-row", type=int, default=24)
a.add_argument("--height", type=int, default=96)
args = a.parse_args()
boxes = vlab.read_mot(args.boxes)
by_id = vlab.by_id(boxes, args.first, args.last)
ids = [int(i) for i in args.ids.split(",") if i] or sorted(by_id, key=lambda i: min(by_id[i]))
H = args.height
cw = H // 2
rows = []
cache = {}
for i in ids:
    fs = sorted(by_id.get(i, {}))
    # Every STEP frames of the id's span plus its first and last frame.
    pick = [f for f in fs if (f - fs[0]) % args.step == 0] if fs else []
    if fs and fs[-1] not in pick:
        pick.append(fs[-1])
    cells = []
    for f in pick:
        if f not in cache:
            cache = {f: vlab.frame(f)}
        img = cache[f]
        x, y, w, h = by_id[i][f]
        pad = 0.1 * h
        x0, y0 = int(max(x - pad, 0)), int(max(y - pad, 0))
        x1, y1 = int(min(x + w + pad, vlab.W)), int(min(y + h + pad, vlab.H))
        c = img[y0:y1, x0:x1]
        if c.size == 0:
            c = np.zeros((H, cw, 3), np.uint8)
        s = H / c.shape[0]
        c = cv2.resize(c, (max(1, min(int(c.shape[1] * s), 2 * cw)), H))
        cell = np.zeros((H + 14, 2 * cw, 3), np.uint8)
        cell[:H, :c.shape[1]] = c
        cv2.putText(cell, str(f), (1, H + 12), 0, 0.4, (255, 255, 255), 1)
        cells.append(cell)
    for k in range(0, max(len(cells), 1), args.per_row):
        chunk = cells[k:k + args.per_row]
        row = np.zeros((H + 14, 40 + args.per_row * 2 * cw, 3), np.uint8)
        if k == 0:
            cv2.putText(row, str(i), (2, 40), 0, 0.8, vlab.colour(i), 2)
        for j, cell in enumerate(chunk):
            row[:, 40 + j * 2 * cw:40 + (j + 1) * 2 * cw] = cell
        rows.append(row)
        rows.append(np.full((3, row.shape[1], 3), 128, np.uint8))
cv2.imwrite(args.out, np.vstack(rows))
