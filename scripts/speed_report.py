#!/usr/bin/env python3
"""Regenerates the figures of docs/speed.md from one run of the benchmarks.

Usage: scripts/speed_report.py [--only models,e2e,process,chart] [--quick] [--build DIR] [--data DIR] [--doc FILE]
                               [--e2e-frames N] [--no-run]

1. Checks that the bench programs of the parts asked for are built (else says which target to build, exits 2).
2. Runs each part's benchmark, writing its raw outputs under the data folder (default docs/data/): the CSV the
   program writes, and what it prints (<bench>.txt). `--quick` passes each bench's smoke option instead (a run of
   a minute or two, whose figures mean nothing: for the test of this script).
3. Records the run of each part in <data>/speed_run_<part>.json: date (UTC), git revision ("-dirty" when the
   checkout has uncommitted changes), CPU model (/proc/cpuinfo), core count, PoCL's device (clinfo -l), the load
   average at the start and at the end of each bench, its wall time.
4. Rewrites every block of the doc between `<!-- speed_report:begin NAME -->` and `<!-- speed_report:end NAME -->`
   from the raw outputs; the text outside the blocks is left exactly as it was. Each block names the run it came
   from. Blocks of parts not run this time are recomputed from their previous raw outputs, if there are any.
5. When a bench fails, says so in one line (which bench, its exit status, its log) and leaves the doc untouched;
   the doc is written to a temporary file and renamed over the old one.

`--no-run` skips the benches and only rewrites the blocks from the raw outputs already in the data folder.
"""
import argparse
import csv
import datetime
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PARTS = ["models", "e2e", "process", "chart"]
# --quick: bench_models on one model of each kind its targets name (cheap N.L, a pow model, a C++-loop family)
QUICK_MODELS = "lambert,half_lambert,phong,blinn_phong,toon,oren_nayar,cook_torrance"
BLOCK = re.compile(r"(<!-- speed_report:begin ([a-z0-9_]+) -->\n)(.*?)(<!-- speed_report:end \2 -->)", re.S)


class BenchFailed(Exception):
    pass


# --- the run: machine facts ----------------------------------------------------------------------------------

def sh(args, cwd=ROOT):
    try:
        return subprocess.run(args, cwd=cwd, capture_output=True, text=True, check=False).stdout
    except OSError:
        return ""


def load_average():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


PROBE = re.compile(r"core speed probe: ([\d.]+) alone,((?: [\d.]+)+) at once G adds/s")


def core_probe(a):
    """bench/core_probe.cpp's line (one thread's G dependent adds/s alone, each thread's at once: on an idle core
    its clock in GHz, less where the host shares the cores), as {"alone", "at_once"}; None if it did not run."""
    m = PROBE.search(sh([os.path.join(a.build, "core_probe")]))
    return {"alone": float(m.group(1)), "at_once": [float(x) for x in m.group(2).split()]} if m else None


def probe_text(p):
    """'1.37 alone, 2.43 at once' (G adds/s), or '-' for a record without a probe."""
    return f"{p['alone']:.2f} alone, {sum(p['at_once']):.2f} at once" if p else "-"


def cpu_model():
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return "unknown CPU"


def pocl_device():
    for line in sh(["clinfo", "-l"]).splitlines():
        m = re.search(r"Device #\d+: (.+)", line)
        if m:
            return m.group(1).strip()
    return "unknown device (clinfo -l printed none)"


def revision():
    rev = sh(["git", "rev-parse", "--short=10", "HEAD"]).strip() or "unknown"
    dirty = sh(["git", "status", "--porcelain", "--untracked-files=no"]).strip()
    return rev + ("-dirty" if dirty else "")


def machine():
    return {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "revision": revision(), "cpu": cpu_model(), "cores": os.cpu_count(), "device": pocl_device()}


# --- the benches ---------------------------------------------------------------------------------------------

def bench_steps(part, a, tmp):
    """The commands of one part: (label, argv, log file name, extra environment)."""
    b, d = a.build, a.data
    if part == "models":
        opts = ["--smoke", "--models", QUICK_MODELS] if a.quick else ["--repeats", str(a.models_repeats)]
        return [("bench_models", [f"{b}/bench_models", *opts, "--csv", f"{d}/bench_models.csv",
                                  "--markdown", f"{d}/bench_models.md"], "bench_models.txt", {})]
    if part == "e2e":
        opts = ["--smoke"] if a.quick else ["--frames", str(a.e2e_frames)]
        return [("bench_e2e", [f"{b}/bench_e2e", *opts, "--csv", f"{d}/bench_e2e.csv"], "bench_e2e.txt", {})]
    if part == "process":
        return [("bench_e2e_process", [f"{b}/bench_e2e_process", *(["--smoke"] if a.quick else [])],
                 "bench_e2e_process.txt", {})] + batch_steps(a, tmp)
    chart = [f"{b}/shadelab", "chart", "--out", f"{tmp}/chart"]
    if a.quick:
        chart += ["--models", "lambert,blinn_phong", "--size", "48x48", "--fragments", "20000", "--repeats", "1",
                  "--rounds", "1", "--sphere-levels", "0,1", "--mesh-levels", "0,1", "--mesh-reference-level", "1"]
    return [("shadelab chart", chart, "chart.txt", {})]


