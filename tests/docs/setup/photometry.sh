#!/usr/bin/env bash
# The files docs/photometry.md's examples take as the user's own, made in the scratch folder before they run:
# ISIS parameter files (the HapkeHen surface of ISIS's unit tests, a Lunar-Lambert law), a geometry table, disc
# images rendered by `moon render` at the page's geometry, an image with phase/incidence/emission backplanes, an
# ISIS3 cube (GDAL's Python bindings) and a FITS file with a SCI extension (astropy).
# Usage (from tests/docs/run_doc_commands.py, in the scratch folder): photometry.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
bin="$1/shadelab"

cat > params.pvl <<'PVL'
Object = PhotometricModel
  Group = Algorithm
    Name = HapkeHen
    Wh = 0.52
    B0 = 1.0
    Hh = 1.0
    Theta = 30.0
    Hg1 = 0.213
    Hg2 = 1.0
  End_Group
End_Object
End
PVL
cp params.pvl hapke.pvl
cat > law.pvl <<'PVL'
Object = PhotometricModel
  Group = Algorithm
    Name = LunarLambert
    L = 0.6
  End_Group
End_Object
End
PVL
printf 'phase,incidence,emission\n0,0,0\n30,20,10\n60,45,30\n90,60,30\n' > geometry.csv

hapke=(-m hapke_hen -p wh=0.25 -p b0=1.2 -p hh=0.08 -p theta=18 -p hg1=0.25)
"$bin" -q moon render "${hapke[@]}" --phase 40 --pa 90 --size 256x256 --radius 110 -o disc.exr > /dev/null
for g in 2 12 40 80; do
    "$bin" -q moon render "${hapke[@]}" --phase "$g" --pa 70 --size 80x80 --radius 34 -o "g$g.exr" > /dev/null
done
"$bin" -q moon render -m lunar_lambert --lunar-l 0.4 --albedo 0.2 --phase 30 --pa 0 --size 220x220 --radius 100 \
    -o obs_primary.fits > /dev/null

/usr/bin/python3 - <<'PY'
import json
import numpy as np
from astropy.io import fits
from osgeo import gdal

# A Lunar-Lambert plane seen from above at phase 30: incidence across the image, the viewer 10 deg off nadir.
h, w = 64, 96
inc = np.tile(np.linspace(5.0, 70.0, w, dtype=np.float32), (h, 1))
ema = np.full((h, w), 10.0, np.float32)
pha = inc + ema                      # sun and viewer on either side of the normal, in one plane
mu0, mu = np.cos(np.radians(inc)), np.cos(np.radians(ema))
L = 0.6
img = (0.2 * (2 * L * mu0 / (mu0 + mu) + (1 - L) * mu0)).astype(np.float32)
for name, plane in (("img", img), ("pha", pha), ("inc", inc), ("ema", ema)):
    fits.PrimaryHDU(plane).writeto(name + ".fits", overwrite=True)

# An ISIS3 cube of a reflectance band and its three backplanes, named in the cube's BandBin.
gdal.UseExceptions()
ds = gdal.GetDriverByName("ISIS3").Create("cube.cub", w, h, 4, gdal.GDT_Float32)
ds.SetMetadata([json.dumps({"IsisCube": {"_type": "object", "BandBin": {
    "_type": "group", "Name": ["Reflectance", "Phase", "Incidence", "Emission"]}}})], "json:ISIS3")
for b, plane in enumerate((img, pha, inc, ema), start=1):
    ds.GetRasterBand(b).WriteArray(plane)
ds = None

# A FITS file whose image is in an extension named SCI (as HST and many archives write them).
with fits.open("obs_primary.fits") as f:
    fits.HDUList([fits.PrimaryHDU(), fits.ImageHDU(f[0].data, header=f[0].header, name="SCI")]).writeto(
        "obs.fits", overwrite=True)
PY
for name in img pha inc ema; do oiiotool "$name.fits" -d float -o "$name.exr"; done
