"""Seed files for fuzz_raster (scripts/fuzz.sh): small valid rasters of each format read through GDAL, each
prefixed with the format byte fuzz/fuzz_raster.cpp reads first. Usage: make_raster_seeds.py OUT_DIR.
The ISIS3 cube, GeoTIFF and PDS4 label are written by GDAL (python3-gdal); the PDS3 image with its attached
label is written byte by byte (GDAL has no PDS3 writer)."""
import os
import struct
import sys

out = sys.argv[1]
os.makedirs(out, exist_ok=True)


def seed(name, fmt, data):
    with open(os.path.join(out, name), "wb") as f:
        f.write(bytes([fmt]) + data)


def pds3(sample_type, bits, values, w=4, h=3):
    record = w * bits // 8
    fmt = {("PC_REAL", 32): "<f", ("MSB_INTEGER", 16): ">h", ("LSB_UNSIGNED_INTEGER", 8): "<B"}[(sample_type, bits)]
    image = b"".join(struct.pack(fmt, v) for v in values)
    for label_records in range(1, 1024):
        label = "\r\n".join([
            "PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", f"RECORD_BYTES = {record}",
            f"FILE_RECORDS = {label_records + h}", f"LABEL_RECORDS = {label_records}",
            f"^IMAGE = {label_records + 1}", "OBJECT = IMAGE", f"  LINES = {h}", f"  LINE_SAMPLES = {w}",
            f"  SAMPLE_TYPE = {sample_type}", f"  SAMPLE_BITS = {bits}", "  SCALING_FACTOR = 0.5",
            "  OFFSET = 1.0", "END_OBJECT = IMAGE", "END", ""]).encode()
        if len(label) <= label_records * record:
            return label.ljust(label_records * record, b" ") + image
    raise SystemExit("make_raster_seeds: PDS3 label does not fit")


seed("pds3_float.lbl", 1, pds3("PC_REAL", 32, [0.25 * i for i in range(12)]))
seed("pds3_int16.img", 3, pds3("MSB_INTEGER", 16, [i * 100 - 300 for i in range(12)]))
seed("pds3_uint8.lbl", 1, pds3("LSB_UNSIGNED_INTEGER", 8, list(range(12))))

try:
    from osgeo import gdal
except ImportError:
    print("make_raster_seeds: no python3-gdal: only the PDS3 seeds were written", file=sys.stderr)
    sys.exit(0)
gdal.UseExceptions()
gdal.PushErrorHandler("CPLQuietErrorHandler")   # the PDS4 template's unfilled fields are warnings only
tmp = os.path.join(out, ".gdal")
os.makedirs(tmp, exist_ok=True)


def written(driver, name, bands, options=()):
    path = os.path.join(tmp, name)
    ds = gdal.GetDriverByName(driver).Create(path, 4, 3, bands, gdal.GDT_Float32, list(options))
    for b in range(1, bands + 1):
        ds.GetRasterBand(b).WriteRaster(0, 0, 4, 3, struct.pack("<12f", *[0.1 * b + 0.05 * i for i in range(12)]))
    ds = None
    return path


with open(written("ISIS3", "cube.cub", 2), "rb") as f:
    seed("isis3_cube.cub", 0, f.read())
with open(written("GTiff", "band.tif", 2), "rb") as f:
    seed("geotiff.tif", 4, f.read())
with open(written("PDS4", "label.xml", 1), "rb") as f:
    seed("pds4_label.xml", 2, f.read())
for name in os.listdir(tmp):
    os.remove(os.path.join(tmp, name))
os.rmdir(tmp)