def batch_steps(a, tmp):
    """A warm batch: the scenes once to fill fresh program, PoCL and mesh caches, then twice with them warm."""
    scenes = [f"{ROOT}/scenes/minimal.json"] if a.quick else sorted(
        os.path.join(ROOT, "scenes", f) for f in os.listdir(f"{ROOT}/scenes") if f.endswith(".json"))
    env = {"SHADELAB_PROGRAM_CACHE": f"{tmp}/programs", "POCL_CACHE_DIR": f"{tmp}/pocl",
           "SHADELAB_MESH_CACHE": f"{tmp}/meshes"}
    return [(f"shadelab batch ({name})", [f"{a.build}/shadelab", "batch", *scenes, "--out", f"{tmp}/out{i}"],
             f"batch_{name}.txt", env) for i, name in enumerate(["fill", "warm1", "warm2"])]


def scrub(text, tmp):
    """No paths of this machine in what is kept: the checkout is '.', the run's scratch folder '$TMP'."""
    return text.replace(tmp, "$TMP").replace(ROOT + "/", "").replace(ROOT, ".")


def run_step(label, argv, log, env, a, tmp):
    start_load, start_probe, t0 = load_average(), core_probe(a), time.time()
    path = os.path.join(a.data, log)
    with open(path, "w") as out:
        rc = subprocess.run(argv, cwd=ROOT, stdout=out, stderr=subprocess.STDOUT, env=dict(os.environ, **env)).returncode
    seconds, end_load, end_probe = round(time.time() - t0, 1), load_average(), core_probe(a)
    with open(path) as f:
        text = scrub(f.read(), tmp)
    with open(path, "w") as f:
        f.write(text)
    if rc != 0:
        raise BenchFailed(f"speed_report: {label} failed (exit status {rc}); its log: {os.path.relpath(path)}")
    return {"bench": label, "command": scrub(" ".join(argv), tmp), "load_start": start_load, "load_end": end_load,
            "probe_start": start_probe, "probe_end": end_probe, "seconds": seconds, "log": log}


def run_part(part, a, rev):
    run = machine()
    run["revision"] = rev   # the checkout the programs were built from, as it was when the run began
    run["quick"] = a.quick
    tmp = tempfile.mkdtemp(prefix=f"speed_report_{part}.")
    try:
        run["steps"] = [run_step(*s, a, tmp) for s in bench_steps(part, a, tmp)]
        if part == "chart":
            for f in ["speed_accuracy.csv", "subdivision.csv"]:
                shutil.copyfile(os.path.join(tmp, "chart", f), os.path.join(a.data, f))
            images = os.path.join(os.path.dirname(os.path.abspath(a.doc)), "images")
            os.makedirs(images, exist_ok=True)
            for f in ["speed_accuracy.png", "subdivision.png"]:
                shutil.copyfile(os.path.join(tmp, "chart", f), os.path.join(images, f))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    with open(os.path.join(a.data, f"speed_run_{part}.json"), "w") as f:
        json.dump(run, f, indent=1)
        f.write("\n")
    return run


def check_built(parts, a):
    need = {"models": ["bench_models", "core_probe"], "e2e": ["bench_e2e", "core_probe"],
            "process": ["bench_e2e_process", "shadelab", "core_probe"], "chart": ["shadelab", "core_probe"]}
    missing = sorted({t for p in parts for t in need[p] if not os.access(os.path.join(a.build, t), os.X_OK)})
    if missing:
        print(f"speed_report: not built: {', '.join(missing)}; build with: cmake --build {os.path.relpath(a.build)} "
              f"--target {' '.join(missing)}", file=sys.stderr)
        sys.exit(2)


# --- reading the raw outputs ---------------------------------------------------------------------------------

def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_text(path):
    with open(path) as f:
        return f.read()


def num(s):
    return float(s) if s not in ("", "-", None) else None


def fmt(v, digits=2):
    return f"{v:.{digits}f}"


def sig(v):
    """A figure with three significant digits, as the tables show them."""
    if v is None:
        return "-"
    if v >= 100:
        return f"{v:.0f}"
    if v >= 1:
        return f"{v:.1f}" if v >= 10 else f"{v:.2f}"
    return f"{v:#.2g}"


