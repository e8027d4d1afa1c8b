#!/bin/sh
# bounded_run.sh FUZZER WORK SEEDS RUNS SECONDS ARTIFACT_PREFIX
# One bounded, repeatable libFuzzer run (what ctest's label 'fuzz' runs): a fresh work corpus, -seed=1, RUNS
# inputs, at most SECONDS. It fails only on a finding (a crash, a leak, an out-of-memory or an input taking
# over 60 s, each saved under ARTIFACT_PREFIX), never because the machine is slow.
set -eu
fuzzer=$1; work=$2; seeds=$3; runs=$4; seconds=$5; prefix=$6
if [ ! -d "$seeds" ]; then
    echo "bounded_run: no seed corpus in $seeds: run scripts/fuzz.sh --ctest, which makes it" >&2
    exit 1
fi
rm -rf "$work"
mkdir -p "$work"
exec "$fuzzer" -seed=1 -runs="$runs" -max_total_time="$seconds" -timeout=60 -rss_limit_mb=2560 \
     -print_final_stats=1 -artifact_prefix="$prefix" "$work" "$seeds"
