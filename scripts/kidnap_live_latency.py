#!/usr/bin/python3
"""Table of the runs of scripts/kidnap_latency.sh: per run the losses, the output's unverified stretch, when the fix was
found in replay time, and an estimate of when a live 20 Hz stream would have it.

The replay time understates the live latency when the tracker runs slower than real time (the search gets more wall
time per replayed frame). The estimate: from the last confirmed pose, the loss is noticed at 'lost at t'; the
search's attempts then run one after another, each taking the wall time its record gives (ms_cloud + ms_search +
ms_refine in initialization.txt), none starting before its frame exists; the fix is known when the attempt that
gave the start ('single fix' or 'pair closed') ends.

Usage: /usr/bin/python3 scripts/kidnap_live_latency.py <output_root of kidnap_latency.sh>
"""
import glob
import os
import re
import statistics
import sys


def fail(msg):
    print(f"kidnap_live_latency: {msg}", file=sys.stderr)
    sys.exit(1)


def live_latency(run_dir, log):
    lost = re.search(r"lost at t ([0-9.]+)", log)
    verified = re.search(r"unverified since t ([0-9.]+)", log)
    if not lost or not verified:
        return None
    t_verified, clock = float(verified.group(1)), float(lost.group(1))
    for line in open(os.path.join(run_dir, "initialization.txt")):
        if not line.startswith("reloc 1,"):
            continue
        f = [x.strip() for x in line.split(",")]
        t_frame, wall_s = float(f[1]), (float(f[9]) + float(f[10]) + float(f[11])) / 1000
        clock = max(clock, t_frame) + wall_s
        if f[-1].startswith(("single fix", "pair closed")):
            return clock - t_verified
    return None


def main():
    if len(sys.argv) != 2 or not os.path.isdir(sys.argv[1]):
        fail("usage: kidnap_live_latency.py <output_root of kidnap_latency.sh> (an existing folder)")
    logs = sorted(glob.glob(os.path.join(sys.argv[1], "*", "k*.log")))
    if not logs:
        fail(f"{sys.argv[1]}: no <sequence>/k<time>.log runs")
    print("| sequence | kidnap at [s] | losses (withdrawn) | unverified [s] | found, replay [s] | found, live estimate [s] | last frame error [cm] |")
    print("|---|---|---|---|---|---|---|")
    live = []
    for path in logs:
        log = open(path).read()
        run_dir = path[:-4]
        seq, kidnap = path.split(os.sep)[-2], os.path.basename(run_dir)[1:]
        losses = re.search(r"^losses +(\d+) \(withdrawn (\d+)", log, re.M)
        stretch = re.search(r"longest unverified stretch ([0-9.]+) s \(fix found after ([0-9.]+) s", log)
        if not losses or not stretch:
            fail(f"{path}: no summary (did quasiloc-track fail?)")
        rows = [l for l in open(os.path.join(run_dir, "diagnostics.csv")) if not l.startswith("#")]
        header = rows[0].strip().split(",")
        last_err = float(rows[-1].strip().split(",")[header.index("error_m")]) * 100
        est = live_latency(run_dir, log) if kidnap != "-1" else None
        if est is not None:
            live.append(est)
        print(f"| {seq} | {'-' if kidnap == '-1' else kidnap} | {losses.group(1)} ({losses.group(2)}) | {stretch.group(1)} | "
              f"{stretch.group(2)} | {'-' if est is None else f'{est:.2f}'} | {last_err:.2f} |")
    if live:
        print(f"\nlive estimate over {len(live)} kidnaps: median {statistics.median(live):.2f} s, "
              f"min {min(live):.2f} s, max {max(live):.2f} s")


if __name__ == "__main__":
    main()
