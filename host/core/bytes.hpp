// Little-endian fields and hex digits for the on-disk caches (cl/program_cache.cpp, mesh/mesh_cache.cpp), so
// that both write and read their entries the same way.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace shadelab::bytes {

// Lower-case hex of the bytes of `raw` (a SHA-256 digest -> 64 characters).
inline std::string hex(const std::string& raw) {
    static const char* digits = "0123456789abcdef";
    std::string s;
    for (unsigned char c : raw) {
        s += digits[c >> 4];
        s += digits[c & 15];
    }
    return s;
}

inline void put_u32(std::string& s, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) s += char((v >> (8 * i)) & 0xff);
}
inline void put_u64(std::string& s, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) s += char((v >> (8 * i)) & 0xff);
}
// The `bytes`-byte little-endian number at s[at] (the caller has checked that s holds it).
inline std::uint64_t get_le(const std::string& s, std::size_t at, int bytes) {
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= std::uint64_t(static_cast<unsigned char>(s[at + std::size_t(i)])) << (8 * i);
    return v;
}

}  // namespace shadelab::bytes
