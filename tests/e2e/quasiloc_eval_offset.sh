# quasiloc-eval on the real V1_01 ground truth against a copy shifted by a known 5 cm: unaligned ATE = 5 cm,
# SE(3)- and Sim(3)-aligned ATE ~ 0, RPE ~ 0; Markdown and JSON written. The same through the INI-less command line,
# and its bad input (a missing ground truth: named, nothing written).
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
aligned = list(find(r, "ate_se3_rmse_m")) + list(find(r, "ate_sim3_rmse_m"))
assert len(aligned) == 2 and max(aligned) < 1e-6, "aligned ATE RMSE %r not ~0" % aligned
rpe = list(find(r, "rpe_per_m_trans_rmse_m")) + list(find(r, "rpe_per_s_trans_rmse_m"))
assert len(rpe) == 2 and max(rpe) < 1e-6, "RPE %r not ~0" % rpe
print("unaligned ATE", unaligned, "aligned", aligned, "RPE", rpe)
PY
# The command-line form: no INI, the same figure.
"$BIN/quasiloc-eval" --estimate "$WORK/est.tum" --groundtruth "$GT" --output-dir "$WORK/cli" | tee "$WORK/cli.txt"
expect_contains "$WORK/cli.txt" "| est | "
ate_cli=$(/usr/bin/python3 -c 'import json,sys; print("%.4f" % (100 * json.load(open(sys.argv[1]))["sequences"][0]["ate_rmse_m"]))' \
  "$WORK/cli/report.json")
[ "$ate_cli" = "5.0000" ] || fail "command-line form: unaligned ATE $ate_cli cm, not 5 cm"
[ -s "$WORK/cli/est_errors.csv" ] || fail "est_errors.csv not written"
expect_failure "$WORK/bad.txt" "$BIN/quasiloc-eval" --estimate "$WORK/est.tum" --groundtruth "$WORK/none.tum" \
  --output-dir "$WORK/bad"
expect_contains "$WORK/bad.txt" "none.tum"
[ ! -e "$WORK/bad" ] || fail "output written despite the error"
expect_failure "$WORK/bad2.txt" "$BIN/quasiloc-eval" --estimate "$WORK/est.tum" --output-dir "$WORK/bad"
expect_contains "$WORK/bad2.txt" "--groundtruth <TUM> is required"
echo "OK"
