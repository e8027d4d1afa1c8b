#include "color/color_kernel.hpp"

#include "core/error.hpp"

namespace shadelab {

namespace {
std::vector<float> run(Runtime& rt, const char* kernel, const std::vector<float>& a, const std::vector<float>& b) {
    if (a.size() != b.size() || a.size() % 3 != 0) throw Error("colour comparison needs two arrays of 3n floats");
    const std::size_t n = a.size() / 3;
    std::vector<float> out(n);
    if (n == 0) return out;
    try {
        cl::Program prog = rt.build("color.cl", {});
        cl::Kernel k(prog, kernel);
        auto& ctx = rt.context();
        cl::Buffer ba(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, a.size() * sizeof(float), const_cast<float*>(a.data()));
        cl::Buffer bb(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, b.size() * sizeof(float), const_cast<float*>(b.data()));
        cl::Buffer bo(ctx, CL_MEM_WRITE_ONLY, n * sizeof(float));
        k.setArg(0, ba);
        k.setArg(1, bb);
        k.setArg(2, bo);
        k.setArg(3, cl_uint(n));
        const std::size_t local = 64;
        rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange((n + local - 1) / local * local), cl::NDRange(local));
        rt.queue().enqueueReadBuffer(bo, CL_TRUE, 0, n * sizeof(float), out.data());
    } catch (const cl::Error& e) {
        rethrow_cl(e, std::string("running ") + kernel + " on " + std::to_string(n) + " pixels");
    }
    return out;
}
}  // namespace

std::vector<float> delta_e2000_device(Runtime& rt, const std::vector<float>& a, const std::vector<float>& b) {
    return run(rt, "delta_e2000_rgb", a, b);
}

std::vector<float> delta_e2000_lab_device(Runtime& rt, const std::vector<float>& a, const std::vector<float>& b) {
    return run(rt, "delta_e2000_lab", a, b);
}

}  // namespace shadelab
