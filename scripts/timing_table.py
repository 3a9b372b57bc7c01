#!/usr/bin/env python3
"""Per-stage tracking time of finished quasiloc-track runs: median, p90, p95 and max per stage, one table per run.

    /usr/bin/python3 scripts/timing_table.py NAME=TRACK_DIR [NAME=TRACK_DIR ...]

TRACK_DIR is a quasiloc-track output_dir (diagnostics.csv, summary.json). The stages are the tracker's wall times
(FrameReport::ms_*, tracker.h); "frame" is what summary.json's time_per_frame_ms counts (the tracker, the loss check
and the search handover). A stage that ran on no frame of a run prints "-". Prints Markdown.
"""
import csv
import json
import math
import os
import sys

STAGES = [
    ("predict", "ms_predict"),
    ("edge field", "ms_image"),
    ("align (render, edge field, LM)", "ms_align"),
    ("visual (wait for the stereo tasks)", "ms_visual"),
    ("window", "ms_window"),
    ("window: Ceres solve", "ms_window_solve"),
    ("window: marginal", "ms_window_marginal"),
    ("loss check", "ms_check"),
    ("tracker total", "ms_total"),
]


def percentile(values, q):
    """Linear interpolation between closest ranks (numpy's default), without numpy."""
    v = sorted(values)
    if not v:
        return math.nan
    pos = (len(v) - 1) * q / 100.0
    lo = int(math.floor(pos))
    hi = min(lo + 1, len(v) - 1)
    return v[lo] + (v[hi] - v[lo]) * (pos - lo)


def read_rows(track_dir):
    path = os.path.join(track_dir, "diagnostics.csv")
    if not os.path.isfile(path):
        sys.exit(f"error: {path} not found (is {track_dir} a quasiloc-track output_dir?)")
    with open(path) as f:
        return list(csv.DictReader(f))


def stage_row(name, values):
    values = [x for x in values if x > 0]
    if not values:
        return f"| {name} | - | - | - | - | 0 |"
    figures = [percentile(values, q) for q in (50, 90, 95, 100)]
    return "| {} | {} | {} |".format(name, " | ".join(f"{x:.2f}" for x in figures), len(values))


def table(name, track_dir):
    rows = read_rows(track_dir)
    lines = [f"### {name}", "", "| stage [ms] | median | p90 | p95 | max | frames |", "|---|---|---|---|---|---|"]
    for label, column in STAGES:
        lines.append(stage_row(label, [float(r[column]) for r in rows if r.get(column) not in (None, "", "nan")]))
    frame = [float(r["ms_total"]) + float(r["ms_check"]) + float(r["ms_search"]) for r in rows]
    lines.append(stage_row("**frame**", frame))
    summary_path = os.path.join(track_dir, "summary.json")
    if os.path.isfile(summary_path):
        with open(summary_path) as f:
            s = json.load(f)
        ate = s.get("ate", {}).get("rmse_m")
        start = s.get("start", {}).get("search_s")
        extra = []
        if ate is not None:
            extra.append(f"ATE RMSE {100 * ate:.3f} cm")
        if start is not None:
            extra.append(f"start search {start:.2f} s")
        extra.append(f"{len(rows)} frames")
        lines += ["", ", ".join(extra)]
    return "\n".join(lines)


def main(argv):
    if len(argv) < 2 or any("=" not in a for a in argv[1:]):
        sys.exit(__doc__)
    print("\n\n".join(table(*a.split("=", 1)) for a in argv[1:]))


if __name__ == "__main__":
    main(sys.argv)
