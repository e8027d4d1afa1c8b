#!/usr/bin/env bash
# shadelab photometry fit as a user runs it: Hapke discs rendered by `moon render` at three phases, fitted back
# with standard errors, several laws ranked (the true one first), `moon fit --law hapke_hen` on one of them, and bad
# input refused with one line and exit 1.
# Usage: photometry_fit.sh SHADELAB_BINARY
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/expect.sh"   # fails, passes, expect
bin="$1"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

hapke=(-m hapke_hen -p wh=0.25 -p b0=1.2 -p hh=0.08 -p theta=18 -p hg1=0.25)
for g in 2 12 40 80; do
    "$bin" -q moon render "${hapke[@]}" --phase "$g" --pa 70 --size 80x80 --radius 34 -o "g$g.exr" > /dev/null || {
        echo "FAIL: moon render at phase $g"; exit 1; }
done
expect "fit hapke" 0 "^wh +0\.(25(00[0-9]*)?|2499[0-9]*) " -- "$bin" photometry fit g2.exr g12.exr g40.exr g80.exr --phase 2,12,40,80 --pa 70 --radius 34 --model hapke_hen
expect "fit reports evaluations per second" 0 "evaluations: [0-9]+ in .* per second" -- \
    "$bin" photometry fit g2.exr g12.exr g40.exr g80.exr --phase 2,12,40,80 --pa 70 --radius 34 --model HapkeHen
expect "ranking" 0 "best: hapke_hen" -- "$bin" photometry fit g2.exr g12.exr g40.exr g80.exr --phase 2,12,40,80 --pa 70 \
    --radius 34 --models lambert,lunar_lambert,minnaert,hapke_hen
expect "phases per image" 1 "--phase is given 2 times for 4 images" -- \
    "$bin" photometry fit g2.exr g12.exr g40.exr g80.exr --phase 2,12 --radius 34 --model hapke_hen
expect "unknown law" 1 "the law 'hapke' cannot be fitted: choose one of" -- \
    "$bin" photometry fit g2.exr --phase 2 --radius 34 --model hapke
expect "unknown free parameter" 1 "--free k is not a parameter of hapke_hen" -- \
    "$bin" photometry fit g2.exr --phase 2 --radius 34 --model hapke_hen --free wh,k
"$bin" -q moon render -m lambert --size 60x60 --radius 20 -o small.exr > /dev/null
expect "backplanes of another size" 1 "small.exr is 60x60 but g2.exr is 80x80: backplanes must have the image's size" -- \
    "$bin" photometry fit g2.exr --backplanes small.exr,small.exr,small.exr --model lambert
# rasters through GDAL: a TIFF read by band (bracket syntax); a band it does not have; backplanes of another size
"$bin" -q moon render -m lambert --size 80x80 --radius 34 --phase 2 -o g2.tif > /dev/null
"$bin" -q moon render -m lambert --size 60x60 --radius 20 -o small.tif > /dev/null
expect "tif band by index" 0 "pixels: [0-9]+ from 1 image" -- \
    "$bin" photometry fit "g2.tif[1]" --phase 2 --radius 34 --model lambert
expect "missing band" 1 "g2.tif has no band '9': its bands are 1" -- \
    "$bin" photometry fit "g2.tif[9]" --phase 2 --radius 34 --model lambert
expect "band backplanes of another size" 1 "small.tif\[1\] is 60x60 but g2.exr is 80x80" -- \
    "$bin" photometry fit g2.exr --backplanes "small.tif[1],small.tif[1],small.tif[1]" --model lambert
# moon fit --law hapke_hen: one disc, wh, theta, hg1 fitted with b0 and hh held (named), bad input
one=(g40.exr --phase 40 --pa 70 --radius 34 --centre 40,40)
expect "moon fit hapke wh" 0 "^wh +0\.(25(00[0-9]*)?|2499[0-9]*) " -- "$bin" moon fit "${one[@]}" --law hapke_hen -p b0=1.2 -p hh=0.08
expect "moon fit hapke theta" 0 "^theta +(18|18\.00[0-9]*|17\.99[0-9]*) " -- "$bin" moon fit "${one[@]}" --law HapkeHen -p b0=1.2 -p hh=0.08
expect "moon fit hapke held" 0 "held: b0, hh, hg2: one image has one phase" -- "$bin" moon fit "${one[@]}" --law hapke_hen
expect "moon fit hapke correlations" 0 "^correlation:" -- "$bin" moon fit "${one[@]}" --law hapke_hen
expect "moon fit not hapke" 1 "lunar_lambert is not a Hapke law" -- "$bin" moon fit "${one[@]}" --law lunar_lambert
expect "moon fit unknown law" 1 "cannot be fitted: choose one of" -- "$bin" moon fit "${one[@]}" --law hapke_lol
expect "moon fit bad start" 1 "-p wh=1.5 is out of range for hapke_hen" -- \
    "$bin" moon fit "${one[@]}" --law hapke_hen -p wh=1.5
expect "moon fit hapke without k maps" 1 "--bins and --grid are Minnaert k maps" -- \
    "$bin" moon fit "${one[@]}" --law hapke_hen --bins 4
expect "moon fit minnaert without -p" 1 "-p and --free go with a Hapke law" -- "$bin" moon fit "${one[@]}" -p wh=0.3
expect "moon fit minnaert as before" 0 "k  = " -- "$bin" moon fit "${one[@]}" --no-plot -o fit.csv

echo "photometry_fit.sh: $passes passed, $fails failed"
[ "$fails" -eq 0 ]
