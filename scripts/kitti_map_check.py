#!/usr/bin/python3
"""What the real KITTI map (../shared/data/kitti_raw_seq78) can and cannot offer a camera-to-map term.

Independent of the C++ code (numpy + OpenCV on the raw PLY and poses), so that it checks the renderer and the
direct term rather than repeating them. Prints three tables:

 1. Moving vehicles in the map. The map fuses the scans of a creeping traffic queue. Map points inside the
    volume that the ego car's own body later drove through (between the first and the last camera position,
    0.3-1.4 m above the road, within 0.8 m of the camera's path) cannot be static: something stood there and
    left. Then, per lane, where along the road the map holds points 0.5-3 m above the road: a queue of separate
    vehicles would show gaps; a smeared track shows none.
 2. Cost profile of normalised mutual information (camera grey level against map reflectivity, Wolcott &
    Eustice) at the exact map points, occlusion-filtered: over all visible points and over road-surface points
    only. Share of the 12 one-step neighbours (0.1 m along / 1 deg about each camera axis) that score below the
    true pose: a term usable for refinement needs ~100 %.
 3. From the true pose, a pattern search maximising the road-surface NMI: where its own optimum lies
    (success = within 0.1 m and 0.5 deg, the bench's criterion).

With --overlays DIR it also writes, for the first and the last query frame, DIR/frame_NN.png: the camera image,
the map's reflectivity seen from the true pose (nearest point per pixel, within 40 m), and the map's inverse depth
laid over the image (where the map and the image disagree is where a camera-to-map term is misled).

Usage (from the repository root):
  /usr/bin/python3 scripts/kitti_map_check.py [data_dir] [--frames-step N] [--overlays DIR]
Takes about two minutes on two cores.
"""
import argparse
import os
import sys

import cv2
import numpy as np

WIDTH, HEIGHT = 1242, 375
MAX_DEPTH_M = 40.0
ROAD_BAND_M = 0.12  # a map point within this of its cell's road height is road surface


def fail(msg):
    print(f"kitti_map_check: {msg}", file=sys.stderr)
    sys.exit(1)


def load_ply_xyzi(path):
    """Binary little-endian PLY with float32 x y z intensity (the dataset's format, checked)."""
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline()
            if not line:
                fail(f"{path}: no end_header")
            header.append(line.decode("ascii", "replace").strip())
            if header[-1] == "end_header":
                break
        n = next((int(h.split()[-1]) for h in header if h.startswith("element vertex")), None)
        props = [h.split()[-1] for h in header if h.startswith("property")]
        if n is None or props != ["x", "y", "z", "intensity"] or "format binary_little_endian 1.0" not in header:
            fail(f"{path}: expected a binary little-endian PLY of float32 x y z intensity")
        data = np.frombuffer(f.read(n * 16), dtype="<f4")
        if data.size != n * 4:
            fail(f"{path}: truncated ({data.size // 4} of {n} points)")
    data = data.reshape(n, 4)
    return data[:, :3].astype(np.float64), data[:, 3].astype(np.float64)


def load_poses(path):
    poses = []
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        T = np.eye(4)
        T[:3] = np.array(line.split(), float).reshape(3, 4)
        poses.append(T)
    return poses


def load_k(path):
    for line in open(path):
        if line.startswith("K_cam2:"):
            return np.array(line.split()[1:], float).reshape(3, 3)
    fail(f"{path}: no K_cam2 line")


def road_height(P):
    """Per 1 m x 1 m cell of the world x-y plane (z is up), the 5th percentile of the points' z."""
    cells = np.floor(P[:, :2]).astype(np.int64)
    key = (cells[:, 0] + 100000) * 200000 + (cells[:, 1] + 100000)
    order = np.argsort(key, kind="stable")
    uniq, start, count = np.unique(key[order], return_index=True, return_counts=True)
    z_sorted = P[order, 2]
    low = np.array([np.percentile(z_sorted[s:s + c], 5) for s, c in zip(start, count)])
    return low[np.searchsorted(uniq, key)]


def right_perturb(T, d):
    """T * exp(d), d = [rotation vector (rad); translation (m)] in the camera frame."""
    E = np.eye(4)
    E[:3, :3] = cv2.Rodrigues(np.asarray(d[:3], float).reshape(3, 1))[0]
    E[:3, 3] = d[3:]
    return T @ E


