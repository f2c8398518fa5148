"""Decodes vtest.avi once into FRAMES_DIR (NNNN.png from 1) for the other tools. Not committed.
   decode.py [VIDEO]"""
import os
import sys
import cv2
import vlab

os.makedirs(vlab.FRAMES_DIR, exist_ok=True)
video = cv2.VideoCapture(sys.argv[1] if len(sys.argv) > 1 else vlab.VIDEO)
n = 0
while True:
    ok, img = video.read()
    if not ok:
        break
    n += 1
    cv2.imwrite(os.path.join(vlab.FRAMES_DIR, "%04d.png" % n), img)
print(n, "frames in", vlab.FRAMES_DIR)