def run_line(run, part):
    """The sentence that names a block's run."""
    steps = run["steps"]
    loads = "; ".join(f"{s['bench']} {s['load_start'].split()[0]} -> {s['load_end'].split()[0]}" for s in steps)
    quick = " **--quick run: smoke sizes, the figures mean nothing**" if run.get("quick") else ""
    probes = "; ".join(f"{s['bench']} {probe_text(s.get('probe_start'))} -> {probe_text(s.get('probe_end'))}"
                       for s in steps if s.get("probe_start") or s.get("probe_end"))
    probes = (f"; [core speed probe](#core-probe) (G dependent adds/s; an idle core's GHz) at start -> end: "
              f"{probes}") if probes else ""
    return (f"*Run: {run['date']}, revision `{run['revision']}`, {run['cores']} cores of an `{run['cpu']}`, PoCL device "
            f"`{run['device']}`; load average (1 min) at start -> end: {loads}{probes}.*{quick}")


def verdict(k, n):
    if n == 0:
        return "not measured in this run"
    return f"met by all {n}" if k == n else ("not met: met by 0 of " + str(n) if k == 0 else f"not met: met by {k} of {n}")


# --- the blocks: bench_models --------------------------------------------------------------------------------

TABLE_MODELS = ["lambert", "half_lambert", "phong", "blinn_phong", "minnaert_1941", "minnaert_b", "oren_nayar",
                "oren_nayar_full", "eon", "toon", "cook_torrance", "gradient"]


def size_label(n):
    n = int(n)
    return f"{n // 1048576}M" if n % 1048576 == 0 else str(n)


class Models:
    def __init__(self, data):
        self.rows = read_csv(os.path.join(data, "bench_models.csv"))
        self.report = read_text(os.path.join(data, "bench_models.md"))
        self.big = max(int(r["n"]) for r in self.rows)
        self.at_big = [r for r in self.rows if int(r["n"]) == self.big]

    def row(self, model, mode, n=None):
        n = self.big if n is None else n
        return next((r for r in self.rows if r["model"] == model and r["mode"] == mode and int(r["n"]) == n), None)

    def with_target(self, mode, text, rows=None):
        return [r for r in (rows or self.at_big) if r["mode"] == mode and text in r["target"]]


def models_stream(m):
    stream = next((l for l in m.report.splitlines() if l.startswith("STREAM on PoCL")), "STREAM: not in the report.")
    vec = next((l for l in m.report.splitlines() if l.startswith("Vectorised")), "Vectorised: not in the report.")
    misses = next((l for l in m.report.splitlines() if re.match(r"\d+ of \d+ rows miss", l)), "")
    return f"{stream} {vec} {misses}".strip()


def models_table(m):
    s = size_label(m.big)
    out = [f"| model | precise Mfrag/s {s} | of STREAM {s} | x C++ {s} | fast / precise {s} |", "|---|---|---|---|---|"]
    for name in TABLE_MODELS:
        p, f = m.row(name, "precise"), m.row(name, "fast")
        if not p:
            continue
        ratio = "-" if not f else fmt(float(f["fast_x_precise"])) + (" (same code)" if "same code" in f["target"] else "")
        out.append(f"| {name} | {sig(num(p['mfrag_per_s']))} | {fmt(float(p['of_stream']))} | "
                   f"{sig(num(p['x_cpp']))} | {ratio} |")
    return "\n".join(out)


def listing(rows, key, digits=2, suffix=""):
    rows = sorted(rows, key=lambda r: float(r[key]))
    return ", ".join(f"{r['model']} {fmt(float(r[key]), digits)}{suffix}" for r in rows) or "none"


def count_met(rows, key, target):
    """'met by K of N' on one of bench_models' other yardsticks (of_plain_stream, the plain-store triad;
    of_stream_footprint, the triad over the model's footprint), over the rows that have it (older CSVs lack them)."""
    have = [r for r in rows if r.get(key)]
    if not have:
        return "not measured"
    return f"met by {len([r for r in have if float(r[key]) >= target])} of {len(have)}"


