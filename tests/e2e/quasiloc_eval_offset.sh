# quasiloc-eval on the real V1_01 ground truth against a copy shifted by a known 5 cm: unaligned ATE = 5 cm,
# SE(3)-aligned ATE ~ 0; Markdown and JSON written.
source "$(dirname "$0")/common.sh"
GT="$SHARED/data/euroc/groundtruth/cam0/V1_01_easy.txt"
awk '{ if ($1 ~ /^#/) print; else printf "%s %.9f %s %s %s %s %s %s\n", $1, $2 + 0.05, $3, $4, $5, $6, $7, $8 }' "$GT" > "$WORK/est.tum"
cat > "$WORK/eval.ini" <<INI
[Eval]
output_dir = $WORK/report
sequence_names = [v101]
align = se3

[Eval.v101]
kind = tracking
estimate = $WORK/est.tum
groundtruth = $GT
INI
"$BIN/quasiloc-eval" "$WORK/eval.ini" | tee "$WORK/log.txt"
[ -s "$WORK/report/report.md" ] || fail "report.md not written"
[ -s "$WORK/report/report.json" ] || fail "report.json not written"
/usr/bin/python3 - "$WORK/report/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
text = json.dumps(r)
print(text[:400])
def find(o, key):
    if isinstance(o, dict):
        for k, v in o.items():
            if k == key: yield v
            yield from find(v, key)
    elif isinstance(o, list):
        for v in o: yield from find(v, key)
vals = list(find(r, "ate_rmse_m"))
assert vals, "no ate_rmse_m in report.json"
unaligned = vals[0]
assert abs(unaligned - 0.05) < 1e-6, "unaligned ATE RMSE %r != 0.05" % unaligned
aligned = list(find(r, "aligned_ate_rmse_m"))
assert aligned and aligned[0] < 1e-6, "aligned ATE RMSE %r not ~0" % aligned
print("unaligned ATE", unaligned, "aligned", aligned[0])
PY
echo "OK"
