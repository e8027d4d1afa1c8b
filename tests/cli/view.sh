#!/usr/bin/env bash
# shadelab view: every PNG and CSV is written, and the numbers behind them hold what is known in closed form:
# Lambert's pi f_r is 1 in every direction and its directional albedo 1 at every incidence (the quadrature's
# error is below 1e-3); Oren-Nayar (sigma > 0) loses energy at normal incidence (albedo < 1).
# Usage: view.sh SHADELAB_BINARY
set -euo pipefail
bin="$1"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$bin" -q view lambert --vs oren_nayar:sigma=0.5 -o "$tmp/v" > "$tmp/list.txt"
for f in polar.csv polar.png albedo.csv albedo.png slice_0.csv slice_1.csv slices.png sphere_0.png sphere_1.png spheres.png; do
    [ -s "$tmp/v/$f" ] || { echo "FAIL: $f missing"; exit 1; }
    grep -q "$f" "$tmp/list.txt" || { echo "FAIL: $f not listed on stdout"; exit 1; }
done
python3 - "$tmp/v" <<'PY'
import csv, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/polar.csv")))
lam = [float(r["m0"]) for r in rows if abs(float(r["theta_r"])) < 89.0]
assert len(lam) > 1000 and max(abs(v - 1) for v in lam) < 1e-9, "Lambert's pi f_r is not 1"
alb = list(csv.DictReader(open(d + "/albedo.csv")))
assert max(abs(float(r["m0"]) - 1) for r in alb) < 1e-3, "Lambert's albedo is not 1"
assert float(alb[0]["m1"]) < 0.95, "Oren-Nayar sigma 0.5 should lose energy at normal incidence"
for r in alb:
    assert 0 <= float(r["m1"]) <= 1.0 + 1e-9
PY
# A mistyped model among --vs is a usage error naming the closest model.
if "$bin" view lambert --vs orennayar -o "$tmp/w" 2> "$tmp/err"; then echo "FAIL: unknown --vs model accepted"; exit 1; fi
grep -q "did you mean 'oren_nayar'" "$tmp/err" || { echo "FAIL: no hint: $(cat "$tmp/err")"; exit 1; }
echo "view: 1 passed, 0 failed"
