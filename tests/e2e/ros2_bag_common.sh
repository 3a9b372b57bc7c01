# Sourced by the bag round-trip tests (bag_roundtrip.sh, ros2_bag_roundtrip.sh), after common.sh.
# same_images <folder A> <folder B>: the same number of images, pixel for pixel, with the same times in their names
same_images() {
  /usr/bin/python3 - "$1" "$2" <<'PY' || fail "images differ between $1 and $2"
import cv2, os, sys
a, b = (sorted(os.listdir(d)) for d in sys.argv[1:3])
assert len(a) == len(b) and len(a) > 0, (len(a), len(b))
for x, y in zip(a, b):
    # stereo_<t_ns>_left.png; the rawlog's own timestamps are MRPT's 100 ns ticks (the simulator names its files
    # with the nanoseconds it computed, the rawlog holds them rounded to 100 ns)
    assert round(int(x.split("_")[-2]) / 100) == round(int(y.split("_")[-2]) / 100), (x, y)
    ia = cv2.imread(os.path.join(sys.argv[1], x), cv2.IMREAD_UNCHANGED)
    ib = cv2.imread(os.path.join(sys.argv[2], y), cv2.IMREAD_UNCHANGED)
    assert ia.dtype == ib.dtype and ia.shape == ib.shape and (ia == ib).all(), (x, y)
print(len(a), "images identical")
PY
}
# same_groundtruth <TUM A> <TUM B>: the same poses, positions within 1e-9 m
same_groundtruth() {
  /usr/bin/python3 - "$1" "$2" <<'PY' || fail "ground truth changed"
import sys
rows = [[list(map(float, l.split())) for l in open(p) if l.strip() and not l.startswith("#")] for p in sys.argv[1:]]
assert len(rows[0]) == len(rows[1]) > 0
assert max(abs(x - y) for a, b in zip(*rows) for x, y in zip(a[1:4], b[1:4])) < 1e-9
PY
}
