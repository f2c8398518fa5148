"""Tests of the training data path (run: training/.venv/bin/python -m unittest discover training/tests).

They use the real MoveNet ONNX file (models/) on synthetic frames and synthetic annotations, so the
expected targets are exact."""
import json
import os
import pathlib
import sys
import tempfile
import unittest

import cv2
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "training"))
from jointflow_train.dataset import PairDataset, box_iou, chain_tracks  # noqa: E402
from jointflow_train.posetrack import build_posetrack_cache, frame_to_grid  # noqa: E402
from jointflow_train.pseudo_labels import associate, motions_and_mask  # noqa: E402
from jointflow_train.spatial import MoveNet, fit_input, shrink_image  # noqa: E402

MODEL = str(ROOT / "models/movenet_multipose.onnx")
LEFT_WRIST, RIGHT_WRIST = 9, 10


def person(points, score=1.0):
    k = np.zeros((17, 3), np.float32)
    for j, (x, y) in points.items():
        k[j] = (x, y, score)
    return k


def body(dx=0.0, dy=0.0, scale=1.0):
    """A plausible 13-joint person around (20, 20) in grid cells."""
    base = {0: (20, 10), 5: (17, 14), 6: (23, 14), 7: (16, 18), 8: (24, 18), 9: (15, 22), 10: (25, 22),
            11: (18, 24), 12: (22, 24), 13: (18, 30), 14: (22, 30), 15: (18, 36), 16: (22, 36)}
    return person({j: (x * scale + dx, y * scale + dy) for j, (x, y) in base.items()})


class AssociationTest(unittest.TestCase):
    def test_clear_match_is_kept(self):
        self.assertEqual(associate([body(), body(dx=40)], [body(dx=1), body(dx=41)]), [(0, 0), (1, 1)])

    def test_ambiguous_people_are_not_matched(self):
        # Two people side by side, the one of frame t halfway between them: no safe choice.
        self.assertEqual(associate([body(dx=5)], [body(dx=0), body(dx=10)]), [])

    def test_unmatched_people_are_masked_and_matched_ones_give_motions(self):
        a, b = [body(), body(dx=40)], [body(dx=2)]
        motions, mask = motions_and_mask(a, b, [(0, 0)], (48, 80))
        self.assertEqual(len(motions), 13)
        self.assertTrue(all(abs(t[0] - f[0] - 2) < 1e-6 for _, f, t in motions))
        self.assertEqual(mask[:, 30, 60].max(), 0)   # inside the unmatched person
        labelled = [0] + list(range(5, 17))
        self.assertEqual(mask[labelled, 30, 20].min(), 1)  # inside the matched one, its joints
        self.assertEqual(mask[1:5, 30, 20].max(), 0)       # the joints it lacks: unknown, ignored
        self.assertEqual(mask[:, 45, 75].min(), 1)   # background


class ChainTest(unittest.TestCase):
    def test_identities_are_chained_through_consecutive_frames(self):
        # Two people walking towards each other: 12 cells apart, then 8, then 4 (their boxes
        # overlap in the last frame). Each step is unambiguous, so the chain carries both.
        frames = [[body(dx=0), body(dx=12)], [body(dx=2), body(dx=10)], [body(dx=10 - 6), body(dx=2 + 6)]]
        ids = chain_tracks(frames)
        self.assertEqual(list(ids[0]), [0, 1])
        self.assertEqual(list(ids[1]), [0, 1])
        self.assertEqual(list(ids[2]), [0, 1])

    def test_a_person_lost_for_a_frame_starts_a_new_chain(self):
        ids = chain_tracks([[body()], [], [body(dx=1)]])
        self.assertEqual([list(i) for i in ids], [[0], [], [1]])

    def test_box_iou(self):
        self.assertAlmostEqual(box_iou((0, 0, 2, 2), (1, 0, 3, 2)), 1 / 3)
        self.assertEqual(box_iou((0, 0, 1, 1), (2, 2, 3, 3)), 0)


class PoseTrackSourceTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.path.exists(MODEL):
            raise unittest.SkipTest(f"{MODEL} absent")
        cls.tmp = tempfile.TemporaryDirectory()
        root = pathlib.Path(cls.tmp.name)
        (root / "images/seq").mkdir(parents=True)
        images, annotations = [], []
        for f in range(3):
            cv2.imwrite(str(root / f"images/seq/{f:06d}.jpg"), np.full((240, 320, 3), 90, np.uint8))
            images.append(dict(file_name=f"images/seq/{f:06d}.jpg", id=100 + f, frame_id=100 + f, is_labeled=True,
                               ignore_regions_x=[[250, 300, 300, 250]] if f == 1 else [],
                               ignore_regions_y=[[150, 150, 200, 200]] if f == 1 else []))
            kp = np.zeros((17, 3))
            kp[LEFT_WRIST] = (100 + 40 * f, 100, 1)
            kp[1] = (50, 50, 1)  # head_bottom: no COCO counterpart, must be ignored
            annotations.append(dict(image_id=100 + f, track_id=7, keypoints=kp.ravel().tolist()))
            if f == 0:
                other = np.zeros((17, 3))
                other[5] = (200, 60, 1)
                annotations.append(dict(image_id=100, track_id=8, keypoints=other.ravel().tolist()))
        json_path = root / "seq.json"
        json_path.write_text(json.dumps(dict(images=images, annotations=annotations, categories=[])))
        cls.cache = str(root / "seq.npz")
        build_posetrack_cache(str(json_path), str(root), cls.cache, MoveNet(MODEL, "ort", 1), 320, 2,
                              np.random.default_rng(0), log=lambda s: None)
        cls.ds = PairDataset([cls.cache], strides=(1,), use_flips=True, use_warps=False)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def entry(self, variant, t):
        return self.ds.entries.index(("pair", 0, variant, t, 1))

    def test_grid_mapping_matches_the_input_policy(self):
        self.assertEqual(fit_input(np.zeros((240, 320, 3), np.uint8), 320).shape, (256, 320, 3))
        np.testing.assert_allclose(frame_to_grid(np.array([[100.0, 100.0]]), (320, 240), (320, 240)), [[25, 25]])

    def test_shrink_is_the_runtime_shrink(self):
        # jointflow::shrinkImage: exactly half is the area resize itself; one-pixel stripes shrunk
        # by 2.4x average to grey (a bilinear resize alone prints bands).
        rng = np.random.default_rng(3)
        image = cv2.GaussianBlur(rng.integers(0, 256, (720, 1280, 3), dtype=np.uint8), (0, 0), 1.5)
        np.testing.assert_array_equal(shrink_image(image, 640, 360),
                                      cv2.resize(image, (640, 360), interpolation=cv2.INTER_AREA))
        stripes = np.zeros((540, 960), np.uint8)
        stripes[:, 1::2] = 255
        small = shrink_image(stripes, 400, 225)
        self.assertEqual(small.shape, (225, 400))
        self.assertLess(small.std(), 2.0)
        self.assertIs(shrink_image(image, 1280, 720), image)

    def test_track_ids_give_the_motion_target(self):
        x, target, mask, motions, (_, _, matches) = self.ds.example(self.entry("orig", 0))
        self.assertEqual(x.shape, (82, 64, 80))
        self.assertEqual(matches, [(0, 0)])
        self.assertEqual(motions, [(LEFT_WRIST, (25.0, 25.0), (35.0, 25.0))])
        np.testing.assert_array_equal(target[2 * LEFT_WRIST, 25, 25:36], 1)
        self.assertEqual(target[2 * LEFT_WRIST, 25, 36], 0)
        self.assertEqual(np.abs(np.delete(target, 2 * LEFT_WRIST, 0)).max(), 0)
        self.assertEqual(mask[1:5].max(), 0)       # eyes, ears: not annotated in PoseTrack
        self.assertEqual(mask[0, 15, 50], 0)       # track 8 has no partner in frame 1
        self.assertEqual(mask[0, 44, 68], 0)       # frame 1's ignore region (grid ~62-75, 37-50)
        self.assertEqual(mask[0, 60, 10], 1)

    def test_reversed_pair_points_back(self):
        x, target, _, motions, (_, _, matches) = self.ds.example(self.entry("orig", 0), reverse=True)
        fwd = self.ds.example(self.entry("orig", 0))[0]
        np.testing.assert_array_equal(x[:41], fwd[41:])  # frame t+1's maps first
        self.assertEqual(motions, [(LEFT_WRIST, (35.0, 25.0), (25.0, 25.0))])
        np.testing.assert_array_equal(target[2 * LEFT_WRIST, 25, 25:36], -1)

    def test_flip_swaps_left_and_right(self):
        _, target, _, motions, _ = self.ds.example(self.entry("flip", 0))
        self.assertEqual(len(motions), 1)
        j, f, t = motions[0]
        self.assertEqual(j, RIGHT_WRIST)
        self.assertAlmostEqual(t[0] - f[0], -10.0, places=4)
        self.assertEqual(target[2 * RIGHT_WRIST].min(), -1)
        self.assertEqual(np.abs(target[2 * LEFT_WRIST]).max(), 0)


class ExportTest(unittest.TestCase):
    """The exported file computes what the trained model computes, on what the runner gives it."""

    def test_pooled_export_matches_the_model_and_reloads(self):
        import onnx
        import torch
        from jointflow_train.export import export_onnx, load_onnx, parity
        from jointflow_train.model import TFFNet
        torch.manual_seed(0)
        model = TFFNet(feature_channels=3, width=4, grid_stride=2)
        model.set_input_stats(torch.rand(40), torch.rand(40) + 0.5)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "tff.onnx")
            export_onnx(model, path, dict(steps=1))
            ops = [n.op_type for n in onnx.load(path).graph.node]
            self.assertNotIn("AveragePool", ops)  # the runner pools
            p = parity(model, path)
            self.assertEqual(p["shape"], [1, 34, 40, 56])
            self.assertLess(max(p["ort"], p["cv2"]), 1e-5 * max(1.0, p["ref_max"]))
            again, meta = load_onnx(path)
            self.assertEqual(meta["steps"], 1)
            x = torch.rand(1, 40, 12, 16)
            with torch.no_grad():
                self.assertLess((again(x) - model(x)).abs().max().item(), 1e-6)


if __name__ == "__main__":
    unittest.main()