def project(K, T_cam_world, Q):
    c = Q @ T_cam_world[:3, :3].T + T_cam_world[:3, 3]
    z = c[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        return K[0, 0] * c[:, 0] / z + K[0, 2], K[1, 1] * c[:, 1] / z + K[1, 2], z


def visible_points(K, P, T_world_cam):
    """Indices of the points in view and not behind a nearer surface (5x5 min z-buffer, 3 % margin)."""
    u, v, z = project(K, np.linalg.inv(T_world_cam), P)
    ok = (z > 0.5) & (z < MAX_DEPTH_M) & (u >= 0) & (u < WIDTH - 1) & (v >= 0) & (v < HEIGHT - 1)
    ui, vi, zi = u[ok].astype(int), v[ok].astype(int), z[ok]
    zbuf = np.full((HEIGHT, WIDTH), np.inf, np.float32)
    np.minimum.at(zbuf, (vi, ui), zi.astype(np.float32))
    zbuf = cv2.erode(zbuf, np.ones((5, 5), np.uint8))  # min filter: splats the sparse points
    idx = np.nonzero(ok)[0]
    return idx[zi <= zbuf[vi, ui] * 1.03 + 0.05]


def nmi(a, b, bins=24):
    joint, _, _ = np.histogram2d(a, b, bins=bins, range=[[0, 1], [0, 1]])
    p = joint / joint.sum()

    def entropy(q):
        q = q[q > 0]
        return -np.sum(q * np.log(q))

    return (entropy(p.sum(1)) + entropy(p.sum(0))) / entropy(p)


def nmi_at(K, gray, T_world_cam, Q, refl):
    u, v, z = project(K, np.linalg.inv(T_world_cam), Q)
    ok = (z > 0.5) & (u >= 0) & (u < WIDTH - 1) & (v >= 0) & (v < HEIGHT - 1)
    if ok.sum() < 50:
        return 1.0
    u, v = u[ok], v[ok]
    x0, y0 = u.astype(int), v.astype(int)
    fx, fy = u - x0, v - y0
    g = (gray[y0, x0] * (1 - fx) * (1 - fy) + gray[y0, x0 + 1] * fx * (1 - fy) + gray[y0 + 1, x0] * (1 - fx) * fy
         + gray[y0 + 1, x0 + 1] * fx * fy)
    return nmi(g, refl[ok])


def steps_6dof(step_m, step_rad):
    for axis in range(6):
        for sign in (-1, 1):
            d = np.zeros(6)
            d[axis] = sign * (step_rad if axis < 3 else step_m)
            yield d


def pattern_search(score, T0, schedule, max_evals=400):
    T, best, evals = T0.copy(), score(T0), 0
    for step_m, step_rad in schedule:
        improved = True
        while improved and evals < max_evals:
            improved = False
            for d in steps_6dof(step_m, step_rad):
                Tn = right_perturb(T, d)
                s = score(Tn)
                evals += 1
                if s > best:
                    T, best, improved = Tn, s, True
    return T


def pose_error(T_est, T_true):
    E = np.linalg.inv(T_true) @ T_est
    angle = np.degrees(np.arccos(np.clip((np.trace(E[:3, :3]) - 1) / 2, -1, 1)))
    return E[:3, 3], angle


def write_overlays(out_dir, data_dir, P, refl, poses, K, frames):
    """Camera image, map reflectivity and map inverse depth over the image, stacked, per frame (see the docstring)."""
    os.makedirs(out_dir, exist_ok=True)
    for k in frames:
        img = cv2.imread(os.path.join(data_dir, "image_02", f"{k:010d}.png"), cv2.IMREAD_COLOR)
        if img is None or img.shape[:2] != (HEIGHT, WIDTH):
            fail(f"{data_dir}/image_02/{k:010d}.png: cannot read a {WIDTH}x{HEIGHT} image")
        u, v, z = project(K, np.linalg.inv(poses[k]), P)
        ok = (z > 0.5) & (z < MAX_DEPTH_M) & (u >= 0) & (u < WIDTH) & (v >= 0) & (v < HEIGHT)
        ui, vi, zi, ri = u[ok].astype(int), v[ok].astype(int), z[ok], refl[ok]
        far_first = np.argsort(-zi)  # the nearest point of a pixel is written last
        depth = np.full((HEIGHT, WIDTH), np.inf)
        reflectivity = np.zeros((HEIGHT, WIDTH))
        depth[vi[far_first], ui[far_first]] = zi[far_first]
        reflectivity[vi[far_first], ui[far_first]] = ri[far_first]
        hit = np.isfinite(depth)
        inv_depth = np.zeros((HEIGHT, WIDTH), np.uint8)
        inv_depth[hit] = np.clip(255 * 3.0 / np.maximum(depth[hit], 1.0), 0, 255).astype(np.uint8)
        coloured = cv2.applyColorMap(inv_depth, cv2.COLORMAP_JET)
        overlay = img.copy()
        overlay[hit] = (0.5 * img[hit] + 0.5 * coloured[hit]).astype(np.uint8)
        refl_img = cv2.cvtColor(np.clip(255 * 2 * reflectivity, 0, 255).astype(np.uint8), cv2.COLOR_GRAY2BGR)
        path = os.path.join(out_dir, f"frame_{k:02d}.png")
        if not cv2.imwrite(path, np.vstack([img, refl_img, overlay])):
            fail(f"{path}: cannot write")
        print(f"overlay written to {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("data_dir", nargs="?", default="../shared/data/kitti_raw_seq78")
    ap.add_argument("--frames-step", type=int, default=2, help="query frames 1, 1+N, ... (odd N is an error)")
    ap.add_argument("--overlays", metavar="DIR", help="write camera / map reflectivity / depth overlay PNGs here")
    args = ap.parse_args()
    if args.frames_step <= 0 or args.frames_step % 2:
        fail(f"--frames-step {args.frames_step}: must be a positive even number (the queries are the odd frames)")
    d = args.data_dir
    for name in ("map_even_frames_5cm.ply", "poses_cam2.txt", "calib.txt", "image_02"):
        if not os.path.exists(os.path.join(d, name)):
            fail(f"{d}: no {name} (is this kitti_raw_seq78?)")
    P, refl = load_ply_xyzi(os.path.join(d, "map_even_frames_5cm.ply"))
    poses = load_poses(os.path.join(d, "poses_cam2.txt"))
    K = load_k(os.path.join(d, "calib.txt"))
    if args.overlays:
        write_overlays(args.overlays, d, P, refl, poses, K, [1, len(poses) - 1 if (len(poses) - 1) % 2 else len(poses) - 2])
    height = P[:, 2] - road_height(P)
    road = np.abs(height) < ROAD_BAND_M
    print(f"map: {len(P)} points, {road.sum()} on the road surface (within {ROAD_BAND_M} m of their cell's road height)")

    # 1. Moving vehicles. World = velodyne frame of frame 0 (x forward, z up); the drive is straight along x.
    cam = np.array([T[:3, 3] for T in poses])
    x0, x1, y_path = cam[0, 0], cam[-1, 0], np.median(cam[:, 1])
    swept = (np.abs(P[:, 1] - y_path) < 0.8) & (height > 0.3) & (height < 1.4) & (P[:, 0] > x0 + 0.5) & (P[:, 0] < x1)
    print(f"\n## 1. Moving vehicles in the map\nthe camera moved {x1 - x0:.2f} m along x; map points inside the volume the ego "
          f"car's body later drove through (x {x0 + 0.5:.2f}..{x1:.2f} m, |y - {y_path:.2f}| < 0.8 m, 0.3-1.4 m above "
          f"the road): {swept.sum()}")
    print("points 0.5-3 m above the road per 0.5 m along x (0-60 m; '#' > 50 points, '+' > 5, '.' fewer):")
    for name, (ya, yb) in (("right lane", (-5.0, -2.2)), ("own lane", (-1.5, 1.5)), ("left lane", (2.2, 5.0))):
        m = (P[:, 1] > ya) & (P[:, 1] < yb) & (height > 0.5) & (height < 3.0)
        hist, _ = np.histogram(P[m, 0], bins=120, range=(0, 60))
        print(f"  {name:10s} " + "".join("#" if c > 50 else ("+" if c > 5 else ".") for c in hist))

    # 2 and 3: per query frame.
    frames = list(range(1, len(poses), args.frames_step))
    wins = {"all visible points": 0, "road surface only": 0}
    results = []
    schedule = [(0.1, np.radians(0.5)), (0.05, np.radians(0.25)), (0.025, np.radians(0.12)), (0.012, np.radians(0.06))]
    for k in frames:
        path = os.path.join(d, "image_02", f"{k:010d}.png")
        img = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
        if img is None or img.shape != (HEIGHT, WIDTH):
            fail(f"{path}: cannot read a {WIDTH}x{HEIGHT} image")
        gray = cv2.GaussianBlur(img.astype(np.float32) / 255, (0, 0), 1.0)
        T_true = poses[k]
        vis = visible_points(K, P, T_true)
        sets = {"all visible points": vis, "road surface only": vis[road[vis]]}
        for name, sel in sets.items():
            s0 = nmi_at(K, gray, T_true, P[sel], refl[sel])
            wins[name] += sum(s0 > nmi_at(K, gray, right_perturb(T_true, d), P[sel], refl[sel])
                              for d in steps_6dof(0.1, np.radians(1.0)))
        sel = sets["road surface only"]
        T_end = pattern_search(lambda T: nmi_at(K, gray, T, P[sel], refl[sel]), T_true, schedule)
        t, angle = pose_error(T_end, T_true)
        results.append((k, t, angle))
        print(f"  frame {k:2d}: road NMI optimum {100 * t[0]:6.1f} {100 * t[1]:6.1f} {100 * t[2]:6.1f} cm (camera x/y/z), "
              f"{angle:.2f} deg", flush=True)

    n = len(frames)
    print("\n## 2. NMI cost profile: share of the 12 one-step neighbours (0.1 m / 1 deg) scoring below the true pose")
    print("| points | share |\n|---|---|")
    for name, w in wins.items():
        print(f"| {name} | {100.0 * w / (12 * n):.1f} % |")
    t = np.array([r[1] for r in results])
    a = np.array([r[2] for r in results])
    ok = (np.linalg.norm(t, axis=1) < 0.1) & (a < 0.5)
    print("\n## 3. Road-surface NMI maximised from the true pose (pattern search, no prior)")
    print("| frames | success (< 0.1 m, < 0.5 deg) | offset x / y / z [cm], mean ± std | rotation [deg], median |")
    print("|---|---|---|---|")
    print(f"| {n} | {ok.sum()}/{n} | " + " / ".join(f"{100 * t[:, i].mean():.1f} ± {100 * t[:, i].std():.1f}" for i in range(3))
          + f" | {np.median(a):.2f} |")


if __name__ == "__main__":
    main()
