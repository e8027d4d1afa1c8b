#!/usr/bin/env bash
# A cluster run in miniature: the bundled scenes listed in a manifest, rendered once unsharded and once as four
# shards run side by side by GNU parallel (PoCL capped to one thread per job), the shard reports merged with
# `shadelab report merge`. The merged report must list the same jobs with the same fields as the unsharded one
# (all but the timings), and every image must be identical pixel for pixel. Usage: shards.sh SHADELAB SOURCE_DIR
set -euo pipefail
bin="$1"; src="$(cd "$2" && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
command -v parallel > /dev/null || { echo "FAIL: GNU parallel is not installed (Debian package 'parallel')"; exit 1; }
ls "$src"/scenes/*.json > "$tmp/jobs.txt"
echo "# a comment line, skipped" >> "$tmp/jobs.txt"
"$bin" -q batch --manifest "$tmp/jobs.txt" --out "$tmp/one" > /dev/null
export POCL_MAX_PTHREAD_COUNT=1
parallel --halt now,fail=1 -j4 "$bin" -q batch --manifest "$tmp/jobs.txt" --out "$tmp/four" --shard {}/4 ::: 1 2 3 4 > /dev/null
"$bin" -q report merge "$tmp"/four/batch_report_shard*of4.json -o "$tmp/four/merged.json" > /dev/null
python3 - "$tmp" <<'PY'
import json, os, subprocess, sys
tmp = sys.argv[1]
one = json.load(open(tmp + "/one/batch_report.json"))
four = json.load(open(tmp + "/four/merged.json"))
timing = {"load_ms", "raster_ms", "build_ms", "kernel_ms", "shade_ms", "resolve_ms", "write_ms", "mfrag_per_s"}
def job(j, out):
    d = {k: v for k, v in j.items() if k not in timing}
    d["outputs"] = [os.path.relpath(o, out) for o in j["outputs"]]
    return d
a = [job(j, tmp + "/one") for j in one["jobs"]]
b = [job(j, tmp + "/four") for j in four["jobs"]]
assert len(a) == one["planned_total"] > 5, len(a)
assert a == b, "merged report differs from the unsharded one"
for k in ("planned_total", "ok", "failed", "up_to_date"):
    assert one[k] == four[k], (k, one[k], four[k])
assert four["shard"] == "1/1" and four["jobs_in_shard"] == len(a)
n = 0
for j in a:
    for o in j["outputs"]:
        # pixel for pixel (idiff, OpenImageIO): EXR files differ in bytes between identical runs (their metadata)
        r = subprocess.run(["idiff", "-fail", "0", "-warn", "0", os.path.join(tmp, "one", o),
                            os.path.join(tmp, "four", o)], capture_output=True, text=True)
        assert r.returncode == 0, (o, r.stdout[-300:])
        n += 1
print(f"{len(a)} jobs, {n} images identical pixel for pixel")
PY
# The Slurm job-array script, as Slurm would start its two tasks (the environment it sets), merged likewise.
for i in 1 2; do
    SLURM_ARRAY_TASK_ID=$i SLURM_ARRAY_TASK_COUNT=2 SLURM_CPUS_PER_TASK=1 SHADELAB="$bin" \
        bash "$src/scripts/slurm_batch.sh" "$tmp/jobs.txt" "$tmp/slurm" > /dev/null 2>&1
done
"$bin" -q report merge "$tmp"/slurm/batch_report_shard*of2.json -o "$tmp/slurm/merged.json" > /dev/null
python3 - "$tmp" <<'PY'
import json, sys
tmp = sys.argv[1]
a = [(j["index"], j["name"], j["status"]) for j in json.load(open(tmp + "/one/batch_report.json"))["jobs"]]
b = [(j["index"], j["name"], j["status"]) for j in json.load(open(tmp + "/slurm/merged.json"))["jobs"]]
assert a == b, "the Slurm recipe's merged report differs"
PY
# A shard missing, or given twice, is one clear line and exit 1.
if "$bin" report merge "$tmp"/four/batch_report_shard1of4.json -o "$tmp/x.json" 2> "$tmp/err"; then echo "FAIL: missing shards accepted"; exit 1; fi
grep -q "shard(s) 2/4, 3/4, 4/4 missing" "$tmp/err" || { echo "FAIL: $(cat "$tmp/err")"; exit 1; }
if "$bin" report merge "$tmp"/four/batch_report_shard1of4.json "$tmp"/four/batch_report_shard1of4.json -o "$tmp/x.json" 2> "$tmp/err"; then echo "FAIL: a shard twice accepted"; exit 1; fi
grep -q "given twice" "$tmp/err" || { echo "FAIL: $(cat "$tmp/err")"; exit 1; }
echo "shards: 1 passed, 0 failed"
