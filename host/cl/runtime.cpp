#include "cl/runtime.hpp"
#include "cl/prebuild.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <map>
#include <mutex>
#include <regex>
#include <sstream>
#include <thread>

#include "cl/program_cache.hpp"
#include "core/assets.hpp"
#include "core/error.hpp"

namespace fs = std::filesystem;

namespace shadelab {

std::string cl_error_name(int code) {
    switch (code) {
#define SL_CASE(x) case x: return #x;
        SL_CASE(CL_SUCCESS) SL_CASE(CL_DEVICE_NOT_FOUND) SL_CASE(CL_DEVICE_NOT_AVAILABLE)
        SL_CASE(CL_COMPILER_NOT_AVAILABLE) SL_CASE(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        SL_CASE(CL_OUT_OF_RESOURCES) SL_CASE(CL_OUT_OF_HOST_MEMORY)
        SL_CASE(CL_PROFILING_INFO_NOT_AVAILABLE) SL_CASE(CL_MEM_COPY_OVERLAP) SL_CASE(CL_IMAGE_FORMAT_MISMATCH)
        SL_CASE(CL_IMAGE_FORMAT_NOT_SUPPORTED) SL_CASE(CL_BUILD_PROGRAM_FAILURE) SL_CASE(CL_MAP_FAILURE)
        SL_CASE(CL_MISALIGNED_SUB_BUFFER_OFFSET) SL_CASE(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
        SL_CASE(CL_COMPILE_PROGRAM_FAILURE) SL_CASE(CL_LINKER_NOT_AVAILABLE) SL_CASE(CL_LINK_PROGRAM_FAILURE)
        SL_CASE(CL_DEVICE_PARTITION_FAILED) SL_CASE(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
        SL_CASE(CL_INVALID_VALUE) SL_CASE(CL_INVALID_DEVICE_TYPE) SL_CASE(CL_INVALID_PLATFORM)
        SL_CASE(CL_INVALID_DEVICE) SL_CASE(CL_INVALID_CONTEXT) SL_CASE(CL_INVALID_QUEUE_PROPERTIES)
        SL_CASE(CL_INVALID_COMMAND_QUEUE) SL_CASE(CL_INVALID_HOST_PTR) SL_CASE(CL_INVALID_MEM_OBJECT)
        SL_CASE(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR) SL_CASE(CL_INVALID_IMAGE_SIZE) SL_CASE(CL_INVALID_SAMPLER)
        SL_CASE(CL_INVALID_BINARY) SL_CASE(CL_INVALID_BUILD_OPTIONS) SL_CASE(CL_INVALID_PROGRAM)
        SL_CASE(CL_INVALID_PROGRAM_EXECUTABLE) SL_CASE(CL_INVALID_KERNEL_NAME)
        SL_CASE(CL_INVALID_KERNEL_DEFINITION) SL_CASE(CL_INVALID_KERNEL) SL_CASE(CL_INVALID_ARG_INDEX)
        SL_CASE(CL_INVALID_ARG_VALUE) SL_CASE(CL_INVALID_ARG_SIZE) SL_CASE(CL_INVALID_KERNEL_ARGS)
        SL_CASE(CL_INVALID_WORK_DIMENSION) SL_CASE(CL_INVALID_WORK_GROUP_SIZE)
        SL_CASE(CL_INVALID_WORK_ITEM_SIZE) SL_CASE(CL_INVALID_GLOBAL_OFFSET) SL_CASE(CL_INVALID_EVENT_WAIT_LIST)
        SL_CASE(CL_INVALID_EVENT) SL_CASE(CL_INVALID_OPERATION) SL_CASE(CL_INVALID_GL_OBJECT)
        SL_CASE(CL_INVALID_BUFFER_SIZE) SL_CASE(CL_INVALID_MIP_LEVEL) SL_CASE(CL_INVALID_GLOBAL_WORK_SIZE)
        SL_CASE(CL_INVALID_PROPERTY) SL_CASE(CL_INVALID_IMAGE_DESCRIPTOR)
        SL_CASE(CL_INVALID_COMPILER_OPTIONS) SL_CASE(CL_INVALID_LINKER_OPTIONS)
        SL_CASE(CL_INVALID_DEVICE_PARTITION_COUNT)
#undef SL_CASE
        case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
        default: return "CL_UNKNOWN_ERROR(" + std::to_string(code) + ")";
    }
}

void rethrow_cl(const cl::Error& e, const std::string& what) {
    throw Error(what + ": " + e.what() + " failed with " + cl_error_name(e.err()) + " (" +
                std::to_string(e.err()) + ")");
}

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

std::string env_or(const char* name, const std::string& fallback) {
    const char* v = std::getenv(name);
    return (v && *v) ? std::string(v) : fallback;
}

bool has_kernels(const fs::path& dir) {
    std::error_code ec;
    return !dir.empty() && fs::exists(dir / "shade.cl", ec);
}

}  // namespace

std::string Runtime::find_kernel_dir(const std::string& requested) {
    std::vector<fs::path> tried;
    auto attempt = [&](const fs::path& p) {
        tried.push_back(p);
        return has_kernels(p);
    };
    if (!requested.empty()) {
        if (attempt(requested)) return fs::absolute(requested).string();
        throw Error("kernel folder '" + requested + "' has no shade.cl: point it at shadelab's kernels/ folder");
    }
    if (const char* env = std::getenv("SHADELAB_KERNELS"); env && *env) {
        if (attempt(env)) return fs::absolute(env).string();
        throw Error(std::string("SHADELAB_KERNELS='") + env +
                    "' has no shade.cl: unset it or point it at shadelab's kernels/ folder");
    }
    std::vector<fs::path> places = installed_share_dirs("kernels");
    places.push_back(SHADELAB_KERNEL_INSTALL_DIR);
    places.push_back(SHADELAB_KERNEL_SOURCE_DIR);
    for (const fs::path& p : places) {
        if (attempt(p)) return fs::weakly_canonical(p).string();
    }
    std::string list;
    for (const auto& p : tried) list += (list.empty() ? "" : ", ") + p.string();
    throw Error("cannot find the OpenCL kernels (looked in " + list +
                "): set SHADELAB_KERNELS to shadelab's kernels/ folder");
}

namespace {

// The device index SHADELAB_CL_DEVICE asks for (-1: none).
int env_device_index() {
    const std::string d = env_or("SHADELAB_CL_DEVICE", "");
    if (d.empty()) return -1;
    char* end = nullptr;
    const long v = std::strtol(d.c_str(), &end, 10);
    if (*end != '\0' || v < 0) throw Error("SHADELAB_CL_DEVICE='" + d + "' is not a device index (0, 1, ...)");
    return int(v);
}

// The fragments one shading work-item evaluates, side by side in SIMD lanes (kernels/shade_fragments.cl,
// SL_VECTOR_WIDTH): `requested` when not 0, else SHADELAB_VECTOR_WIDTH when set (1, 2, 4, 8 or 16), else the
// device's native float vector width (PoCL: 16 on AVX-512 hosts, 8 on AVX2), rounded down to a power of two in
// [1, 16].
std::size_t choose_vector_width(const cl::Device& device, std::size_t requested) {
    const std::string env = env_or("SHADELAB_VECTOR_WIDTH", "");
    if (requested == 0 && !env.empty()) {
        if (env != "1" && env != "2" && env != "4" && env != "8" && env != "16")
            throw Error("SHADELAB_VECTOR_WIDTH='" + env + "' is not a vector width: use 1, 2, 4, 8 or 16 (or unset it)");
        requested = std::size_t(std::stoul(env));
    }
    if (requested > 16 || (requested & (requested - 1)) != 0)
        throw Error("vector width " + std::to_string(requested) + " is not one of 1, 2, 4, 8, 16");
    if (requested != 0) return requested;
    const cl_uint native = device.getInfo<CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT>();
    std::size_t width = 1;
    while (width * 2 <= std::min<cl_uint>(native, 16)) width *= 2;
    return width;
}

// The platform whose name contains `want` (lower case), else PoCL, else the first one when nothing was asked.
cl::Platform choose_platform(const std::vector<cl::Platform>& platforms, const std::string& want) {
    std::vector<std::string> names;
    for (const auto& p : platforms) {
        const std::string name = p.getInfo<CL_PLATFORM_NAME>();
        names.push_back(name);
        const std::string lname = lower(name);
        if (!want.empty() ? lname.find(want) != std::string::npos
                          : lname.find("portable computing language") != std::string::npos)
            return p;
    }
    if (want.empty()) return platforms.front();   // no PoCL: take what there is
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "'" : ", '") + n + "'";
    throw Error("no OpenCL platform matches '" + want + "' (platforms: " + list + "): change SHADELAB_CL_PLATFORM");
}

// Device `want` of the platform (-1: its first CPU device, else its first device).
cl::Device choose_device(const cl::Platform& platform, int want) {
    std::vector<cl::Device> devices;
    try {
        platform.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error& e) {
        if (e.err() != CL_DEVICE_NOT_FOUND) throw;
    }
    if (devices.empty())
        throw Error("OpenCL platform '" + platform.getInfo<CL_PLATFORM_NAME>() +
                    "' has no devices: install pocl-opencl-icd or choose another platform");
    if (want >= int(devices.size()))
        throw Error("SHADELAB_CL_DEVICE=" + std::to_string(want) + " but the platform has " +
                    std::to_string(devices.size()) + " device(s): use 0.." + std::to_string(devices.size() - 1));
    if (want >= 0) return devices[std::size_t(want)];
    for (const auto& d : devices)
        if (d.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_CPU) return d;
    return devices.front();
}

}  // namespace

Runtime::Runtime(const RuntimeOptions& options) {
    kernel_dir_ = find_kernel_dir(options.kernel_dir);
    cache_dir_ = shadelab::program_cache_dir(options.program_cache);

    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error& e) {
        if (e.err() != -1001) rethrow_cl(e, "listing OpenCL platforms");
    }
    if (platforms.empty())
        throw Error("no OpenCL platform found: install PoCL (apt-get install pocl-opencl-icd ocl-icd-libopencl1, "
                    "or run scripts/install-deps.sh as root)");
    const std::string want_platform = lower(
        options.platform_substring.empty() ? env_or("SHADELAB_CL_PLATFORM", "") : options.platform_substring);
    const int want_device = options.device_index >= 0 ? options.device_index : env_device_index();
    try {
        platform_ = choose_platform(platforms, want_platform);
        device_ = choose_device(platform_, want_device);
        context_ = cl::Context(device_);
        queue_ = cl::CommandQueue(context_, device_, CL_QUEUE_PROFILING_ENABLE);
        vector_width_ = choose_vector_width(device_, options.vector_width);
        device_identity_ = platform_.getInfo<CL_PLATFORM_NAME>() + "\n" + platform_.getInfo<CL_PLATFORM_VERSION>() +
                           "\n" + device_.getInfo<CL_DEVICE_NAME>() + "\n" + device_.getInfo<CL_DEVICE_VERSION>() +
                           "\n" + device_.getInfo<CL_DRIVER_VERSION>();
    } catch (const cl::Error& e) {
        rethrow_cl(e, "setting up the OpenCL device");
    }
}

Runtime::~Runtime() {
    try {
        for (Stored& s : stored_) {
            const std::vector<unsigned char> binary = binary_of(s.program);
            if (!binary.empty() && binary.size() != s.bytes) write_program_cache_entry(cache_dir_, s.key, binary);
        }
    } catch (...) {
        // The cache is an optimisation: a failure here costs the next run a build, nothing else.
    }
}

std::string Runtime::device_description() const {
    return device_.getInfo<CL_DEVICE_NAME>() + " (" + platform_.getInfo<CL_PLATFORM_NAME>() + ", " +
           device_.getInfo<CL_DEVICE_OPENCL_C_VERSION>() + ")";
}

cl::Program Runtime::build_from_source(const std::string& path, const std::string& options) {
    std::ifstream in(path);
    if (!in) throw Error("cannot read kernel source '" + path + "': is the kernels/ folder complete?");
    std::stringstream text;
    text << in.rdbuf();

    cl::Program program;
    try {
        program = cl::Program(context_, text.str());
    } catch (const cl::Error& e) {
        rethrow_cl(e, "creating program from '" + path + "'");
    }
    try {
        program.build({device_}, options.c_str());
    } catch (const cl::Error& e) {
        std::string log;
        try {
            log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_);
        } catch (const cl::Error&) {
            log = "(no build log)";
        }
        // PoCL compiles a temporary copy of the source; name the real file so "file:line" can be followed.
        log = std::regex_replace(log, std::regex(R"([^\s:'"]*tempfile_[A-Za-z0-9]+\.cl)"), path);
        throw Error("OpenCL build of '" + path + "' failed (" + cl_error_name(e.err()) + ") on " +
                    device_description() + " with options '" + options + "':\n" + log);
    }
    return program;
}

