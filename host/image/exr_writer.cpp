#include "image/exr_writer.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>

#include <ctime>
#include <algorithm>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>

namespace shadelab {

namespace {

constexpr std::pair<const char*, Imf::Compression> kCompressions[] = {
    {"none", Imf::NO_COMPRESSION}, {"rle", Imf::RLE_COMPRESSION},     {"zips", Imf::ZIPS_COMPRESSION},
    {"zip", Imf::ZIP_COMPRESSION},  {"piz", Imf::PIZ_COMPRESSION},     {"pxr24", Imf::PXR24_COMPRESSION},
    {"b44", Imf::B44_COMPRESSION},  {"b44a", Imf::B44A_COMPRESSION}};
// (Not DWAA and DWAB: OpenImageIO's files with them are smaller than OpenEXR's own at its default quality,
// so those stay with OpenImageIO, in the plug-in, where their size is what it was.)

bool compression_of(const std::string& name, Imf::Compression& c) {
    for (const auto& [n, value] : kCompressions)
        if (name == n) {
            c = value;
            return true;
        }
    return false;
}

const char* const kNames[4][4] = {{"Y"}, {"R", "G"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};

// "YYYY:MM:DD HH:MM:SS", local time: OpenImageIO's DateTime, which it stores as EXR's capDate.
std::string cap_date() {
    const std::time_t now = std::time(nullptr);
    std::tm local{};
    localtime_r(&now, &local);
    char text[32];
    std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", &local);
    return text;
}

}  // namespace

bool exr_direct(const std::string& compression, int channels) {
    Imf::Compression c;
    return channels >= 1 && channels <= 4 && compression_of(compression, c);
}

bool write_exr(const std::string& file, const Image& img, const std::string& compression, std::string& why) {
    Imf::Compression c = Imf::ZIPS_COMPRESSION;
    if (!compression_of(compression, c) || img.channels < 1 || img.channels > 4) {
        why = "internal: write_exr called for compression '" + compression + "' and " + std::to_string(img.channels) +
              " channels";
        return false;
    }
    try {
        Imf::Header header(img.width, img.height);
        header.compression() = c;
        header.insert("Software", Imf::StringAttribute("shadelab"));
        Imf::addCapDate(header, cap_date());
        Imf::FrameBuffer frame;
        const std::size_t pixel = std::size_t(img.channels) * sizeof(float), row = pixel * std::size_t(img.width);
        char* base = reinterpret_cast<char*>(const_cast<float*>(img.pixels.data()));
        for (int ch = 0; ch < img.channels; ++ch) {
            const char* name = kNames[img.channels - 1][ch];
            header.channels().insert(name, Imf::Channel(Imf::FLOAT));
            frame.insert(name, Imf::Slice(Imf::FLOAT, base + std::size_t(ch) * sizeof(float), pixel, row));
        }
        // OpenEXR compresses line blocks on its global pool: all hardware threads, as OpenImageIO's default
        static std::once_flag pool;
        std::call_once(pool, [] { Imf::setGlobalThreadCount(int(std::max(1u, std::thread::hardware_concurrency()))); });
        Imf::OutputFile out(file.c_str(), header, Imf::globalThreadCount());
        out.setFrameBuffer(frame);
        out.writePixels(img.height);
        return true;
    } catch (const std::exception& e) {
        why = e.what();
        return false;
    }
}

}  // namespace shadelab
