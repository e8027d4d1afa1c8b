// PDS3 and PDS4 images through GDAL (host/image/raster.hpp; read_image sends .img / .lbl / .xml there). The files
// are made here, not by the code under test: the PDS3 images by writing an attached ODL label and the raw lines
// byte by byte (GDAL's PDS3 driver reads only), the PDS4 product (XML label + raw .img) with GDAL's PDS4 driver.
// Checked: values at every pixel and the raster geometry (size, row 0 at the top = the label's first line, column
// 0 the first sample), 16-bit integers with the label's SCALING_FACTOR and OFFSET applied, and broken labels
// (missing keywords, a truncated or unparsable label, data shorter than the label says, a missing data file)
// refused with one line naming the file. shadelab reads no viewing geometry from PDS labels: PHASE_ANGLE and the
// like in a label are ignored; the geometry comes from --phase/--pa/--radius or backplane images.
#include <catch2/catch.hpp>

#include <gdal_priv.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "image/image.hpp"
#include "image/raster.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

constexpr int kW = 7, kH = 5;   // not square, so that a transposed read would show

// The I/F-like value the files hold at (x, y), y the label's line (0 first).
float value_at(int x, int y) { return 0.05f + 0.01f * float(10 * y + x); }
// The 16-bit DN of the integer file and the value SCALING_FACTOR 0.0001, OFFSET 0.01 make of it.
std::uint16_t dn_at(int x, int y) { return std::uint16_t(1000 + 100 * y + x); }
double scaled_at(int x, int y) { return 0.0001 * dn_at(x, y) + 0.01; }

struct Pds3Sample {
    std::string type;   // SAMPLE_TYPE
    int bits;           // SAMPLE_BITS
};

// A PDS3 image with an attached label (PDS Standards Reference 3.8, ch. 5 and appendix A.21): fixed-length
// records of one image line each, the label padded to whole records, ^IMAGE pointing at the first image record.
// `drop` removes the label line containing that keyword; `lines_written` < kH truncates the data.
void write_pds3(const std::string& path, const Pds3Sample& s, const std::string& drop = "", int lines_written = kH) {
    const int record = kW * s.bits / 8;
    std::vector<std::string> body = {
        "PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", "RECORD_BYTES = " + std::to_string(record),
        "FILE_RECORDS = @FILE", "LABEL_RECORDS = @LABEL", "^IMAGE = @IMAGE", "TARGET_NAME = MOON",
        "PHASE_ANGLE = 30.0 <DEG>", "OBJECT = IMAGE", "  LINES = " + std::to_string(kH),
        "  LINE_SAMPLES = " + std::to_string(kW), "  SAMPLE_TYPE = " + s.type,
        "  SAMPLE_BITS = " + std::to_string(s.bits),
        "  BANDS = 1"};
    if (s.bits == 16) body.insert(body.end(), {"  SCALING_FACTOR = 0.0001", "  OFFSET = 0.01"});
    body.insert(body.end(), {"END_OBJECT = IMAGE", "END"});
    // the label's size in records does not depend on the three numbers filled in last (they stay short)
    std::string label;
    for (const auto& l : body)
        if (drop.empty() || l.find(drop) == std::string::npos) label += l + "\r\n";
    const int label_records = int(label.size() + 16) / record + 1;
    auto fill = [&](const std::string& key, int v) { label.replace(label.find(key), key.size(), std::to_string(v)); };
    fill("@FILE", label_records + kH);
    fill("@LABEL", label_records);
    fill("@IMAGE", label_records + 1);
    label.resize(std::size_t(label_records * record), ' ');
    std::ofstream f(path, std::ios::binary);
    f << label;
    for (int y = 0; y < lines_written; ++y)
        for (int x = 0; x < kW; ++x) {
            if (s.bits == 32) {   // PC_REAL: IEEE float, least significant byte first
                const float v = value_at(x, y);
                unsigned char b[4];
                std::memcpy(b, &v, 4);
                if (s.type == "IEEE_REAL") std::swap(b[0], b[3]), std::swap(b[1], b[2]);   // most significant first
                f.write(reinterpret_cast<const char*>(b), 4);
            } else {   // MSB_UNSIGNED_INTEGER
                const std::uint16_t v = dn_at(x, y);
                const char b[2] = {char(v >> 8), char(v & 0xff)};
                f.write(b, 2);
            }
        }
}

// A PDS4 product with GDAL's PDS4 driver: `path` the XML label, the raw array beside it.
void write_pds4(const std::string& path) {
    GDALAllRegister();
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("PDS4");
    REQUIRE(drv);
    GDALDataset* ds = drv->Create(path.c_str(), kW, kH, 1, GDT_Float32, nullptr);
    REQUIRE(ds);
    std::vector<float> v(std::size_t(kW * kH));
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) v[std::size_t(y * kW + x)] = value_at(x, y);
    CHECK(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, kW, kH, v.data(), kW, kH, GDT_Float32, 0, 0) == CE_None);
    GDALClose(ds);
}

