#!/usr/bin/python3
"""Plots of one quasiloc-track run: a top view of the estimated trajectory against the ground truth, and
the translation / rotation error and the time per stage over time. Run with Debian's python3 (numpy, matplotlib):

    /usr/bin/python3 share/quasiloc/plot_tracking.py <track_output_dir> <groundtruth.tum> [--title TEXT]

Reads <dir>/trajectory.tum (T_world_cam0) and <dir>/diagnostics.csv; writes <dir>/trajectory_top.png and
<dir>/error_time.png. Ground-truth poses are matched to estimates by timestamp (within 5 ms); errors are in the
map frame, without alignment (as quasiloc-track prints them)."""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_tum(path):
    rows = []
    with open(path) as f:
        for line_no, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            values = line.split()
            if len(values) != 8:
                sys.exit(f"{path}:{line_no}: expected 8 columns (t tx ty tz qx qy qz qw), got {len(values)}")
            rows.append([float(v) for v in values])
    if not rows:
        sys.exit(f"{path}: no poses")
    return np.array(rows)


def rotation_angle_deg(qa, qb):
    dots = np.abs(np.sum(qa * qb, axis=1) / (np.linalg.norm(qa, axis=1) * np.linalg.norm(qb, axis=1)))
    return np.degrees(2 * np.arccos(np.clip(dots, -1, 1)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("track_dir")
    ap.add_argument("groundtruth")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    est = read_tum(os.path.join(a.track_dir, "trajectory.tum"))
    gt = read_tum(a.groundtruth)
    idx = np.clip(np.searchsorted(gt[:, 0], est[:, 0]), 1, len(gt) - 1)
    nearer = np.where(np.abs(gt[idx - 1, 0] - est[:, 0]) < np.abs(gt[idx, 0] - est[:, 0]), idx - 1, idx)
    ok = np.abs(gt[nearer, 0] - est[:, 0]) < 0.005
    if not ok.any():
        sys.exit(f"{a.groundtruth}: no ground-truth pose within 5 ms of any estimate")
    e, g = est[ok], gt[nearer[ok]]
    t = e[:, 0] - e[0, 0]
    err_cm = 100 * np.linalg.norm(e[:, 1:4] - g[:, 1:4], axis=1)
    err_deg = rotation_angle_deg(e[:, 4:8], g[:, 4:8])
    title = a.title or os.path.basename(os.path.normpath(a.track_dir))

    fig, ax = plt.subplots(figsize=(7, 6))
    ax.plot(gt[:, 1], gt[:, 2], color="0.6", lw=3, label="ground truth")
    ax.plot(est[:, 1], est[:, 2], color="tab:red", lw=1, label="quasiloc-track")
    ax.plot(est[0, 1], est[0, 2], "ko", label="start")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m] (map frame)")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{title}: top view (ATE RMSE {np.sqrt(np.mean(err_cm ** 2)):.2f} cm)")
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(a.track_dir, "trajectory_top.png"), dpi=110)

    stages = {}
    diag = os.path.join(a.track_dir, "diagnostics.csv")
    if os.path.exists(diag):
        with open(diag) as f:
            rows = list(csv.DictReader(f))
        for key in ("ms_image", "ms_align", "ms_visual", "ms_window", "ms_total"):
            if rows and key in rows[0]:
                stages[key] = (np.array([float(r["t"]) for r in rows]) - e[0, 0], np.array([float(r[key]) for r in rows]))
    fig, axes = plt.subplots(3 if stages else 2, 1, figsize=(9, 8 if stages else 6), sharex=True)
    axes[0].plot(t, err_cm, color="tab:red")
    axes[0].set_ylabel("translation error [cm]")
    axes[0].set_title(f"{title}: error against ground truth (map frame, no alignment)")
    axes[1].plot(t, err_deg, color="tab:blue")
    axes[1].set_ylabel("rotation error [deg]")
    if stages:
        for key, (ts, ms) in stages.items():
            axes[2].plot(ts, ms, lw=1 if key != "ms_total" else 2, label=key[3:])
        axes[2].axhline(50, color="k", ls="--", lw=1, label="50 ms (20 Hz)")
        axes[2].set_ylabel("time per frame [ms]")
        axes[2].legend(ncol=3, fontsize=8)
    axes[-1].set_xlabel("time [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(a.track_dir, "error_time.png"), dpi=110)
    print(f"wrote {a.track_dir}/trajectory_top.png and error_time.png ({len(e)} poses with ground truth, "
          f"ATE RMSE {np.sqrt(np.mean(err_cm ** 2)):.2f} cm, max {err_cm.max():.2f} cm)")


if __name__ == "__main__":
    main()
