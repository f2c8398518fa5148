"""Contact sheet: frames FIRST..LAST every STEP with the boxes of a MOT file drawn.
   sheet.py BOXES.txt FIRST LAST STEP OUT.jpg [--cols 3] [--scale 0.5] [--ids 1,2]"""
import argparse
import cv2
import vlab

a = argparse.ArgumentParser()
a.add_argument("boxes")
a.add_argument("first", type=int)
a.add_argument("last", type=int)
a.add_argument("step", type=int)
a.add_argument("out")
a.add_argument("--cols", type=int, default=3)
a.add_argument("--scale", type=float, default=0.5)
a.add_argument("--ids", default="")
a.add_argument("--crop", default="", help="x,y,w,h region of the frame to show")
a.add_argument("--grid", type=int, default=0, help="lines every N frame pixels, to read keys off")
args = a.parse_args()
boxes = vlab.read_mot(args.boxes)
keep = set(int(i) for i in args.ids.split(",") if i)
tiles = []
for f in range(args.first, args.last + 1, args.step):
    img = vlab.frame(f)
    b = {i: v for i, v in boxes.get(f, {}).items() if not keep or i in keep}
    ox = oy = 0
    if args.crop:
        ox, oy, cw, ch = (int(v) for v in args.crop.split(","))
        img = img[oy:oy + ch, ox:ox + cw].copy()
        b = {i: (x - ox, y - oy, w, h) for i, (x, y, w, h) in b.items()}
    img = cv2.resize(img, None, fx=args.scale, fy=args.scale, interpolation=cv2.INTER_AREA)
    if args.grid:
        for gx in range((ox // args.grid + 1) * args.grid, ox + img.shape[1], args.grid):
            px = int((gx - ox) * args.scale)
            cv2.line(img, (px, 0), (px, img.shape[0]), (0, 255, 255), 1)
            cv2.putText(img, str(gx), (px + 2, img.shape[0] - 4), 0, 0.4, (0, 255, 255), 1)
        for gy in range((oy // args.grid + 1) * args.grid, oy + img.shape[0], args.grid):
            py = int((gy - oy) * args.scale)
            cv2.line(img, (0, py), (img.shape[1], py), (0, 255, 255), 1)
            cv2.putText(img, str(gy), (2, py - 2), 0, 0.4, (0, 255, 255), 1)
    vlab.draw(img, b, args.scale, 1, 0.5 if args.scale < 0.7 else 0.7)
    cv2.putText(img, str(f), (4, 22), 0, 0.8, (0, 0, 0), 4)
    cv2.putText(img, str(f), (4, 22), 0, 0.8, (255, 255, 255), 2)
    tiles.append(img)
cv2.imwrite(args.out, vlab.grid(tiles, args.cols), [cv2.IMWRITE_JPEG_QUALITY, 85])