// A program from a cached device binary; throws cl::Error when the driver refuses it.
cl::Program Runtime::build_from_binary(const std::vector<unsigned char>& binary, const std::string& options) {
    cl::Program::Binaries bins{binary};
    std::vector<cl_int> status;
    cl::Program program(context_, {device_}, bins, &status);
    if (!status.empty() && status[0] != CL_SUCCESS) throw cl::Error(status[0], "clCreateProgramWithBinary");
    program.build({device_}, options.c_str());
    return program;
}

std::vector<unsigned char> Runtime::binary_of(const cl::Program& program) {
    try {
        const std::vector<std::vector<unsigned char>> bins = program.getInfo<CL_PROGRAM_BINARIES>();
        return bins.size() == 1 ? bins[0] : std::vector<unsigned char>();
    } catch (const cl::Error&) {
        return {};   // the driver gives no binary: nothing to cache
    }
}

namespace {

std::string build_options(const std::string& kernel_dir, const std::vector<std::string>& defines,
                          const std::string& extra_options) {
    std::string options = "-cl-std=CL1.2 -I " + kernel_dir;
    for (const auto& d : defines) options += " -D" + d;
    if (!extra_options.empty()) options += " " + extra_options;
    return options;
}

// Programs being built right now, per runtime and key: a thread that asks for one of them waits for its build
// instead of building it a second time. (Here rather than in Runtime so that runtime.hpp, which most of the tree
// includes, stays as it is.)
std::mutex building_mutex;
std::map<std::pair<const void*, std::string>, std::shared_future<cl::Program>> building;

// What one build needs of its runtime, lent by Runtime::build (runs without the runtime's lock).
struct BuildContext {
    const std::string& kernel_dir;
    const std::string& cache_dir;        // "": no program-binary cache
    const std::string& kernel_tree;
    const std::string& device_identity;
    std::function<cl::Program(const std::string& path, const std::string& options)> from_source;
    std::function<cl::Program(const std::vector<unsigned char>& binary, const std::string& options)> from_binary;
    std::function<std::vector<unsigned char>(const cl::Program&)> binary_of;
};

struct Built {
    cl::Program program;
    std::string disk_key;
    std::size_t bytes = 0;    // binary size in the cache entry (0: none written)
    bool from_disk = false, rejected = false;
};

// The program from the program-binary cache when it holds an entry the device accepts, else from source (and
// stored in the cache).
Built load_or_build(const BuildContext& c, const std::string& main_file, const std::string& options) {
    Built b;
    if (!c.cache_dir.empty()) {
        b.disk_key = program_cache_key(c.kernel_tree, main_file, options, c.device_identity);
        std::vector<unsigned char> binary;
        std::string why;
        if (read_program_cache_entry(c.cache_dir, b.disk_key, binary, b.rejected, why)) {
            try {
                b.program = c.from_binary(binary, options);
                b.from_disk = true;
                b.bytes = binary.size();
                return b;
            } catch (const cl::Error&) {
                b.rejected = true;   // the driver refuses it (another PoCL build, a damaged binary): rebuild
            }
        }
    }
    b.program = c.from_source((fs::path(c.kernel_dir) / main_file).string(), options);
    if (!c.cache_dir.empty()) {
        const std::vector<unsigned char> binary = c.binary_of(b.program);
        b.bytes = write_program_cache_entry(c.cache_dir, b.disk_key, binary) ? binary.size() : 0;
    }
    return b;
}

}  // namespace

