// Resource limits: work whose memory need is known up front (an image size, a header's element counts)
// is checked against one limit before anything is allocated, so a hostile or mistyped size ends in one
// clear line with the figure it would need instead of std::bad_alloc or the OOM killer.
//
// The limit is the machine's physical memory unless SHADELAB_MAX_MEMORY says otherwise ("8G", "512M",
// "2T" or plain bytes); commands that allocate by a user-given size also take --max-memory, which sets it.
#pragma once
#include <cstdint>
#include <string>

namespace shadelab {

// Peak memory of a render per pixel of the image, at full coverage: the rasteriser's per-pixel buffers,
// the fragment buffer (8 floats), the shaded planes, the RGBA float image and the encoder's copy.
// Measured (peak RSS over the ~230 MB of an idle PoCL process, quad filling the frame, PNG or EXR):
// 80 bytes/pixel at 2048x2048, 76 at 4096x4096; 90 leaves a margin. 16384x16384 then needs 24 GB.
constexpr double kRenderBytesPerPixel = 90.0;

// Bytes as "6.4 GB" (decimal units: what `free -g`-style figures and file managers show).
std::string format_bytes(double bytes);

// "8G", "512M", "1.5T", "4096" -> bytes; throws shadelab::Error naming `what` for anything else.
std::uint64_t parse_bytes(const std::string& text, const std::string& what);

// The current limit in bytes.
std::uint64_t memory_limit();
// Overrides the limit for this process (--max-memory); 0 restores the default.
void set_memory_limit(std::uint64_t bytes);

// Throws shadelab::Error "<what> would need <figure>, more than the limit of <limit> (<how to raise>)"
// when `bytes` (a double, so a product of hostile sizes cannot wrap around) exceeds the limit.
void check_memory(const std::string& what, double bytes);

}  // namespace shadelab
