#!/usr/bin/python3
"""How close the map sampled from a GMMLoc .gmm lies to the room's 3D line map.

Independent evidence: data/euroc/maps/lines/v1_line_3d.txt (and v2) were extracted from the same Leica scans as
the .gmm files, by other software. Points are taken along every segment (every 2 cm) and the distance from each
to the nearest map point is measured. A map in the right frame and on the right surfaces gives a median of about
the sampling spacing; a frame offset would show as a large median and a non-zero mean offset vector.

The GMM stops below the ceiling (the highest component mean is at 3.42 m) while the line map also holds the
ceiling's edges (up to z = 4.1 m), so the figures are printed for all line points and for those below
--below-z (default 3.4 m, the top of room 1's GMM; a fixed height, so that maps sampled with other options compare).

Usage (from the repository root):
  build/bin/map-import --input ../shared/data/euroc/maps/gmm/v1.gmm --output /tmp/v1.map --export /tmp/v1.ply
  /usr/bin/python3 scripts/gmm_map_check.py /tmp/v1.ply ../shared/data/euroc/maps/lines/v1_line_3d.txt \
      [--below-z 3.4] [--max-median-m 0.03]
The cloud is the PLY that map-import exports (binary_little_endian float x y z intensity) or an "x y z i" text.
With --max-median-m it exits 1 when the median over the line points below --below-z exceeds the bound.
Needs numpy and scipy (both in Debian's /usr/bin/python3 here).
"""
import argparse
import sys

import numpy as np

try:
    from scipy.spatial import cKDTree
except ImportError:
    sys.exit("gmm_map_check: needs scipy (apt install python3-scipy)")

STEP_M = 0.02


def read_cloud(path):
    with open(path, "rb") as f:
        data = f.read()
    if not data.startswith(b"ply"):
        return np.loadtxt(path, comments="#", delimiter=None)[:, :3]
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in header:
        sys.exit(f"gmm_map_check: {path}: expected a binary_little_endian PLY (map-import --export)")
    props = [line.split()[2] for line in header if line.startswith("property float")]
    count = int(next(line.split()[2] for line in header if line.startswith("element vertex")))
    rows = np.frombuffer(data, dtype="<f4", count=count * len(props), offset=end).reshape(count, len(props))
    return rows[:, [props.index("x"), props.index("y"), props.index("z")]].astype(np.float64)


def line_points(path):
    segs = np.loadtxt(path, ndmin=2)
    if segs.shape[1] != 6:
        sys.exit(f"gmm_map_check: {path}: expected rows x1 y1 z1 x2 y2 z2")
    pts = []
    for s in segs:
        a, b = s[:3], s[3:]
        n = max(2, int(np.linalg.norm(b - a) / STEP_M) + 1)
        pts.append(a + np.outer(np.linspace(0, 1, n), b - a))
    return np.vstack(pts), len(segs)


def report(name, d, offsets):
    near = d < 0.05
    mean_offset = offsets[near].mean(axis=0) if near.any() else np.zeros(3)
    print(f"{name:26s} {len(d):7d} points  median {np.median(d) * 100:6.2f} cm  p75 {np.percentile(d, 75) * 100:6.1f} cm"
          f"  p90 {np.percentile(d, 90) * 100:6.1f} cm  within 5 cm {near.mean() * 100:5.1f} %"
          f"  mean offset (within 5 cm) [{mean_offset[0] * 100:+.2f} {mean_offset[1] * 100:+.2f} {mean_offset[2] * 100:+.2f}] cm")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("cloud")
    ap.add_argument("lines")
    ap.add_argument("--below-z", type=float, default=3.4)
    ap.add_argument("--max-median-m", type=float, default=None)
    args = ap.parse_args()
    cloud = read_cloud(args.cloud)
    pts, nseg = line_points(args.lines)
    d, idx = cKDTree(cloud).query(pts)
    offsets = cloud[idx] - pts
    print(f"map {args.cloud}: {len(cloud)} points, z {cloud[:, 2].min():.2f}..{cloud[:, 2].max():.2f} m;"
          f" lines {args.lines}: {nseg} segments sampled every {STEP_M * 100:.0f} cm")
    report("all line points", d, offsets)
    below = pts[:, 2] <= args.below_z
    report(f"below z = {args.below_z} m", d[below], offsets[below])
    if args.max_median_m is not None:
        median = float(np.median(d[below]))
        if median > args.max_median_m:
            print(f"FAIL: median {median:.4f} m > {args.max_median_m} m", file=sys.stderr)
            return 1
        print(f"median {median:.4f} m <= {args.max_median_m} m")
    return 0


if __name__ == "__main__":
    sys.exit(main())