cl::Program Runtime::build(const std::string& main_file, const std::vector<std::string>& defines,
                           const std::string& extra_options) {
    std::vector<std::string> all = defines;
    all.push_back("SL_VECTOR_WIDTH=" + std::to_string(vector_width_));
    const std::string options = build_options(kernel_dir_, all, extra_options);
    const std::string key = main_file + "|" + options;
    const auto slot = std::make_pair(static_cast<const void*>(this), key);
    std::promise<cl::Program> promise;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (auto it = cache_.find(key); it != cache_.end()) return it->second;
        if (!cache_dir_.empty() && kernel_tree_.empty()) kernel_tree_ = kernel_tree_text(kernel_dir_);
    }
    {
        std::unique_lock<std::mutex> lock(building_mutex);
        if (auto it = building.find(slot); it != building.end()) {
            std::shared_future<cl::Program> pending = it->second;
            lock.unlock();
            return pending.get();   // another thread builds it (its failure is rethrown here)
        }
        std::lock_guard<std::mutex> cached(mutex_);   // finished between the two looks?
        if (auto it = cache_.find(key); it != cache_.end()) return it->second;
        building.emplace(slot, promise.get_future().share());
    }
    auto done = [&] {
        std::lock_guard<std::mutex> lock(building_mutex);
        building.erase(slot);
    };
    const auto t0 = std::chrono::steady_clock::now();
    try {
        const BuildContext c{kernel_dir_, cache_dir_, kernel_tree_, device_identity_,
                             [this](const std::string& path, const std::string& o) { return build_from_source(path, o); },
                             [this](const std::vector<unsigned char>& bin, const std::string& o) { return build_from_binary(bin, o); },
                             [this](const cl::Program& p) { return binary_of(p); }};
        const Built b = load_or_build(c, main_file, options);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!cache_dir_.empty()) stored_.push_back({b.disk_key, b.program, b.bytes});
            ++builds_;
            cache_hits_ += b.from_disk ? 1 : 0;
            cache_rejected_ += b.rejected ? 1 : 0;
            build_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            cache_.emplace(key, b.program);
        }
        done();
        promise.set_value(b.program);
        return b.program;
    } catch (...) {
        done();
        promise.set_exception(std::current_exception());
        throw;
    }
}

void prebuild(Runtime& runtime, const std::vector<ProgramRequest>& requests, unsigned threads) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    threads = unsigned(std::min<std::size_t>(threads, requests.size()));
    std::atomic<std::size_t> next{0};
    std::mutex failure_mutex;
    std::exception_ptr failure;
    auto work = [&] {
        for (std::size_t i = next++; i < requests.size(); i = next++) {
            try {
                runtime.build(requests[i].main_file, requests[i].defines, requests[i].extra_options);
            } catch (...) {
                std::lock_guard<std::mutex> lock(failure_mutex);
                if (!failure) failure = std::current_exception();
            }
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace shadelab