def models_targets(m):
    s = size_label(m.big)
    precise = [r for r in m.at_big if r["mode"] == "precise"]
    ok = [r for r in precise if float(r["of_stream"]) >= 0.25]
    low = sorted(precise, key=lambda r: float(r["of_stream"]))[:3]
    cheap = m.with_target("precise", "of_stream>=0.80")
    cheap_ok = [r for r in cheap if float(r["of_stream"]) >= 0.8]
    trans = m.with_target("precise", "x_cpp>=5")
    trans_ok = [r for r in trans if float(r["x_cpp"]) >= 5]
    pow_fast = m.with_target("fast", "x_precise>=1.3")
    pow_ok = [r for r in pow_fast if float(r["fast_x_precise"]) >= 1.3]
    same = m.with_target("fast", "same code")
    fp_precise = [r for r in precise if r.get("of_stream_footprint")]
    fp_low = sorted(fp_precise, key=lambda r: float(r["of_stream_footprint"]))[:3]
    lines = [
        f"- **Every model >= 0.25 of STREAM (precise, {s}): {verdict(len(ok), len(precise))}** "
        f"(lowest: {listing(low, 'of_stream')}).",
        f"- **Cheap models >= 0.8 of STREAM (precise, {s}): {verdict(len(cheap_ok), len(cheap))}** "
        f"({listing(cheap, 'of_stream')}).",
        f"- **Transcendental models >= 5x the C++ loop (precise, {s}): {verdict(len(trans_ok), len(trans))}** "
        f"({listing(trans, 'x_cpp', 1, 'x')}).{per_size_cpp(m, trans)}",
        f"- Against plain STREAM alone (the triad with plain stores, as McCalpin's C code, which pays the "
        f"write-allocate read that the kernels' streaming stores avoid past the cache): every model >= 0.25 "
        f"{count_met(precise, 'of_plain_stream', 0.25)}, cheap models >= 0.8 {count_met(cheap, 'of_plain_stream', 0.8)} "
        f"({listing(cheap, 'of_plain_stream')}).",
        f"- Against STREAM over the model's footprint (the triad's three arrays as many bytes as the model's "
        f"planes, where the target's arrays have the planes' length: a third or a quarter of those bytes, which a "
        f"large last-level cache can hold when the planes do not): every model >= 0.25 "
        f"{count_met(precise, 'of_stream_footprint', 0.25)} (lowest: "
        f"{listing(fp_low, 'of_stream_footprint')}), "
        f"cheap models >= 0.8 {count_met(cheap, 'of_stream_footprint', 0.8)} "
        f"({listing([r for r in cheap if r.get('of_stream_footprint')], 'of_stream_footprint')}).",
        f"- **Fast >= 1.3x precise where fast is different code (the {len(pow_fast)} models that call pow, {s}): "
        f"{verdict(len(pow_ok), len(pow_fast))}**{spread(pow_fast)}; the models whose fast build is the same code "
        f"as precise give{spread(same)}, which is this run's noise between two builds of one kernel.",
    ]
    return "\n".join(lines)


def per_size_cpp(m, trans):
    if len({int(r["n"]) for r in m.rows}) < 2:
        return ""
    parts = []
    for r in trans:
        rows = [x for x in m.rows if x["model"] == r["model"] and x["mode"] == "precise" and x["x_cpp"]]
        k = sum(1 for x in rows if float(x["x_cpp"]) >= 5)
        parts.append(f"{r['model']} {k} of {len(rows)}")
    return " Sizes where each reaches it: " + ", ".join(parts) + "."


def spread(rows):
    v = sorted(float(r["fast_x_precise"]) for r in rows if r["fast_x_precise"])
    if not v:
        return " (no rows)"
    return f" fast / precise {fmt(v[0])} - {fmt(v[-1])} (median {fmt(statistics.median(v))})"


# --- the blocks: bench_e2e -----------------------------------------------------------------------------------

class E2e:
    def __init__(self, data):
        self.rows = read_csv(os.path.join(data, "bench_e2e.csv"))
        self.text = read_text(os.path.join(data, "bench_e2e.txt"))
        self.groups = {}
        for r in self.rows:
            self.groups.setdefault((r["mesh"], r["triangles"], r["width"], r["height"]), []).append(r)
        self.threads = re.findall(r"^== (\S+) \((\d+) triangles\), (\d+)x(\d+).*?^rasteriser threads: \d+ threads = "
                                  r"([\d.]+)x", self.text, re.S | re.M)
        # the core speed probe after each case: what 2 threads of dependent adds did against one (None: older log)
        self.probe_scaling = [float(x) for x in re.findall(r"core probe after it: \d+ threads at once = ([\d.]+)x",
                                                          self.text)]


def med(rows, key):
    return statistics.median(float(r[key]) for r in rows)


def e2e_table(e):
    out = ["| mesh, size | shadelab / llvmpipe (rows) | shadelab frame, median (raster / resolve / kernel) | "
           "llvmpipe frame, median | rows >= target |", "| --- | --- | --- | --- | --- |"]
    for (mesh, tris, w, h), rows in e.groups.items():
        ratios = [float(r["ratio"]) for r in rows]
        met = sum(int(r["target_met"]) for r in rows)
        out.append(f"| {mesh} ({int(tris):,} triangles), {w}x{h} | {fmt(min(ratios))}x - {fmt(max(ratios))}x "
                   f"({len(rows)}) | {sig(med(rows, 'shadelab_ms'))} ms ({sig(med(rows, 'raster_ms'))} / "
                   f"{sig(med(rows, 'resolve_ms'))} / {sig(med(rows, 'kernel_ms'))}) | {sig(med(rows, 'llvmpipe_ms'))} ms"
                   f" | {met} of {len(rows)} |")
    return "\n".join(out)


