// What shadelab's on-disk caches (cl/program_cache.cpp, mesh/mesh_cache.cpp) share: the folder they live in, the
// SHA-256 they key and check with (OpenSSL's EVP interface, FIPS 180-4), and the entry header
//   magic (4 bytes), format (u32), key (32 bytes), payload size (u64), payload SHA-256 (32 bytes), payload
// with its checks: an entry is used only when all of them hold.
#pragma once
#include <openssl/evp.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "core/bytes.hpp"
#include "core/error.hpp"

namespace shadelab::cache_file {

constexpr std::size_t kDigest = 32;   // SHA-256
constexpr std::size_t kHeader = 4 + 4 + kDigest + 8 + kDigest;

// The folder `setting` names: "" = the variable `env_var`, then $XDG_CACHE_HOME/shadelab/<name>, then
// $HOME/.cache/shadelab/<name>; "off" or "0" = no cache (returns "").
inline std::string folder(const std::string& setting, const char* env_var, const char* name) {
    auto env = [](const char* v) {
        const char* s = std::getenv(v);
        return s ? std::string(s) : std::string();
    };
    const std::string s = setting.empty() ? env(env_var) : setting;
    if (s == "off" || s == "0") return "";
    if (!s.empty()) return s;
    const std::string xdg = env("XDG_CACHE_HOME");
    if (!xdg.empty()) return (std::filesystem::path(xdg) / "shadelab" / name).string();
    const std::string home = env("HOME");
    if (!home.empty()) return (std::filesystem::path(home) / ".cache" / "shadelab" / name).string();
    return "";   // nowhere to keep it: no cache
}

// Incremental SHA-256.
class Sha256 {
public:
    Sha256() : ctx_(EVP_MD_CTX_new(), EVP_MD_CTX_free) {
        if (!ctx_ || EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr) != 1) fail();
    }
    void add(const void* data, std::size_t n) {
        if (n && EVP_DigestUpdate(ctx_.get(), data, n) != 1) fail();
    }
    std::string raw() {   // the 32 bytes of the digest
        unsigned char md[EVP_MAX_MD_SIZE];
        unsigned int len = 0;
        if (EVP_DigestFinal_ex(ctx_.get(), md, &len) != 1 || len != kDigest) fail();
        return std::string(reinterpret_cast<const char*>(md), kDigest);
    }

private:
    [[noreturn]] static void fail() { throw Error("internal: SHA-256 failed in OpenSSL"); }
    std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx_;
};

inline std::string sha256_raw(const void* data, std::size_t n) {
    Sha256 h;
    h.add(data, n);
    return h.raw();
}

// The header of an entry whose key is `hex_key` (64 hex digits) and whose payload has `size` bytes and SHA-256
// `payload_digest` (raw).
inline std::string header(const char (&magic)[4], std::uint32_t format, const std::string& hex_key,
                          std::uint64_t size, const std::string& payload_digest) {
    std::string h(magic, 4);
    bytes::put_u32(h, format);
    for (std::size_t i = 0; i < kDigest; ++i) h += char(std::stoi(hex_key.substr(2 * i, 2), nullptr, 16));
    bytes::put_u64(h, size);
    return h + payload_digest;
}

// Empty when the entry `f` has this magic and format, holds `hex_key`, and its payload has the size and the SHA-256
// its header says; else why not. `entry` and `payload` name them in the reason ("mesh-cache", "payload").
inline std::string header_problem(const std::string& f, const char (&magic)[4], std::uint32_t format,
                                  const std::string& hex_key, const std::string& entry, const std::string& payload) {
    if (f.size() < kHeader || std::memcmp(f.data(), magic, 4) != 0)
        return "not a shadelab " + entry + " entry (or truncated header)";
    if (bytes::get_le(f, 4, 4) != format)
        return "format version " + std::to_string(bytes::get_le(f, 4, 4)) + ", expected " + std::to_string(format);
    if (bytes::hex(f.substr(8, kDigest)) != hex_key) return "the entry holds another key (stale or renamed)";
    const std::uint64_t size = bytes::get_le(f, 8 + kDigest, 8);
    if (size != f.size() - kHeader)
        return payload + " size " + std::to_string(size) + " does not match the file (" +
               std::to_string(f.size() - kHeader) + " bytes after the header): truncated or corrupt";
    if (sha256_raw(f.data() + kHeader, f.size() - kHeader) != f.substr(16 + kDigest, kDigest))
        return "the " + payload + "'s SHA-256 does not match: corrupt";
    return {};
}

}  // namespace shadelab::cache_file
