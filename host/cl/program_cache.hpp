// A shadelab program-binary cache: the device binary of every OpenCL program built, on disk, so that the next
// process loads it (clCreateProgramWithBinary) instead of compiling the source again.
//
// Key: SHA-256 (FIPS 180-4) of everything the binary depends on: a format version, the main file's name, the
// build options, the text of every file under the kernel folder (so an edited include is a different key),
// and the device (platform name and version - the PoCL version -, device name and version, driver version).
// One file per key, '<hex key>.clbin', holding: magic "SLPC", format version, the key, the binary's size and
// its SHA-256, then the binary. An entry is used only if all of these check out and the device accepts the
// binary; anything else (stale, truncated, corrupt, another key under the file's name, a binary the driver
// refuses) is counted as rejected and rebuilt from source, and the entry is overwritten.
//
// Where: SHADELAB_PROGRAM_CACHE (a folder; "off" or "0" disables the cache), else $XDG_CACHE_HOME/shadelab/
// programs, else $HOME/.cache/shadelab/programs; RuntimeOptions::program_cache overrides the variable.
// Writes are atomic (core/atomic_file.hpp); a cache that cannot be written is skipped, never an error.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace shadelab {

// The folder `setting` names ("" = the environment, then the XDG default; "off"/"0" = none: returns "").
std::string program_cache_dir(const std::string& setting);

// SHA-256 of `bytes`, as 64 lowercase hex digits.
std::string sha256_hex(const std::string& bytes);

// The key material's digest for one program (see the header comment).
std::string program_cache_key(const std::string& kernel_tree_text, const std::string& main_file,
                              const std::string& options, const std::string& device_identity);

// Every file under `kernel_dir` (sorted by relative path), as "path\nsize\ncontent" records: what a
// program's binary may depend on through #include.
std::string kernel_tree_text(const std::string& kernel_dir);

// Entry file of `key` in `dir`.
std::string program_cache_entry(const std::string& dir, const std::string& key);

// Reads the entry for `key`: true with the binary when it exists and checks out; false when missing
// (`rejected` false) or unusable (`rejected` true, with the reason in `why`).
bool read_program_cache_entry(const std::string& dir, const std::string& key, std::vector<unsigned char>& binary,
                              bool& rejected, std::string& why);

// Writes the entry for `key` atomically; returns false (and leaves no file) when it cannot.
bool write_program_cache_entry(const std::string& dir, const std::string& key, const std::vector<unsigned char>& binary);

}  // namespace shadelab