def e2e_targets(e):
    rows = e.rows
    target = float(rows[0]["target"]) if rows else 2.0
    met = sum(int(r["target_met"]) for r in rows)
    worst = min(rows, key=lambda r: float(r["ratio"]))
    faster = sum(1 for r in rows if float(r["ratio"]) >= 1.0)
    sums = {k: sum(float(r[k]) for r in rows) for k in
            ["shadelab_ms", "raster_ms", "upload_ms", "kernel_ms", "download_ms", "resolve_ms"]}
    total = sums.pop("shadelab_ms")
    share = ", ".join(f"{k[:-3].replace('raster', 'rasterise')} {100 * v / total:.0f}%" for k, v in sums.items())
    rest = 100 * (total - sum(sums.values())) / total
    th = [(f"{m} {w}x{h}", float(x)) for m, _, w, h, x in e.threads]
    th_met = sum(1 for _, x in th if x >= 1.7)
    th_range = f"{fmt(min(x for _, x in th))}x - {fmt(max(x for _, x in th))}x" if th else "-"
    ps = e.probe_scaling
    probe_scaling = (f"; the [core speed probe](#core-probe) after each case: 2 threads of dependent additions at once "
                     f"{fmt(min(ps))}x - {fmt(max(ps))}x one alone (the most any 2-thread code could gain just then)"
                     if ps else "")
    if ps and len(ps) == len(th):   # the cases in which a second core was there to be had, as far as the probe saw
        free = [x for (_, x), p in zip(th, ps) if p >= 1.7]
        probe_scaling += (f"; in the {len(free)} cases whose probe read at least 1.7x, the rasteriser met the bar in "
                          f"{sum(1 for x in free if x >= 1.7)}")
    return "\n".join([
        f"- **Target >= {target:g}x llvmpipe on every row: {verdict(met, len(rows))}** (worst "
        f"{fmt(float(worst['ratio']))}x: {worst['mesh']} {worst['width']}x{worst['height']} {worst['model']} "
        f"{worst['mode']}); shadelab faster than llvmpipe in {faster} of {len(rows)} rows.",
        f"- **Rasteriser on 2 threads >= 1.7x one thread: {verdict(th_met, len(th))}** ({th_range} over the "
        f"(mesh, size) cases; the bar is for an idle machine, see the load above){probe_scaling}.",
        f"- Where shadelab's time goes, summed over the {len(rows)} rows: {share}, the rest {rest:.0f}%.",
        f"- Agreement: coverage differs from llvmpipe on at most {100 * max(float(r['coverage_mismatch_fraction']) for r in rows):.4f}% "
        f"of the pixels of a row; p99 Delta E 2000 <= {max(float(r['de_p99']) for r in rows):.4f} and mean <= "
        f"{max(float(r['de_mean']) for r in rows):.4f} in every row.",
    ])


# --- the blocks: bench_e2e_process and the batch -------------------------------------------------------------

def section(text, title):
    """The lines of one '== title' section of bench_e2e_process's report, up to the next section."""
    m = re.search(r"^== " + re.escape(title) + r".*?$(.*?)(?=^== |\Z)", text, re.S | re.M)
    return m.group(0).splitlines() if m else []


def process_writes(t):
    lines = section(t, "image writes")
    rows = [re.match(r"^(png zlib \d+(?:, filter \d+)?(?:, memLevel \d+)?|exr \w+)( \(default\))?\s+([\d.]+)ms\s+([\d.]+)ms\s+([\d.]+)x\s+([\d.]+)MB", l)
            for l in lines]
    rows = [r for r in rows if r]
    if not rows:
        return "Image writes: not measured in this run."
    head = lines[0].lstrip("= ").split(":")[0]
    out = [f"| {head} | shadelab `write_image` | `oiiotool -o`, same pixels and setting | oiiotool / shadelab | file |",
           "| --- | --- | --- | --- | --- |"]
    for r in rows:
        label = r.group(1).replace("zlib", "zlib level") + (" **(shadelab's default)**" if r.group(2) else "")
        out.append(f"| {label} | {sig(float(r.group(3)))} ms | {sig(float(r.group(4)))} ms | {r.group(5)}x | "
                   f"{r.group(6)} MB |")
    ok = [r for r in rows if float(r.group(5)) >= 1.0]
    slow = ", ".join(f"{r.group(1)} {r.group(5)}x" for r in rows if float(r.group(5)) < 1.0)
    out.append("")
    out.append(f"- **Every write at least as fast as oiiotool's: {verdict(len(ok), len(rows))}**"
               + (f" (slower: {slow})." if slow else "."))
    return "\n".join(out)


def process_startup(t):
    lines = section(t, "process start-up")
    rows = matched_rows(lines, r"^(shadelab .+?|  the same, .+?)\s+([\d.]+)\s+([\d.]+)$")
    ratio = next((re.search(r"([\d.]+)x \(medians\)", l) for l in lines if l.startswith("render with the libraries")), None)
    if not rows or not ratio:
        return "Process start-up: not measured in this run (`bench_e2e_process --startup-only` measures it alone)."
    runs = re.search(r"wall time, (\d+) runs each", lines[0])
    header = [f"fresh processes, {runs.group(1) if runs else '?'} runs each, alternated", "best", "median"]
    out = markdown_table(header, [[r.group(1).strip(), f"{r.group(2)} ms", f"{r.group(3)} ms"] for r in rows])
    out += ["", f"- The render with OpenImageIO and GDAL preloaded, as when the program linked them, took "
            f"**{ratio.group(1)}x** the time of the render without them (medians)."]
    return "\n".join(out)


