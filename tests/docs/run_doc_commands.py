#!/usr/bin/env python3
"""Runs the commands a doc page shows, as they stand, so a doc example that stops working fails the tests.

Usage: run_doc_commands.py PAGE.md BUILD_DIR SOURCE_DIR

What counts as a command: in the page's code blocks (fenced blocks other than python/cpp/json, and indented
blocks), every line that starts with `build/`, `shadelab ` or `$ ` followed by one of those (continuation lines
joined). They run in order, in one scratch folder per page that sees the source tree's meshes/, scenes/ and
tests/ read-only through links and the build folder as build/ (and `shadelab` on PATH); outputs land in the
scratch folder. A page may have a setup script, tests/docs/setup/STEM.sh, that makes "the user's own files" the
page takes as given (an ISIS parameter file, a disc image) in the scratch folder first.

What is checked:
- every command exits 0, or the status its comment announces with "(exits N)";
- a transcript (`$ command` followed by the output the page shows, up to the next `$` line or the block's end)
  is checked loosely: every shown output line must be printed by the run (stdout or stderr, any order), with
  the same words and every number within 2% (or 1e-6 absolute). Lines that report timings or the machine
  (ms, took, faster, speed-up, device, Mfrag, per second) are not compared, nor elisions (`[...]`), nor what
  the planner chose by timing (its "chosen:" line names a speed-up; the "mesh N renders with" lines under it;
  the "catalogue per material" rows of its table, which it adds only when the catalogue search timed a cheaper
  model faster: under load the search keeps the requested one and the table has no such rows).
  A block preceded by `<!-- doc-check: words -->` compares words only (numbers free) and ignores the `*` / `x`
  marks at the start of a row, for output whose numbers are timings.

Not run, and listed in the output with the reason:
- synopses: a line with an optional part `[--...]` or `[...]`, an ellipsis `...`, an alternative `a|b` or an
  upper-case placeholder (IMAGE, SCENE) - they show a command's form, not a command;
- lines marked "(not run by the tests: REASON)".
"""
import os
import re
import subprocess
import sys
import tempfile
import time

FENCE = re.compile(r"^(\s*)```(\S*)\s*$")
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
TOKEN = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[^\s\d.,;:()\[\]=+\-]+|[=+\-]")
TIMING = re.compile(r"\d\s*ms\b|\bms\b|took|faster|speed-up|\bdevice\b|Mfrag|per second|/s\b|build \d"
                    r"|^mesh \d+ renders with ")
# The planner's table rows of the catalogue's configurations: there only when its search timed a substitute faster.
BY_TIMING = re.compile(r"^[*x]?\s*catalogue per material, ")
PLACEHOLDER = re.compile(r"(?<![\w/.=-])[A-Z][A-Z0-9_]+(?![\w/.])")
SKIPPED_LANGS = {"python", "cpp", "c++", "json", "cmake", "ini", "pvl"}
RTOL, ATOL = 0.02, 1e-6


def blocks(lines):
    """Yields (first line number, check mode, [lines]) for each code block of the page."""
    i, n = 0, len(lines)
    while i < n:
        m = FENCE.match(lines[i])
        if m:
            lang, start, body = m.group(2).lower(), i + 1, []
            i += 1
            while i < n and not FENCE.match(lines[i]):
                body.append(lines[i])
                i += 1
            i += 1
            if lang not in SKIPPED_LANGS:
                yield start + 1, mode_before(lines, start - 1), body
            continue
        if lines[i].startswith("    ") and (i == 0 or not lines[i - 1].strip()):
            start, body = i, []
            while i < n and (lines[i].startswith("    ") or not lines[i].strip()):
                body.append(lines[i][4:])
                i += 1
            yield start + 1, mode_before(lines, start), body
            continue
        i += 1


def mode_before(lines, index):
    for j in range(max(0, index - 3), index):
        m = re.search(r"<!--\s*doc-check:\s*(\w+)\s*-->", lines[j])
        if m:
            return m.group(1)
    return "loose"


def is_command(text):
    return text.startswith("build/") or text.startswith("shadelab ")


def steps(first_line, body):
    """Splits a block into commands, each with the output lines it shows (for a transcript)."""
    out, k = [], 0
    transcript = any(l.startswith("$ ") for l in body)   # then only `$` lines are commands
    while k < len(body):
        raw = body[k].rstrip()
        line_no = first_line + k
        prompt = raw.startswith("$ ")
        text = raw[2:] if prompt else raw
        k += 1
        if not is_command(text) or (transcript and not prompt):
            if out and out[-1]["prompt"]:
                out[-1]["shown"].append(raw)
            continue
        while text.endswith("\\") and k < len(body):
            text = text[:-1] + " " + body[k].strip()
            k += 1
        out.append({"line": line_no, "text": text, "prompt": prompt, "shown": []})
    return out


def split_comment(text):
    m = re.search(r"\s{2,}#|\s#\s", text)
    return (text[:m.start()], text[m.end():]) if m else (text, "")


