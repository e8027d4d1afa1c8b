// The structs the kernels and the host share (kernels/consts/*.h), checked on the device: the host's layout is
// fixed at compile time by the static_asserts in those headers (SL_SIZE_IS, SL_FIELD_AT); here every header is
// built once by the device's compiler with SL_LAYOUT_PROBE, which turns each of those checks into a kernel that
// writes the device's sizeof or offsetof next to the expected number. A device that laid a struct out otherwise
// than the host would read every constant after the difference from the wrong place.
#include <catch2/catch.hpp>

#include <array>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "support.hpp"

using namespace shadelab;
using namespace shadelab::test;
namespace fs = std::filesystem;

namespace {

// The probe kernels of one header, each run once: name -> (device value, expected value).
std::vector<std::pair<std::string, std::array<cl_uint, 2>>> probe_header(const std::string& header) {
    Runtime& rt = runtime();
    const std::string source = "#include \"consts/" + header + "\"\n";
    cl::Program prog(rt.context(), source);
    const std::string options = "-cl-std=CL1.2 -DSL_LAYOUT_PROBE=1 -I " + rt.kernel_dir();
    try {
        prog.build({rt.device()}, options.c_str());
    } catch (const cl::Error&) {
        FAIL("consts/" << header << " does not build as OpenCL C:\n" << prog.getBuildInfo<CL_PROGRAM_BUILD_LOG>(rt.device()));
    }
    std::vector<cl::Kernel> kernels;
    prog.createKernels(&kernels);
    std::vector<std::pair<std::string, std::array<cl_uint, 2>>> out;
    cl::Buffer buf(rt.context(), CL_MEM_WRITE_ONLY, 2 * sizeof(cl_uint));
    for (cl::Kernel& k : kernels) {
        k.setArg(0, buf);
        rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1), cl::NDRange(1));
        std::array<cl_uint, 2> v{};
        rt.queue().enqueueReadBuffer(buf, CL_TRUE, 0, sizeof v, v.data());
        out.emplace_back(k.getInfo<CL_KERNEL_FUNCTION_NAME>(), v);
    }
    return out;
}

}  // namespace

TEST_CASE("every shared struct has the host's layout on the device", "[layout]") {
    std::set<std::string> probed;
    std::size_t headers = 0;
    for (const auto& entry : fs::directory_iterator(fs::path(runtime().kernel_dir()) / "consts")) {
        if (entry.path().extension() != ".h") continue;
        ++headers;
        const std::string header = entry.path().filename().string();
        for (const auto& [name, v] : probe_header(header)) {
            INFO(header << ": " << name << " device " << v[0] << " bytes, host " << v[1]);
            CHECK(v[0] == v[1]);
            probed.insert(name);
        }
    }
    CHECK(headers >= 10);
    // The structs every kernel reads, and one field of a family's struct: the probes exist (a header that lost
    // its checks would pass the loop above with nothing to compare).
    for (const char* name : {"sl_probe_size_ModelConsts", "sl_probe_field_ModelConsts_block", "sl_probe_size_DeviceLight",
                             "sl_probe_field_DeviceLight_range", "sl_probe_size_DeviceView",
                             "sl_probe_field_DeviceView_perspective", "sl_probe_field_OrenNayarConsts_B",
                             "sl_probe_field_HapkeConsts_inv_hc"}) {
        INFO(name);
        CHECK(probed.count(name) == 1);
    }
}
