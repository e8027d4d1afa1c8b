#!/usr/bin/env bash
# Runs a doc page's worked example as it stands: its ```sh blocks (with `shadelab` meaning the built binary),
# then its last ```python block, in a scratch folder. Usage: run_doc_blocks.sh PAGE.md SHADELAB PYTHON
set -euo pipefail
page="$1"; bin="$(cd "$(dirname "$2")" && pwd)/$(basename "$2")"; py="$3"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
awk '/^```sh$/{on=1; next} /^```$/{on=0} on' "$page" > "$tmp/example.sh"
awk '/^```python$/{on=1; buf=""; next} /^```$/{if (on) last=buf; on=0} on{buf=buf $0 "\n"} END{printf "%s", last}' "$page" > "$tmp/example.py"
[ -s "$tmp/example.sh" ] && [ -s "$tmp/example.py" ] || { echo "FAIL: no sh or python block in $page"; exit 1; }
cd "$tmp"
export bin
sed -i 's|^shadelab |"$bin" |' example.sh
bash -e example.sh
"$py" example.py
[ "$(ls ./*.png 2>/dev/null | wc -l)" -gt 0 ] || { echo "FAIL: the example wrote no picture"; exit 1; }
echo "doc example: 1 passed, 0 failed"