def synopsis_reason(cmd):
    bare = re.sub(r"'[^']*'|\"[^\"]*\"", "''", cmd)
    if "[" in bare and re.search(r"\[(--|\.\.\.|\w+\.\.\.)", bare) or re.search(r"\s\[", bare):
        return "an optional part in brackets"
    if "..." in bare:
        return "an ellipsis"
    if re.search(r"\w\|\w", bare):
        return "alternatives a|b"
    m = PLACEHOLDER.search(bare)
    if m:
        return f"the placeholder {m.group(0)}"
    return None


def tokens(line, words_only):
    line = line.strip()
    if words_only:
        line = re.sub(r"^[*x]\s+", "", line)
    return TOKEN.findall(line)


def same_line(shown, actual, words_only):
    a, b = tokens(shown, words_only), tokens(actual, words_only)
    if len(a) != len(b):
        return False
    for s, t in zip(a, b):
        ns, nt = NUMBER.fullmatch(s), NUMBER.fullmatch(t)
        if ns and nt:
            if words_only:
                continue
            x, y = float(s), float(t)
            if abs(x - y) > RTOL * max(abs(x), abs(y)) + ATOL:
                return False
        elif s != t:
            return False
    return True


def closest(shown, actual_lines):
    words = set(re.findall(r"[A-Za-z_]{3,}", shown))
    best, score = "", -1
    for a in actual_lines:
        s = len(words & set(re.findall(r"[A-Za-z_]{3,}", a)))
        if s > score:
            best, score = a, s
    return best


def check_transcript(shown_lines, output, mode):
    """The shown lines the run did not print (empty when the transcript holds)."""
    if mode == "none":
        return []
    actual = [l.rstrip() for l in output.splitlines() if l.strip()]
    missing = []
    for s in shown_lines:
        t = s.strip()
        if not t or t.startswith("[...") or t == "[...]" or TIMING.search(t) or BY_TIMING.match(t):
            continue
        if not any(same_line(t, a, mode == "words") for a in actual):
            missing.append((t, closest(t, actual)))
    return missing


def main():
    if len(sys.argv) != 4:
        print("usage: run_doc_commands.py PAGE.md BUILD_DIR SOURCE_DIR", file=sys.stderr)
        return 2
    page, build, src = sys.argv[1], os.path.abspath(sys.argv[2]), os.path.abspath(sys.argv[3])
    with open(page, encoding="utf-8") as f:
        lines = f.read().splitlines()
    name = os.path.relpath(page, src)
    stem = os.path.splitext(os.path.basename(page))[0].lower()
    all_steps = [(mode, st) for first, mode, body in blocks(lines) for st in steps(first, body)]
    if not all_steps:
        print(f"{name}: shows no command")
        return 0
    passed = failed = 0
    skipped = []
    with tempfile.TemporaryDirectory() as tmp:
        os.symlink(build, os.path.join(tmp, "build"))
        for d in ("meshes", "scenes", "tests"):
            os.symlink(os.path.join(src, d), os.path.join(tmp, d))
        env = dict(os.environ, PATH=build + os.pathsep + os.environ.get("PATH", ""))
        setup = os.path.join(src, "tests", "docs", "setup", stem + ".sh")
        if os.path.exists(setup):
            r = subprocess.run(["bash", setup, build, src], cwd=tmp, env=env, capture_output=True, text=True)
            if r.returncode != 0:
                print(f"FAIL ({name}): its setup {os.path.relpath(setup, src)} exited {r.returncode}")
                print("\n".join((r.stdout + r.stderr).splitlines()[-8:]))
                return 1
        for mode, st in all_steps:
            cmd, comment = split_comment(st["text"])
            where = f"{name}:{st['line']}"
            m = re.search(r"\(not run by the tests: ([^)]*)\)", st["text"])
            if m:
                skipped.append((where, cmd.strip(), m.group(1)))
                continue
            reason = synopsis_reason(cmd)
            if reason:
                skipped.append((where, cmd.strip(), "a synopsis: " + reason))
                continue
            want = 0
            m = re.search(r"\(exits (\d+)\)", comment)
            if m:
                want = int(m.group(1))
            t0 = time.monotonic()
            try:
                r = subprocess.run(["bash", "-c", cmd], cwd=tmp, env=env, stdin=subprocess.DEVNULL,
                                   capture_output=True, text=True, timeout=900)
                output, code = r.stdout + r.stderr, r.returncode
            except subprocess.TimeoutExpired:
                output, code = "(timed out after 900 s)", -1
            seconds = time.monotonic() - t0
            if seconds > 20:
                print(f"slow ({where}): {seconds:.0f} s: {cmd.strip()}")
            problems = []
            if code != want:
                problems.append(f"exit status {code}, the page expects {want}")
            for shown, near in check_transcript(st["shown"], output, mode):
                problems.append(f"shown but not printed: {shown!r}\n      nearest printed line: {near!r}")
            if problems:
                failed += 1
                print(f"FAIL ({where}): {cmd.strip()}")
                for p in problems:
                    print("    " + p)
                if code != want:
                    print("\n".join("    | " + l for l in output.splitlines()[-6:]))
            else:
                passed += 1
    for where, cmd, why in skipped:
        print(f"not run ({where}, {why}): {cmd}")
    print(f"{name}: {passed} passed, {failed} failed, {len(skipped)} not run (listed)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
