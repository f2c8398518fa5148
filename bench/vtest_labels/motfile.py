"""MOT text files and box overlap, without OpenCV: shared by the labelling tools, the benchmark
(bench/vtest_identity.py) and the label test (tests/bench/test_vtest_labels.py)."""


def read_mot(path):
    """{frame: {id: (x, y, w, h)}} of a MOT file (gt or prediction rows)."""
    out = {}
    with open(path) as rows:
        for line in rows:
            v = line.strip().split(",")
            if len(v) < 6:
                continue
            f, i = int(float(v[0])), int(float(v[1]))
            out.setdefault(f, {})[i] = tuple(float(x) for x in v[2:6])
    return out


def by_id(boxes, first=1, last=10**9):
    """{id: {frame: box}} of read_mot's {frame: {id: box}}, frames first..last."""
    out = {}
    for f, row in boxes.items():
        if first <= f <= last:
            for i, b in row.items():
                out.setdefault(i, {})[f] = b
    return out


def iou(p, q):
    iw = max(0.0, min(p[0] + p[2], q[0] + q[2]) - max(p[0], q[0]))
    ih = max(0.0, min(p[1] + p[3], q[1] + q[3]) - max(p[1], q[1]))
    inter = iw * ih
    union = p[2] * p[3] + q[2] * q[3] - inter
    return inter / union if union > 0 else 0.0


def match_frame(gt, pred, min_iou=0.5):
    """Greedy one-to-one pairs {gt id: pred id} of one frame, highest IoU first, IoU >= min_iou."""
    pairs = sorted(((iou(g, p), gi, pi) for gi, g in gt.items() for pi, p in pred.items()),
                   reverse=True)
    out, used = {}, set()
    for v, gi, pi in pairs:
        if v < min_iou:
            break
        if gi not in out and pi not in used:
            out[gi] = pi
            used.add(pi)
    return out
