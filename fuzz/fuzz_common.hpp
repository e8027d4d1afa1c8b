// Shared by the libFuzzer targets: the input goes to a file (the loaders read paths, as the CLI does),
// one per process, so parallel fuzzing jobs (-jobs=N) do not share it.
#pragma once
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "core/error.hpp"

namespace shadelab::fuzz {

// '<TMPDIR>/shadelab-fuzz-<pid>/<name>' (the folder is made on first use).
inline std::string scratch_path(const std::string& name) {
    static const std::string dir = [] {
        const char* t = std::getenv("TMPDIR");
        const std::string d = std::string(t && *t ? t : "/tmp") + "/shadelab-fuzz-" + std::to_string(::getpid());
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir + "/" + name;
}

inline void write_file(const std::string& path, const std::uint8_t* data, std::size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

// Writes the input to the scratch file `name`, then returns load(path), or nothing when the loader refuses
// it with shadelab::Error (the promised outcome for bad input; anything else is a finding).
template <class Load>
auto load_input(const std::uint8_t* data, std::size_t size, const std::string& name, Load load)
    -> std::optional<decltype(load(std::string()))> {
    const std::string path = scratch_path(name);
    write_file(path, data, size);
    try {
        return load(path);
    } catch (const shadelab::Error&) {
        return std::nullopt;
    }
}

}  // namespace shadelab::fuzz