std::string read_text(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

// The one-line error of read_image(path), "" if it did not throw.
std::string error_of(const std::string& path) {
    try {
        read_image(path);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

void check_one_line_naming(const std::string& msg, const std::string& file) {
    INFO(msg);
    CHECK_FALSE(msg.empty());
    CHECK(msg.find('\n') == std::string::npos);
    CHECK(msg.find(file) != std::string::npos);
}

// Every pixel of `path` read as a kW x kH image holding `want` (exactly, or to 1e-7 relative), none masked.
template <class Want>
void check_read(const std::string& path, Want want, bool exact) {
    REQUIRE(is_gdal_path(path));
    const Image img = read_image(path);
    REQUIRE(img.width == kW);
    REQUIRE(img.height == kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            INFO("x " << x << " y " << y);
            if (exact) CHECK(img.at(x, y, 0) == float(want(x, y)));
            else CHECK(img.at(x, y, 0) == Approx(want(x, y)).epsilon(1e-7));
            CHECK(img.at(x, y, 1) == 1.0f);   // not masked
        }
    CHECK(read_image(path + "[1]").at(3, 2, 0) == img.at(3, 2, 0));   // band 1 by index
}

}  // namespace

TEST_CASE("PDS3 image with an attached label: values at every pixel, row 0 = the first line, float and scaled integers",
          "[pds]") {
    const auto dir = test::scratch_dir("pds3");
    for (const Pds3Sample& s : {Pds3Sample{"PC_REAL", 32}, Pds3Sample{"IEEE_REAL", 32},
                                Pds3Sample{"MSB_UNSIGNED_INTEGER", 16}}) {
        INFO(s.type);
        const std::string path = (dir / (s.type + ".img")).string();
        write_pds3(path, s);
        if (s.bits == 32) check_read(path, value_at, true);
        else check_read(path, scaled_at, false);   // DN * 0.0001 + 0.01
    }
}

TEST_CASE("PDS3: broken labels and short data are refused with one line naming the file", "[pds][errors]") {
    const auto dir = test::scratch_dir("pds3-broken");
    const Pds3Sample f32{"PC_REAL", 32};
    const std::string no_lines = (dir / "no-lines.img").string();
    write_pds3(no_lines, f32, "LINES =");
    check_one_line_naming(error_of(no_lines), no_lines);
    const std::string no_type = (dir / "no-sample-type.img").string();
    write_pds3(no_type, f32, "SAMPLE_TYPE");
    check_one_line_naming(error_of(no_type), no_type);
    CHECK(error_of(no_type).find("IMAGE object has no SAMPLE_TYPE") != std::string::npos);   // GDAL alone would guess
    const std::string short_data = (dir / "short.img").string();
    write_pds3(short_data, f32, "", 2);   // the label says 5 lines, 2 are there
    check_one_line_naming(error_of(short_data), short_data);
    const std::string garbage = (dir / "garbage.img").string();
    std::ofstream(garbage) << "this is not a PDS label\n";
    check_one_line_naming(error_of(garbage), garbage);
    CHECK(error_of((dir / "none.img").string()).find("not found") != std::string::npos);
    CHECK(error_of(no_lines + "[2]").find("cannot read '" + no_lines + "[2]' with GDAL") == 0);   // before the band
}

TEST_CASE("PDS4 product (XML label + raw array, written by GDAL's PDS4 driver): values, size, orientation", "[pds]") {
    const auto dir = test::scratch_dir("pds4");
    const std::string xml = (dir / "disc.xml").string();
    write_pds4(xml);
    check_read(xml, value_at, true);
    CHECK_THROWS_WITH(read_image(xml + "[2]"), Catch::Contains("has no band '2': its bands are 1"));
}

TEST_CASE("PDS4: a truncated label, a label without its array and a missing data file are refused with one line",
          "[pds][errors]") {
    const auto dir = test::scratch_dir("pds4-broken");
    const std::string good = (dir / "good.xml").string();
    write_pds4(good);
    const std::string label = read_text(good);
    const std::string truncated = (dir / "truncated.xml").string();
    std::ofstream(truncated, std::ios::binary) << label.substr(0, label.size() / 2);
    check_one_line_naming(error_of(truncated), truncated);
    // the label with its File_Area_Observational (the array's description) removed
    const std::size_t a = label.find("<File_Area_Observational>"), b = label.find("</File_Area_Observational>");
    REQUIRE(a != std::string::npos);
    REQUIRE(b != std::string::npos);
    const std::string no_array = (dir / "no-array.xml").string();
    const std::size_t end = b + std::strlen("</File_Area_Observational>");
    std::ofstream(no_array, std::ios::binary) << label.substr(0, a) + label.substr(end);
    check_one_line_naming(error_of(no_array), no_array);
    // the data file gone
    std::string data;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().extension() == ".img" && e.path().stem() == "good") data = e.path().string();
    REQUIRE_FALSE(data.empty());
    std::filesystem::remove(data);
    check_one_line_naming(error_of(good), good);
}