def process_builds(t):
    lines = section(t, "program builds")
    rows = [re.match(r"^(.+?)\s+(\d+)ms\s+(\d+)ms\s+(\d+)\s+(\d+)\s+([\d.]+)x the cold run", l) for l in lines]
    rows = [r for r in rows if r]
    if not rows:
        return "Program builds: not measured in this run."
    what = lines[0].lstrip("= ").replace("program builds: ", "").replace("catalogue models", "catalogue model")
    out = [f"| program builds, {what} | build() | whole process | programs | from shadelab's cache | vs cold |",
           "| --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        out.append(f"| {r.group(1)} | {int(r.group(2)) / 1000:.2f} s | {int(r.group(3)) / 1000:.2f} s | {r.group(4)} | "
                   f"{r.group(5)} | {r.group(6)}x |")
    return "\n".join(out)


def batch_stages(text):
    m = re.search(r"wall ([\d.]+) s, (\d+) programs built\n\s*stages: load ([\d.]+) ms, raster ([\d.]+) ms, build "
                  r"([\d.]+) ms, kernel ([\d.]+) ms, resolve ([\d.]+) ms, write ([\d.]+) ms \(shade wall ([\d.]+) ms",
                  text)
    if not m:
        return None
    keys = ["wall_s", "programs", "load", "raster", "build", "kernel", "resolve", "write", "shade"]
    return dict(zip(keys, map(float, m.groups())))


def process_batch(data, run):
    steps = [s for s in run["steps"] if s["bench"].startswith("shadelab batch (warm")]
    if not steps:
        return "The warm batch: not run."
    stages = [batch_stages(read_text(os.path.join(data, s["log"]))) for s in steps]
    if None in stages:
        return "The warm batch: its `stages:` line was not found in " + ", ".join(s["log"] for s in steps) + "."
    shares = [100 * st["build"] / (1000 * st["wall_s"]) for st in stages]
    ok = sum(1 for x in shares if x < 20)
    runs = "; ".join(f"wall {st['wall_s']:.2f} s, build {st['build']:.0f} ms ({x:.1f}%), load {st['load']:.0f} ms, "
                     f"raster {st['raster']:.0f} ms, kernel {st['kernel']:.0f} ms, write {st['write']:.0f} ms"
                     for st, x in zip(stages, shares))
    cmd = steps[0]["command"].split(" --out")[0]
    return (f"- **Warm batch, program builds < 20% of its wall time: {verdict(ok, len(stages))}** "
            f"(`{cmd}`, caches filled by one run before, {len(stages)} timed runs: {runs}).")


def matched_rows(lines, pattern):
    """The matches of `pattern` at the start of each line, for the lines it matches."""
    return [m for m in (re.match(pattern, l) for l in lines) if m]


def markdown_table(header, rows):
    """A markdown table: the header's cells, a rule, then one line of cells per row."""
    return ["| " + " | ".join(header) + " |", "|" + " --- |" * len(header)] + ["| " + " | ".join(r) + " |" for r in rows]


def process_contact(t):
    lines = section(t, "cold contact sheet")
    rows = [re.match(r"^(one program per model \(before\)|models share one program \(new\))\s+(\d+)ms\s+(\d+)ms\s+"
                     r"(\d+)ms\s+(\d+)", l) for l in lines]
    rows = [r for r in rows if r]
    summary = next((re.search(r"([\d.]+)x faster in wall time, ([\d.]+)x less CPU", l) for l in lines
                    if l.startswith("cold contact sheet, best")), None)
    if not rows or not summary:
        return "- **Cold catalogue (`shadelab contact`) >= 3x faster: not measured in this run.**"
    out = ["| cold `shadelab contact`, every run | wall | CPU | build() | programs |", "| --- | --- | --- | --- | --- |"]
    for r in rows:
        out.append(f"| {r.group(1)} | {int(r.group(2)) / 1000:.1f} s | {int(r.group(3)) / 1000:.1f} s | "
                   f"{int(r.group(4)) / 1000:.1f} s | {r.group(5)} |")
    wall, cpu = float(summary.group(1)), float(summary.group(2))
    out += ["", f"- **Cold catalogue >= 3x faster (best of each, wall time): {'met' if wall >= 3 else 'not met'}: "
            f"{wall:.2f}x** in wall time, {cpu:.2f}x in CPU time."]
    return "\n".join(out)


def process_planning(t):
    rows = matched_rows(section(t, "planning"), r"^(\S+)\s+(.+?)\s+(\d+)ms\s+(\d+)ms\s+(\d+)ms\s+([\d.]+)ms\s+([\d.]+)x the old cold plan")
    if not rows:
        return "Planning: not measured in this run."
    header = ["scene", "case", "plan", "search", "programs", "render", "vs the old cold plan"]
    return "\n".join(markdown_table(header, [[r.group(1), r.group(2), f"{r.group(3)} ms", f"{r.group(4)} ms",
                                               f"{r.group(5)} ms", f"{r.group(6)} ms", f"{r.group(7)}x"] for r in rows]))


