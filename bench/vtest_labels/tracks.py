"""One line per id of a MOT file: first and last frame, boxes, gaps, where it starts and ends.
   tracks.py BOXES.txt"""
import sys
import vlab

by_id = vlab.by_id(vlab.read_mot(sys.argv[1]))
for i in sorted(by_id, key=lambda i: min(by_id[i])):
    fs = sorted(by_id[i])
    gaps = [(a, b) for a, b in zip(fs, fs[1:]) if b - a > 1]
    foot = [by_id[i][fs[0]], by_id[i][fs[-1]]]  # bottom centres, where the person stands
    foot = ["(%d,%d)" % (x + w / 2, y + h) for x, y, w, h in foot]
    print("id %3d  %3d-%3d  n=%3d  %s -> %s  gaps %s" % (
        i, fs[0], fs[-1], len(fs), foot[0], foot[1],
        " ".join("%d-%d" % (a + 1, b - 1) for a, b in gaps)))
