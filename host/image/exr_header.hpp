// The EXR header, read with OpenEXR's core C library before OpenImageIO opens the file.
//
// Why before: OpenImageIO 2.4 opens an EXR through OpenEXR's C++ InputFile, which allocates its decode
// buffers at open time, sized by the header alone: max(1, 2 x threads) line (or tile) buffers, each
// holding one unpacked chunk (scanlines-per-chunk x data-window width x bytes per pixel, 16 lines for
// ZIP, 32 for PIZ/B44, 256 for DWAB) and its decompressor's two buffers of the same size. An 877-byte
// file whose data window is 2097160 pixels wide (its display window 8x6) costs 1.6 GB of allocations
// before the first pixel is read. The core library parses the header without allocating any of that,
// so the sizes can be checked against the file and the memory limit first.
#pragma once
#include <cstdint>
#include <string>

namespace shadelab {

struct ExrHeader {
    int width = 0, height = 0;           // data window of part 0 (what OpenImageIO reads)
    int channels = 0;
    double bytes_per_pixel = 0;          // sum over part 0's channels of their stored size
    std::uint64_t max_chunk_bytes = 0;   // the largest unpacked chunk over all parts
    std::int64_t chunks = 0;             // over all parts
    int parts = 0;
};

// Parses the header of `path`; throws shadelab::Error (one line naming the file and the field) when it
// cannot be parsed, holds deep data, has more chunks than the file could index, or when decoding it
// would need more memory than the limit (core/limits.hpp), counting the float image, the native copy
// and OpenEXR's decode buffers.
ExrHeader check_exr_header(const std::string& path);

}  // namespace shadelab
