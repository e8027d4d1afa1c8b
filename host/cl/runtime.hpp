// OpenCL runtime layer: device choice, program building from kernels/*.cl, error names.
//
// Device choice: the first CPU device of a platform whose name contains "Portable Computing Language"
// (PoCL), unless SHADELAB_CL_PLATFORM (substring of the platform name, case-insensitive) and/or
// SHADELAB_CL_DEVICE (index within that platform) say otherwise, or RuntimeOptions does.
// Kernel sources are found in SHADELAB_KERNELS (env), else next to the executable
// (../share/shadelab/kernels), else the install prefix, else the source tree this build came from.
#pragma once
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "cl/cl.hpp"

namespace shadelab {

// "CL_OUT_OF_RESOURCES" for -5, "CL_UNKNOWN_ERROR(-1234)" for codes it does not know.
std::string cl_error_name(int code);

// Wraps an OpenCL call site: turns cl::Error into shadelab::Error "what: CL_NAME (code)".
[[noreturn]] void rethrow_cl(const cl::Error& e, const std::string& what);

struct RuntimeOptions {
    std::string platform_substring;   // empty: env SHADELAB_CL_PLATFORM, else prefer PoCL
    int device_index = -1;            // -1: env SHADELAB_CL_DEVICE, else first CPU device
    std::string kernel_dir;           // empty: search as described above
    std::string program_cache;        // empty: env SHADELAB_PROGRAM_CACHE, else the XDG cache folder;
                                      // "off": no program-binary cache (see cl/program_cache.hpp)
    std::size_t vector_width = 0;     // fragments a shading work-item evaluates (1, 2, 4, 8, 16); 0: env
                                      // SHADELAB_VECTOR_WIDTH, else the device's native float width
};

class Runtime {
public:
    explicit Runtime(const RuntimeOptions& options = {});
    // Stores the programs of this runtime in the program-binary cache again where their binaries have grown
    // since they were stored (PoCL adds the kernels it compiled at their first launch), so the next process
    // skips that compilation too. Never throws.
    ~Runtime();
    Runtime(const Runtime&) = delete;
    Runtime& operator=(const Runtime&) = delete;

    cl::Context& context() { return context_; }
    cl::CommandQueue& queue() { return queue_; }
    const cl::Device& device() const { return device_; }
    const std::string& kernel_dir() const { return kernel_dir_; }
    std::string device_description() const;   // "device name (platform name, OpenCL C version)"
    // Fragments a shading work-item evaluates side by side (SIMD lanes), passed to every program as
    // SL_VECTOR_WIDTH: the device's native float width (16 on AVX-512, 8 on AVX2), or SHADELAB_VECTOR_WIDTH.
    std::size_t vector_width() const { return vector_width_; }

    // Builds (or returns the cached) program whose main file is `main_file` (relative to kernel_dir),
    // with `-I kernel_dir`, one `-D` per define and SL_VECTOR_WIDTH (vector_width()), then `extra_options`
    // (e.g. -cl-mad-enable). The file is passed unmodified, so build-log line numbers match the files on disk.
    // A build failure throws shadelab::Error with the log, the options and the device.
    cl::Program build(const std::string& main_file, const std::vector<std::string>& defines,
                      const std::string& extra_options = "");

    std::size_t programs_built() const { return builds_; }            // from source or from the cache
    std::size_t programs_from_cache() const { return cache_hits_; }    // loaded from the program-binary cache
    std::size_t cache_entries_rejected() const { return cache_rejected_; }   // stale/corrupt, rebuilt
    double build_seconds() const { return build_seconds_; }            // wall time spent in build()
    const std::string& program_cache_dir() const { return cache_dir_; }   // "" when the cache is off

    static std::string find_kernel_dir(const std::string& requested = {});

private:
    cl::Platform platform_;
    cl::Device device_;
    cl::Context context_;
    cl::CommandQueue queue_;
    std::string kernel_dir_;
    std::mutex mutex_;
    std::map<std::string, cl::Program> cache_;
    std::size_t builds_ = 0, cache_hits_ = 0, cache_rejected_ = 0;
    double build_seconds_ = 0.0;
    std::string cache_dir_;
    std::string kernel_tree_;          // every kernel file's text, read at the first build (cache key)
    std::string device_identity_;
    std::size_t vector_width_ = 1;
    struct Stored {
        std::string key;
        cl::Program program;
        std::size_t bytes;   // binary size in the cache entry (0: none written)
    };
    std::vector<Stored> stored_;

    cl::Program build_from_source(const std::string& path, const std::string& options);
    cl::Program build_from_binary(const std::vector<unsigned char>& binary, const std::string& options);
    std::vector<unsigned char> binary_of(const cl::Program& program);
};

}  // namespace shadelab
