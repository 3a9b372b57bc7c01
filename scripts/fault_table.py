#!/usr/bin/python3
"""Runs quasiloc-track (quasiloc-track-harness, its test harness) on the simulated sequences with one injected fault per run ([FaultInjection],
docs/reliability.md) and prints a Markdown table per run: ATE, losses, relocalization time, frames reported
unverified, the largest error of a frame not flagged unverified, and the time to get back within 3 cm after the
fault ends.

    /usr/bin/python3 scripts/fault_table.py [--sim-root out/seq30] [--out out/faults] [--seqs A B] [--faults x y]
                                            [--set Section.key=value]...

--sim-root holds <SEQ>/sim as scripts/track_sequences.sh makes them (30 s, the EuRoC ground-truth IMU biases). Each
run takes the build lock (/tmp/quasiloc-build.lock) on its own, so other work interleaves. Runs whose summary.json
exists are reused (delete the folder to run again). Exit status 1 when a run crashed or a target is missed.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SEQS = ["V1_01_easy", "V1_02_medium", "V1_03_difficult", "V2_01_easy", "V2_02_medium", "V2_03_difficult"]
F = "FaultInjection."
# name -> (--set overrides, fault windows [from_s, to_s) after the first frame)
FAULTS = {
    "none": ([], []),
    "drop 10 %": ([F + "drop_from_s=5", F + "drop_duration_s=20", F + "drop_ratio=0.1"], [(5, 25)]),
    "drop 0.5 s": ([F + "drop_from_s=10", F + "drop_duration_s=0.5"], [(10, 10.5)]),
    "drop 2 s": ([F + "drop_from_s=10", F + "drop_duration_s=2"], [(10, 12)]),
    "IMU gap 0.1 s": ([F + "imu_gap_from_s=10", F + "imu_gap_duration_s=0.1"], [(10, 10.1)]),
    "IMU gap 1 s": ([F + "imu_gap_from_s=10", F + "imu_gap_duration_s=1"], [(10, 11)]),
    "black 1 s": ([F + "image_fault=black", F + "image_from_s=10", F + "image_duration_s=1"], [(10, 11)]),
    "saturated 1 s": ([F + "image_fault=saturated", F + "image_from_s=10", F + "image_duration_s=1"], [(10, 11)]),
    "desync 20 ms": ([F + "desync_from_s=10", F + "desync_duration_s=10", F + "desync_ms=20"], [(10, 20)]),
    "dup + reorder": ([F + "duplicate_at_s=10", F + "reorder_at_s=15"], [(10, 10.05), (15, 15.1)]),
}
UNFLAGGED_MAX_M, BACK_WITHIN_M, BACK_WITHIN_S = 0.10, 0.03, 2.0


def slug(name):
    return "".join(c if c.isalnum() else "_" for c in name).strip("_")


def run_track(args, seq, fault, out_dir):
    sim = os.path.join(args.sim_root, seq, "sim")
    rawlog = os.path.join(sim, seq + ".rawlog")
    cmd = ["flock", "/tmp/quasiloc-build.lock", os.path.join(args.build_dir, "bin", "quasiloc-track-harness"),
           os.path.join(ROOT, "config.ini"),
           "--set", "Tracking.input_rawlog=" + rawlog, "--set", "Tracking.calibration_ini=" + sim + "/calib.ini",
           "--set", "Tracking.map_file=" + sim + "/lidar_map.map", "--set", "Tracking.groundtruth=" + sim + "/gt.tum",
           "--set", "Tracking.output_dir=" + out_dir, "--set", "Tracking.write_scene=false"]
    for s in FAULTS[fault][0] + args.set:
        cmd += ["--set", s]
    os.makedirs(os.path.dirname(out_dir), exist_ok=True)
    with open(out_dir + ".log", "w") as log:
        return subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=ROOT)


def figures(out_dir, windows):
    with open(os.path.join(out_dir, "summary.json")) as f:
        s = json.load(f)
    t0 = s["start"]["first_frame_t"]
    rows = []
    with open(os.path.join(out_dir, "diagnostics.csv")) as f:
        for r in csv.DictReader(f):
            rows.append((float(r["t"]) - t0, float(r["error_m"]), r.get("unverified") == "1"))
    unflagged = [e for _, e, u in rows if not u and not math.isnan(e)]
    back = []
    for _, end in windows:
        later = [t for t, e, _ in rows if t >= end and e <= BACK_WITHIN_M]
        back.append(later[0] - end if later else math.inf)
    return {
        "ate_cm": 100 * s["ate"]["rmse_m"], "max_cm": 100 * s["ate"]["max_m"], "losses": s["losses"],
        "relocs": s["relocalizations"], "wait_s": s["longest_wait_s"], "unverified": s.get("frames_unverified", 0),
        "frames": s["frames"], "unflagged_max_cm": 100 * max(unflagged) if unflagged else 0.0,
        "back_s": max(back) if back else None,
    }


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sim-root", default=os.path.join(ROOT, "out", "seq30"))
    p.add_argument("--out", default=os.path.join(ROOT, "out", "faults"))
    p.add_argument("--build-dir", default=os.environ.get("QUASILOC_BUILD_DIR", os.path.join(ROOT, "build")))
    p.add_argument("--seqs", nargs="*", default=SEQS)
    p.add_argument("--faults", nargs="*", default=list(FAULTS))
    p.add_argument("--set", action="append", default=[], metavar="Section.key=value",
                   help="an option for every run (a variant of the configuration)")
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    header = ("| sequence | fault | frames | ATE RMSE cm | ATE max cm | losses (restarts) | longest wait s "
              "| unverified frames | max unflagged error cm | back within 3 cm after s | targets |")
    lines = [header, "|" + "---|" * 11]
    print(header, flush=True)
    failed = False
    for seq in args.seqs:
        for fault in args.faults:
            out_dir = os.path.join(args.out, seq, slug(fault))
            status = 0
            if not os.path.exists(os.path.join(out_dir, "summary.json")):
                status = run_track(args, seq, fault, out_dir)
            if status != 0:
                line = "| %s | %s | CRASH (exit %d, see %s.log) |||||||| missed |" % (seq, fault, status, out_dir)
                failed = True
            else:
                g = figures(out_dir, FAULTS[fault][1])
                ok = g["unflagged_max_cm"] <= 100 * UNFLAGGED_MAX_M and (g["back_s"] is None or
                                                                       g["back_s"] <= BACK_WITHIN_S)
                failed |= not ok
                back = "-" if g["back_s"] is None else ("never" if math.isinf(g["back_s"]) else "%.2f" % g["back_s"])
                line = "| %s | %s | %d | %.2f | %.2f | %d (%d) | %.2f | %d | %.2f | %s | %s |" % (
                    seq, fault, g["frames"], g["ate_cm"], g["max_cm"], g["losses"], g["relocs"], g["wait_s"],
                    g["unverified"], g["unflagged_max_cm"], back, "met" if ok else "missed")
            lines.append(line)
            print(line, flush=True)
    with open(args.out + ".md.tmp", "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(args.out + ".md.tmp", args.out + ".md")
    print("table written to %s.md" % args.out)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
