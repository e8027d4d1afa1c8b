#!/usr/bin/env python3
"""bench.speed_report_smoke: scripts/speed_report.py with every bench's smoke mode (--quick), on a copy of
docs/speed.md and with its raw outputs in a scratch folder, so the one command that regenerates the page's
figures never rots. No timing is checked; what is checked:

- the run exits 0, and every `<!-- speed_report:begin NAME -->` block of the copy was filled from this run
  (names its run and says it was a --quick run), none left "not run yet";
- the hand-written text outside the blocks, and the blocks' names and order, are those of docs/speed.md;
- the run's record (speed_run_PART.json) has date, revision, CPU, device, load and the core speed probe for every
  bench, and no raw output names the checkout's folder;
- a bench that fails is named in one line with its exit status and leaves the page byte for byte as it was;
  a missing program is named with the target to build (exit 2).

Usage: speed_report_smoke.py SOURCE_DIR BUILD_DIR
"""
import json
import os
import re
import shutil
import stat
import subprocess
import sys
import tempfile

BLOCK = re.compile(r"(<!-- speed_report:begin ([a-z0-9_]+) -->\n)(.*?)(<!-- speed_report:end \2 -->)", re.S)
PARTS = ["models", "e2e", "process", "chart"]


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def split(text):
    """(the text outside the blocks, [(name, body)]) of a page."""
    return BLOCK.sub(lambda m: m.group(1) + m.group(4), text), [(m.group(2), m.group(3)) for m in BLOCK.finditer(text)]


def run(script, *args):
    return subprocess.run([sys.executable, script, *args], capture_output=True, text=True)


def check_filled(page, original):
    outside, blocks = split(page)
    want_outside, want_blocks = split(original)
    if outside != want_outside:
        fail("the text outside the speed_report blocks changed")
    if [n for n, _ in blocks] != [n for n, _ in want_blocks] or not blocks:
        fail(f"blocks {[n for n, _ in blocks]}, expected {[n for n, _ in want_blocks]}")
    for name, body in blocks:
        if not body.strip() or "Not run yet" in body:
            fail(f"block '{name}' was not filled:\n{body}")
        if name == "runs":
            if body.count("(--quick)") != len(PARTS):
                fail(f"the runs block does not list every part as this --quick run:\n{body}")
        elif "*Run: " not in body or "--quick run" not in body:
            fail(f"block '{name}' does not name this --quick run:\n{body}")
    print(f"{len(blocks)} blocks filled; the text outside them unchanged")


def check_record(data, source):
    for part in PARTS:
        with open(os.path.join(data, f"speed_run_{part}.json")) as f:
            r = json.load(f)
        for key in ["date", "revision", "cpu", "cores", "device", "steps"]:
            if not r.get(key):
                fail(f"speed_run_{part}.json has no {key}")
        for s in r["steps"]:
            if not (re.match(r"^[\d.]+ [\d.]+ [\d.]+$", s["load_start"]) and re.match(r"^[\d.]+ ", s["load_end"])):
                fail(f"speed_run_{part}.json: no load average for {s['bench']}")
            for key in ["probe_start", "probe_end"]:   # bench/core_probe.cpp: G adds/s alone and of each thread at once
                p = s.get(key)
                if not (p and p["alone"] > 0 and p["at_once"] and all(g > 0 for g in p["at_once"])):
                    fail(f"speed_run_{part}.json: no core speed probe ({key}) for {s['bench']}: {p}")
    for f in os.listdir(data):
        path = os.path.join(data, f)
        if os.path.isfile(path) and f.endswith((".txt", ".json", ".md")):
            with open(path, errors="replace") as fh:
                if source in fh.read():
                    fail(f"{f} names the checkout's folder")
    print("run record complete, no checkout paths in the raw outputs")


def check_failure(script, work, page, build):
    fake = os.path.join(work, "fake-build")
    os.makedirs(fake)
    prog = os.path.join(fake, "bench_models")
    with open(prog, "w") as f:
        f.write("#!/bin/sh\necho 'bench_models: error: pretend'\nexit 3\n")
    os.chmod(prog, os.stat(prog).st_mode | stat.S_IEXEC)
    shutil.copy(os.path.join(build, "core_probe"), fake)   # the run asks for it before and after each bench
    before = open(page, "rb").read()
    r = run(script, "--only", "models", "--build", fake, "--data", os.path.join(work, "fail"), "--doc", page)
    lines = r.stderr.strip().splitlines()
    if r.returncode != 1 or len(lines) != 1 or "bench_models failed (exit status 3)" not in lines[0] \
            or "bench_models.txt" not in lines[0]:
        fail(f"a failing bench: exit {r.returncode}, stderr {r.stderr!r}")
    if open(page, "rb").read() != before:
        fail("a failing bench changed the page")
    r = run(script, "--only", "e2e", "--build", os.path.join(work, "empty"), "--data", os.path.join(work, "fail"),
            "--doc", page)
    if r.returncode != 2 or "--target bench_e2e" not in r.stderr:
        fail(f"a missing program: exit {r.returncode}, stderr {r.stderr!r}")
    print("a failing bench and a missing program: one line each, the page untouched")


def main():
    source, build = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    script = os.path.join(source, "scripts", "speed_report.py")
    work = tempfile.mkdtemp(prefix="speed_report_smoke.")
    try:
        page, data = os.path.join(work, "speed.md"), os.path.join(work, "data")
        original = open(os.path.join(source, "docs", "speed.md")).read()
        shutil.copyfile(os.path.join(source, "docs", "speed.md"), page)
        r = run(script, "--quick", "--build", build, "--data", data, "--doc", page)
        print(r.stdout, r.stderr)
        if r.returncode != 0:
            fail(f"speed_report.py --quick exited {r.returncode}")
        check_filled(open(page).read(), original)
        check_record(data, source)
        check_failure(script, work, page, build)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("PASS")


if __name__ == "__main__":
    main()