def process_meshes(t):
    lines = section(t, "mesh loading")
    rows = matched_rows(lines, r"^(\S+)\s+(\d+)\s+([\d.]+)ms\s+([\d.]+)ms\s+([\d.]+)ms\s+([\d.]+)ms\s+([\d.]+)x\s+([\d.]+)MB")
    if not rows:
        return "Mesh loading: not measured in this run."
    best = re.search(r"best of (\d+)", lines[0])
    header = [f"mesh loading, best of {best.group(1) if best else '?'}", "triangles", "cache off (full loader)",
              "key (SHA-256 of the file)", "miss (full load + entry stored)", "**cache hit**", "off / hit", "entry"]
    return "\n".join(markdown_table(header, [[g[0], f"{int(g[1]):,}", f"{g[2]} ms", f"{g[3]} ms", f"{g[4]} ms",
                                               f"{g[5]} ms", f"{g[6]}x", f"{g[7]} MB"] for g in (r.groups() for r in rows)]))


# --- the blocks: shadelab chart ------------------------------------------------------------------------------

def chart_summary(data):
    rows = read_csv(os.path.join(data, "speed_accuracy.csv"))

    def top(key):
        r = max(rows, key=lambda r: float(r[key]))
        return f"{float(r[key]):.2g} ({r['model']}, {r['mode']})"

    speeds = [float(r["mfrag_per_s"]) for r in rows]
    front_de = ", ".join(f"{r['model']} ({r['mode']})" for r in rows if r["front_de2000_p99"] == "1") or "none"
    front_rel = ", ".join(f"{r['model']} ({r['mode']})" for r in rows if r["front_rel_max"] == "1") or "none"
    return "\n".join([
        f"- {len(rows)} model x mode rows. Largest errors against the double reference: max relative error "
        f"{top('rel_max')}, p99 relative {top('rel_p99')}, p99 Delta E 2000 {top('de2000_p99')}, max Delta E 2000 "
        f"{top('de2000_max')} (1 is a just-noticeable difference).",
        f"- Speed: {min(speeds):.0f} to {max(speeds):.0f} Mfrag/s.",
        f"- **The front** by p99 Delta E: {front_de}; by max relative error: {front_rel}.",
    ])


def chart_subdivision(data):
    rows = read_csv(os.path.join(data, "subdivision.csv"))
    levels = sorted({int(r["level"]) for r in rows})
    curves = {}
    for r in rows:
        key = (r["surface"].replace(".obj", ""), r["model"], r["evaluation"].replace("_", " "))
        curves.setdefault(key, {})[int(r["level"])] = float(r["de2000_p99"])
    out = ["| surface, model, evaluation | " + " | ".join(f"level {l}" for l in levels) + " |",
           "| --- |" + " --- |" * len(levels)]
    for (surface, model, ev), c in curves.items():
        out.append(f"| {surface}, {model}, {ev} | " + " | ".join(sig(c[l]) if l in c else "" for l in levels) + " |")
    return "\n".join(out + ["", subdivision_lines(curves)])


def subdivision_lines(curves):
    steps = [c[l] / c[l + 1] for (_, _, ev), c in curves.items() if ev == "per pixel" for l in c
             if l + 1 in c and c[l + 1] > 0]
    first = [f"{s} {m} {ev}: level {next((str(l) for l in sorted(c) if c[l] <= 1.0), 'not reached')}" for (s, m, ev), c in
             curves.items()]
    fall = f"- Per-pixel p99 error falls by {min(steps):.1f}-{max(steps):.1f}x per level." if steps else ""
    return (fall + "\n- First level within Delta E 1 at p99 (not reached: not within the levels run): " + "; ".join(first)
            + ".").strip()


# --- the doc -------------------------------------------------------------------------------------------------

# block name -> (part, body(data folder, that part's run))
BLOCKS = {
    "models_stream": ("models", lambda d, r: models_stream(Models(d))),
    "models_table": ("models", lambda d, r: models_table(Models(d))),
    "models_targets": ("models", lambda d, r: models_targets(Models(d))),
    "e2e_table": ("e2e", lambda d, r: e2e_table(E2e(d))),
    "e2e_targets": ("e2e", lambda d, r: e2e_targets(E2e(d))),
    "process_writes": ("process", lambda d, r: process_writes(read_text(os.path.join(d, "bench_e2e_process.txt")))),
    "process_builds": ("process", lambda d, r: process_builds(read_text(os.path.join(d, "bench_e2e_process.txt")))),
    "process_startup": ("process", lambda d, r: process_startup(read_text(os.path.join(d, "bench_e2e_process.txt")))),
    "process_batch": ("process", process_batch),
    "process_contact": ("process", lambda d, r: process_contact(read_text(os.path.join(d, "bench_e2e_process.txt")))),
    "process_planning": ("process", lambda d, r: process_planning(read_text(os.path.join(d, "bench_e2e_process.txt")))),
    "process_meshes": ("process", lambda d, r: process_meshes(read_text(os.path.join(d, "bench_e2e_process.txt")))),
    "chart_summary": ("chart", lambda d, r: chart_summary(d)),
    "chart_subdivision": ("chart", lambda d, r: chart_subdivision(d)),
}


