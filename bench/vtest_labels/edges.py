"""Where each visit starts and ends (not at the clip's first or last frame): a row of the frames
around its first box (FIRST-8 ... FIRST+2) and one around its last (LAST-2 ... LAST+8), a window
about the box with every label drawn, to see whether the person is in view before or after.
   edges.py BOXES.txt OUT.png [--ids 1,2]"""
import cv2
import numpy as np
import vlab

a = vlab.arguments("boxes", "out", "ids")
a.add_argument("--size", type=int, default=200)
a.add_argument("--scale", type=float, default=0.8)
args = a.parse_args()
boxes = vlab.read_mot(args.boxes)
by_id = vlab.by_id(boxes)
keep = [int(i) for i in args.ids.split(",") if i] or sorted(by_id)
S = args.size
rows = []
for i in keep:
    fs = sorted(by_id[i])
    for end, frames in (("first", range(fs[0] - 8, fs[0] + 3, 2)),
                        ("last", range(fs[-1] - 2, fs[-1] + 9, 2))):
        ref = fs[0] if end == "first" else fs[-1]
        if ref in (1, vlab.N):
            continue
        x, y, w, h = by_id[i][ref]
        cx, cy = int(x + w / 2), int(y + h / 2)
        x0 = min(max(cx - S // 2, 0), vlab.W - S)
        y0 = min(max(cy - S // 2, 0), vlab.H - S)
        tiles = []
        for f in frames:
            if not 1 <= f <= vlab.N:
                tiles.append(np.zeros((int(S * args.scale), int(S * args.scale), 3), np.uint8))
                continue
            img = vlab.frame(f)[y0:y0 + S, x0:x0 + S].copy()
            b = {j: (bx - x0, by - y0, bw, bh) for j, (bx, by, bw, bh) in boxes.get(f, {}).items()}
            img = cv2.resize(img, None, fx=args.scale, fy=args.scale)
            vlab.draw(img, b, args.scale, 1, 0.5)
            cv2.putText(img, "%d:%d" % (i, f), (2, 14), 0, 0.45, (255, 255, 255), 1)
            tiles.append(img)
        rows.append(np.hstack(tiles))
cv2.imwrite(args.out, np.vstack(rows))
