#include "cl/program_cache.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/atomic_file.hpp"
#include "core/bytes.hpp"
#include "core/cache_file.hpp"
#include "core/error.hpp"

namespace fs = std::filesystem;

namespace shadelab {

namespace {

constexpr char kMagic[4] = {'S', 'L', 'P', 'C'};
constexpr std::uint32_t kFormat = 1;
using cache_file::kDigest;
using cache_file::kHeader;

using bytes::hex;
using bytes::put_u64;

}  // namespace

std::string program_cache_dir(const std::string& setting) {
    return cache_file::folder(setting, "SHADELAB_PROGRAM_CACHE", "programs");
}

std::string sha256_hex(const std::string& bytes) { return hex(cache_file::sha256_raw(bytes.data(), bytes.size())); }

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
    why = cache_file::header_problem(f, kMagic, kFormat, key, "program-cache", "binary");
    if (why.empty() && f.size() == kHeader) why = "binary size 0: truncated or corrupt";
    if (!why.empty()) return false;
    binary.assign(f.begin() + std::ptrdiff_t(kHeader), f.end());
    rejected = false;
    return true;
}

bool write_program_cache_entry(const std::string& dir, const std::string& key, const std::vector<unsigned char>& binary) {
    if (binary.empty() || key.size() != 2 * kDigest) return false;
    std::string f = cache_file::header(kMagic, kFormat, key, binary.size(), cache_file::sha256_raw(binary.data(), binary.size()));
    f.append(reinterpret_cast<const char*>(binary.data()), binary.size());
    try {
        write_text_atomically(program_cache_entry(dir, key), "program cache entry", f);
    } catch (const Error&) {
        return false;   // read-only or full: run without the cache
    }
    return true;
}

}  // namespace shadelab