def load_runs(data):
    runs = {}
    for part in PARTS:
        path = os.path.join(data, f"speed_run_{part}.json")
        if os.path.exists(path):
            with open(path) as f:
                runs[part] = json.load(f)
    return runs


def wall(seconds):
    return f"{seconds / 60:.1f} min" if seconds >= 60 else f"{seconds:.0f} s"


def runs_block(runs):
    out = ["| part | run (UTC) | revision | CPU, cores | PoCL device | bench: load average (1 min) start -> end, wall time "
           "| [core speed probe](#core-probe), G adds/s start -> end |",
           "| --- | --- | --- | --- | --- | --- | --- |"]
    for part in PARTS:
        r = runs.get(part)
        if not r:
            out.append(f"| {part} | not run | | | | | |")
            continue
        steps = "; ".join(f"{s['bench']}: {s['load_start'].split()[0]} -> {s['load_end'].split()[0]}, "
                          f"{wall(s['seconds'])}" for s in r["steps"])
        probes = "; ".join(f"{s['bench']}: {probe_text(s.get('probe_start'))} -> {probe_text(s.get('probe_end'))}"
                           for s in r["steps"])
        if not any(s.get("probe_start") or s.get("probe_end") for s in r["steps"]):
            probes = "not recorded (a run from before the probe)"
        out.append(f"| {part}{' (--quick)' if r.get('quick') else ''} | {r['date']} | `{r['revision']}` | {r['cpu']}, "
                   f"{r['cores']} | {r['device']} | {steps} | {probes} |")
    return "\n".join(out)


def block_body(name, data, runs):
    if name == "runs":
        return runs_block(runs)
    if name not in BLOCKS:
        raise SystemExit(f"speed_report: the doc has a block '{name}' this script does not know")
    part, body = BLOCKS[name]
    run = runs.get(part)
    if not run:
        return f"*Not run yet: `scripts/speed_report.py --only {part}` fills this block.*"
    return run_line(run, part) + "\n\n" + body(data, run)


def render(doc_in, doc_out, data):
    """Rewrites every marker block of doc_in from the raw outputs into doc_out (temporary file, then rename)."""
    text = read_text(doc_in)
    runs = load_runs(data)
    names = [m.group(2) for m in BLOCK.finditer(text)]
    if not names:
        raise SystemExit(f"speed_report: no '<!-- speed_report:begin NAME -->' blocks in {doc_in}")
    new = BLOCK.sub(lambda m: m.group(1) + block_body(m.group(2), data, runs) + "\n" + m.group(4), text)
    fd, tmp = tempfile.mkstemp(prefix=".speed_report.", dir=os.path.dirname(os.path.abspath(doc_out)))
    with os.fdopen(fd, "w") as f:
        f.write(new)
    os.replace(tmp, doc_out)
    return names


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", default=",".join(PARTS), help="parts to run, comma-separated: " + ",".join(PARTS))
    ap.add_argument("--quick", action="store_true", help="each bench's smoke options (figures mean nothing)")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="build folder (default: build)")
    ap.add_argument("--data", default=os.path.join(ROOT, "docs", "data"), help="raw outputs (default: docs/data)")
    ap.add_argument("--doc", default=os.path.join(ROOT, "docs", "speed.md"), help="doc to rewrite")
    ap.add_argument("--doc-in", help="read the doc's text from here (default: --doc itself)")
    ap.add_argument("--e2e-frames", type=int, default=3, help="bench_e2e --frames (default 3)")
    ap.add_argument("--models-repeats", type=int, default=5,
                    help="bench_models --repeats: best of this many timed runs per model and mode (default 5)")
    ap.add_argument("--no-run", action="store_true", help="only rewrite the blocks from the raw outputs")
    a = ap.parse_args()
    a.build, a.data = os.path.abspath(a.build), os.path.abspath(a.data)
    parts = [p for p in a.only.split(",") if p]
    bad = [p for p in parts if p not in PARTS]
    if bad:
        ap.error(f"unknown part(s) {', '.join(bad)}; the parts are {', '.join(PARTS)}")
    os.makedirs(a.data, exist_ok=True)
    if not a.no_run:
        check_built(parts, a)
        try:
            rev = revision()
            for part in parts:
                print(f"speed_report: {part} (load average {load_average()}) ...", flush=True)
                run_part(part, a, rev)
        except BenchFailed as e:
            print(e, file=sys.stderr)
            return 1
    names = render(a.doc_in or a.doc, a.doc, a.data)
    print(f"speed_report: {len(names)} blocks of {os.path.relpath(a.doc)} rewritten from {os.path.relpath(a.data)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
