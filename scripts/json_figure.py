#!/usr/bin/python3
"""Prints figures from a program's summary.json, one per key path, space-separated:
    json_figure.py <summary.json> ate.rmse_m ate.max_m [--scale 100] [--digits 2]
--scale multiplies numbers (100: metres -> cm), --digits rounds them. A missing key or file exits non-zero."""
import argparse
import json
import sys

parser = argparse.ArgumentParser()
parser.add_argument("file")
parser.add_argument("keys", nargs="+")
parser.add_argument("--scale", type=float, default=None)
parser.add_argument("--digits", type=int, default=None)
args = parser.parse_args()
try:
    with open(args.file) as f:
        doc = json.load(f)
    out = []
    for path in args.keys:
        v = doc
        for k in path.split("."):
            v = v[k]
        if isinstance(v, (int, float)) and not isinstance(v, bool) and args.scale is not None:
            v = v * args.scale
        if isinstance(v, float) and args.digits is not None:
            v = f"{v:.{args.digits}f}"
        out.append(str(v))
    print(" ".join(out))
except (OSError, KeyError, TypeError, json.JSONDecodeError) as e:
    sys.exit(f"json_figure.py: {args.file}: {e!r}")
