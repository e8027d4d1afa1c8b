#include "cl/program_cache.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/atomic_file.hpp"
#include "core/bytes.hpp"
#include "core/error.hpp"

namespace fs = std::filesystem;

namespace shadelab {

namespace {

constexpr char kMagic[4] = {'S', 'L', 'P', 'C'};
constexpr std::uint32_t kFormat = 1;
constexpr std::size_t kDigest = 32;   // SHA-256
constexpr std::size_t kHeader = sizeof kMagic + 4 + kDigest + 8 + kDigest;

std::string env(const char* name) {
    const char* v = std::getenv(name);
    return v ? std::string(v) : std::string();
}

std::string sha256_raw(const void* data, std::size_t n) {
    unsigned char md[EVP_MAX_MD_SIZE];
    unsigned int len = 0;
    if (EVP_Digest(data, n, md, &len, EVP_sha256(), nullptr) != 1 || len != kDigest)
        throw Error("internal: SHA-256 of the program cache failed in OpenSSL");
    return std::string(reinterpret_cast<const char*>(md), kDigest);
}

using bytes::get_le;
using bytes::hex;
using bytes::put_u32;
using bytes::put_u64;

}  // namespace

std::string program_cache_dir(const std::string& setting) {
    const std::string s = setting.empty() ? env("SHADELAB_PROGRAM_CACHE") : setting;
    if (s == "off" || s == "0") return "";
    if (!s.empty()) return s;
    const std::string xdg = env("XDG_CACHE_HOME");
    if (!xdg.empty()) return (fs::path(xdg) / "shadelab" / "programs").string();
    const std::string home = env("HOME");
    if (!home.empty()) return (fs::path(home) / ".cache" / "shadelab" / "programs").string();
    return "";   // nowhere to keep it: no cache
}

std::string sha256_hex(const std::string& bytes) { return hex(sha256_raw(bytes.data(), bytes.size())); }

std::string program_cache_key(const std::string& kernel_tree, const std::string& main_file, const std::string& options,
                              const std::string& device_identity) {
    // Length-prefixed fields, so no two different tuples give the same byte string.
    std::string m = "shadelab-program-cache " + std::to_string(kFormat) + "\n";
    for (const std::string* f : {&main_file, &options, &device_identity, &kernel_tree}) {
        put_u64(m, f->size());
        m += *f;
    }
    return sha256_hex(m);
}

std::string kernel_tree_text(const std::string& kernel_dir) {
    std::vector<fs::path> files;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(kernel_dir, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec))
        if (it->is_regular_file(ec)) files.push_back(it->path());
    std::sort(files.begin(), files.end());
    std::string text;
    for (const fs::path& p : files) {
        std::ifstream in(p, std::ios::binary);
        std::ostringstream s;
        s << in.rdbuf();
        const std::string body = s.str();
        text += fs::relative(p, kernel_dir, ec).generic_string() + "\n" + std::to_string(body.size()) + "\n" + body;
    }
    return text;
}

std::string program_cache_entry(const std::string& dir, const std::string& key) {
    return (fs::path(dir) / (key + ".clbin")).string();
}

bool read_program_cache_entry(const std::string& dir, const std::string& key, std::vector<unsigned char>& binary,
                              bool& rejected, std::string& why) {
    rejected = false;
    const std::string path = program_cache_entry(dir, key);
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::ostringstream s;
    s << in.rdbuf();
    const std::string f = s.str();
    rejected = true;
    if (f.size() < kHeader || std::memcmp(f.data(), kMagic, sizeof kMagic) != 0) {
        why = "not a shadelab program-cache entry (or truncated header)";
        return false;
    }
    if (get_le(f, 4, 4) != kFormat) {
        why = "format version " + std::to_string(get_le(f, 4, 4)) + ", expected " + std::to_string(kFormat);
        return false;
    }
    if (hex(f.substr(8, kDigest)) != key) {
        why = "the entry holds another key (stale or renamed)";
        return false;
    }
    const std::uint64_t size = get_le(f, 8 + kDigest, 8);
    if (size == 0 || size != f.size() - kHeader) {
        why = "binary size " + std::to_string(size) + " does not match the file (" + std::to_string(f.size() - kHeader) +
              " bytes after the header): truncated or corrupt";
        return false;
    }
    if (sha256_raw(f.data() + kHeader, std::size_t(size)) != f.substr(16 + kDigest, kDigest)) {
        why = "the binary's SHA-256 does not match: corrupt";
        return false;
    }
    binary.assign(f.begin() + std::ptrdiff_t(kHeader), f.end());
    rejected = false;
    return true;
}

bool write_program_cache_entry(const std::string& dir, const std::string& key, const std::vector<unsigned char>& binary) {
    if (binary.empty() || key.size() != 2 * kDigest) return false;
    std::string f(kMagic, sizeof kMagic);
    put_u32(f, kFormat);
    for (std::size_t i = 0; i < kDigest; ++i) f += char(std::stoi(key.substr(2 * i, 2), nullptr, 16));
    put_u64(f, binary.size());
    f += sha256_raw(binary.data(), binary.size());
    f.append(reinterpret_cast<const char*>(binary.data()), binary.size());
    try {
        write_text_atomically(program_cache_entry(dir, key), "program cache entry", f);
    } catch (const Error&) {
        return false;   // read-only or full: run without the cache
    }
    return true;
}

}  // namespace shadelab
