// kernels/common.cl's own trigonometry (sl_sin, sl_cos, sl_tan, sl_asin, sl_acos, sl_atan, sl_atan2), which
// both precision modes map the built-in names to: ulps against double over millions of arguments per function,
// dense grids plus the edges where such functions break (arguments near multiples of pi/2 and poles of tan,
// |x| -> 1 for asin/acos, tiny and huge ratios and every sign for atan2, denormals, zeros). PoCL's own built-ins
// (SL_BUILTIN_TRIG) are measured on the same inputs and printed beside them, not asserted.
//
// kBounds holds the asserted bounds, each next to the value measured when it was set (about 2x under it);
// docs/precision.md ("Own trigonometry") quotes them. Besides the ulp bound: every output for a finite argument
// in the domain is finite and inside the function's range.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "shade/shader.hpp"
#include "sweep.hpp"

using namespace shadelab;

namespace {

Runtime& runtime() {
    static Runtime rt;
    return rt;
}

// The built-in names, as a model file writes them: common.cl maps them to its own functions unless
// SL_BUILTIN_TRIG is defined.
const char* const kProbe = R"CL(
#include "common.cl"
__kernel void trig_probe(__global const float* x, __global const float* y, __global float* out, const uint n,
                         const uint f) {
    const size_t i = get_global_id(0);
    if (i >= n) return;
    const float a = x[i], b = y[i];
    float r;
    switch (f) {
    case 0: r = sin(a); break;
    case 1: r = cos(a); break;
    case 2: r = tan(a); break;
    case 3: r = asin(a); break;
    case 4: r = acos(a); break;
    case 5: r = atan(a); break;
    default: r = atan2(a, b); break;
    }
    out[i] = r;
}
)CL";

enum Fn { kSin, kCos, kTan, kAsin, kAcos, kAtan, kAtan2 };
const char* const kFnNames[] = {"sin", "cos", "tan", "asin", "acos", "atan", "atan2"};

struct Sweep {
    Fn fn;
    const char* domain;
    double measured;   // own function, precise mode, max ulp when the bound was set (fast mode is the same code)
    double bound;      // asserted, ulps: about 2x measured, never above OpenCL 1.2's limit for the built-in
                       // (sin, cos 4; tan 5; asin, acos 4; atan 5; atan2 6)
};

// clang-format off
const Sweep kSweeps[] = {
    {kSin,   "x in [-pi, pi], 4M uniform, and every 2^-k, k = 0..149",                 1.41, 3},
    {kSin,   "|x| in [pi, 1e6], 2M log-uniform, and the floats nearest k pi, k < 3e5", 1.67, 3.5},
    {kCos,   "x in [-pi, pi], 4M uniform, and every 2^-k, k = 0..149",                 1.54, 3},
    {kCos,   "|x| in [pi, 1e6], 2M log-uniform, and the floats nearest (k+1/2) pi",    1.67, 3.5},
    {kTan,   "x in [-pi/2, pi/2], 4M uniform, and every 2^-k",                          2.40, 5},
    {kTan,   "|x| in [pi/2, 1e4], 1M, and 64 floats around each pole (k+1/2) pi",      2.58, 5},
    {kAsin,  "x in [-1, 1], 4M uniform, every 2^-k, and 1 - j 2^-24, j < 2^16",         1.94, 4},
    {kAcos,  "x in [-1, 1], 4M uniform, every 2^-k, and +-(1 - j 2^-24), j < 2^16",     1.27, 3},
    {kAtan,  "x in [-1e4, 1e4], 2M log-uniform both signs, and every +-2^k",            2.75, 5},
    {kAtan2, "(y, x): 2M directions, 1M log-uniform ratios, every sign, axes and zeros", 2.81, 5.5},
};
// clang-format on

void push(std::vector<float>& x, std::vector<float>& y, double a, double b = 1.0) {
    x.push_back(float(a));
    y.push_back(float(b));
}

// The arguments of sweep s.
void inputs(std::size_t s, std::vector<float>& x, std::vector<float>& y) {
    std::mt19937_64 g(31 + s);
    auto uni = [&](double lo, double hi) { return lo + (hi - lo) * test::unit_double(g); };
    auto logu = [&](double lo, double hi) { return std::exp(uni(std::log(lo), std::log(hi))); };
    auto sign = [&]() { return (g() & 1) ? 1.0 : -1.0; };
    const double pi = M_PI;
    switch (s) {
    case 0: case 2:
        for (int i = 0; i < 4000000; ++i) push(x, y, uni(-pi, pi));
        for (int k = 0; k <= 149; ++k) { push(x, y, std::ldexp(1.0, -k)); push(x, y, -std::ldexp(1.0, -k)); }
        push(x, y, 0.0);
        break;
    case 1: case 3:
        for (int i = 0; i < 2000000; ++i) push(x, y, sign() * logu(pi, 1e6));
        for (int k = 1; k < 300000; k += 1) {   // the floats on both sides of k pi (sin) or (k + 1/2) pi (cos)
            const double c = (s == 1 ? double(k) : k + 0.5) * pi;
            const float f = float(c);
            push(x, y, f);
            push(x, y, std::nextafter(f, 0.0f));
            push(x, y, std::nextafter(f, 2e6f));
        }
        break;
    case 4:
        for (int i = 0; i < 4000000; ++i) push(x, y, uni(-pi / 2, pi / 2));
        for (int k = 0; k <= 149; ++k) { push(x, y, std::ldexp(1.0, -k)); push(x, y, -std::ldexp(1.0, -k)); }
        break;
    case 5:
        for (int i = 0; i < 1000000; ++i) push(x, y, sign() * logu(pi / 2, 1e4));
        for (int k = 0; k < 6000; ++k) {
            float f = float((k + 0.5) * pi);
            for (int j = 0; j < 32; ++j) f = std::nextafter(f, 0.0f);
            for (int j = 0; j < 64; ++j) { push(x, y, f); push(x, y, -f); f = std::nextafter(f, 1e5f); }
        }
        break;
    case 6: case 7:
        for (int i = 0; i < 4000000; ++i) push(x, y, uni(-1.0, 1.0));
        for (int k = 0; k <= 149; ++k) { push(x, y, std::ldexp(1.0, -k)); push(x, y, -std::ldexp(1.0, -k)); }
        for (int j = 0; j < 1 << 16; ++j) {
            push(x, y, 1.0 - j * 0x1p-24);
            push(x, y, -(1.0 - j * 0x1p-24));
            push(x, y, 0.5 + (j - 32768) * 0x1p-25);   // around the switch of form at |x| = 1/2
        }
        push(x, y, 0.0);
        break;
    case 8:
        for (int i = 0; i < 2000000; ++i) push(x, y, sign() * logu(1e-6, 1e4));
        for (int k = -126; k <= 127; ++k) { push(x, y, std::ldexp(1.0, k)); push(x, y, -std::ldexp(1.0, k)); }
        for (int j = -4096; j <= 4096; ++j) push(x, y, 0.41421356 + j * 1e-9);   // the reduction's switch
        push(x, y, 0.0);
        break;
    default:
        for (int i = 0; i < 2000000; ++i) {   // directions of every quadrant, at scales 1e-30 .. 1e30
            const double phi = uni(-pi, pi), r = logu(1e-30, 1e30);
            push(x, y, r * std::sin(phi), r * std::cos(phi));
        }
        for (int i = 0; i < 1000000; ++i) {   // ratios y/x from 1e-8 to 1e8, every sign
            const double t = logu(1e-8, 1e8), xx = sign() * logu(1e-3, 1e3);
            push(x, y, sign() * t * std::abs(xx), xx);
        }
        for (double a : {0.0, 1.0, -1.0, 1e-38, -1e-38, 1e-45, 3e38, -3e38})
            for (double b : {0.0, 1.0, -1.0, 1e-38, -1e-38, 1e-45, 3e38, -3e38}) push(x, y, a, b);
        for (int j = -4096; j <= 4096; ++j) push(x, y, 0.41421356 + j * 1e-9, 1.0);
        break;
    }
}

double exact(Fn f, double a, double b) {
    switch (f) {
    case kSin: return std::sin(a);
    case kCos: return std::cos(a);
    case kTan: return std::tan(a);
    case kAsin: return std::asin(a);
    case kAcos: return std::acos(a);
    case kAtan: return std::atan(a);
    default: return std::atan2(a, b);
    }
}

// The function's range (closed), where every output must lie.
bool in_range(Fn f, double v) {
    switch (f) {
    case kSin: case kCos: return v >= -1.0 && v <= 1.0;
    case kTan: return std::isfinite(v);
    case kAsin: case kAtan: return std::abs(v) <= double(float(M_PI / 2));
    case kAcos: return v >= 0.0 && v <= double(float(M_PI));
    default: return std::abs(v) <= double(float(M_PI));
    }
}

double float_ulp(double d) {
    const double a = std::abs(d);
    if (a < 1.1754943508222875e-38) return std::ldexp(1.0, -149);
    return std::ldexp(1.0, std::ilogb(a) - 23);
}

std::vector<float> run(cl::Program& prog, const std::vector<float>& x, const std::vector<float>& y, Fn f) {
    const std::size_t n = x.size();
    auto& ctx = runtime().context();
    cl::Buffer bx(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(float), const_cast<float*>(x.data()));
    cl::Buffer by(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(float), const_cast<float*>(y.data()));
    cl::Buffer bout(ctx, CL_MEM_WRITE_ONLY, n * sizeof(float));
    cl::Kernel k(prog, "trig_probe");
    k.setArg(0, bx); k.setArg(1, by); k.setArg(2, bout); k.setArg(3, cl_uint(n)); k.setArg(4, cl_uint(f));
    const std::size_t local = Shader::kLocalSize;
    runtime().queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange((n + local - 1) / local * local),
                                           cl::NDRange(local));
    std::vector<float> out(n);
    runtime().queue().enqueueReadBuffer(bout, CL_TRUE, 0, n * sizeof(float), out.data());
    return out;
}

cl::Program build(const std::vector<std::string>& defines, const std::string& extra) {
    std::string o = "-cl-std=CL1.2 -I " + runtime().kernel_dir();
    for (const auto& d : defines) o += " -D" + d;
    if (!extra.empty()) o += " " + extra;
    cl::Program p(runtime().context(), kProbe);
    try {
        p.build({runtime().device()}, o.c_str());
    } catch (const cl::Error&) {
        FAIL("OpenCL build failed with '" << o << "':\n" << p.getBuildInfo<CL_PROGRAM_BUILD_LOG>(runtime().device()));
    }
    return p;
}

}  // namespace

TEST_CASE("own trigonometry - ulps against double over dense sweeps and the edges, both modes", "[precision][mathfn]") {
    cl::Program progs[3] = {build({}, Shader::options_for(Precision::Precise)),
                            build({"SL_FAST=1"}, Shader::options_for(Precision::Fast)),
                            build({"SL_BUILTIN_TRIG=1"}, Shader::options_for(Precision::Precise))};
    const char* labels[3] = {"own precise", "own fast", "PoCL built-in"};
    std::cout << "own trigonometry on " << runtime().device_description() << "\n"
              << std::left << std::setw(7) << "fn" << std::setw(78) << "sweep" << std::right << std::setw(10)
              << "values" << std::setw(13) << "own ulp" << std::setw(13) << "fast ulp" << std::setw(13) << "PoCL ulp"
              << std::setw(8) << "bound" << "\n";
    for (std::size_t s = 0; s < sizeof(kSweeps) / sizeof(kSweeps[0]); ++s) {
        const Sweep& sw = kSweeps[s];
        std::vector<float> x, y;
        inputs(s, x, y);
        std::vector<double> ref(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) ref[i] = exact(sw.fn, x[i], y[i]);
        double ulp[3] = {0, 0, 0};
        std::size_t worst[3] = {0, 0, 0}, bad[3] = {0, 0, 0}, first_bad[3] = {0, 0, 0};
        for (int m = 0; m < 3; ++m) {
            const auto out = run(progs[m], x, y, sw.fn);
            for (std::size_t i = 0; i < x.size(); ++i) {
                const double v = out[i];
                if (!in_range(sw.fn, v)) {
                    if (bad[m]++ == 0) first_bad[m] = i;
                    continue;
                }
                const double u = std::abs(v - ref[i]) / float_ulp(ref[i]);
                if (u > ulp[m]) { ulp[m] = u; worst[m] = i; }
            }
        }
        std::cout << std::left << std::setw(7) << kFnNames[sw.fn] << std::setw(78) << sw.domain << std::right
                  << std::setw(10) << x.size() << std::setprecision(3) << std::setw(13) << ulp[0] << std::setw(13)
                  << ulp[1] << std::setw(13) << ulp[2] << std::setw(8) << sw.bound << "\n";
        for (int m = 0; m < 2; ++m) {
            INFO(kFnNames[sw.fn] << " (" << labels[m] << ") over " << sw.domain << ": worst at x = "
                                 << std::setprecision(9) << x[worst[m]] << ", y = " << y[worst[m]] << " ("
                                 << ulp[m] << " ulp); " << bad[m] << " outputs out of range"
                                 << (bad[m] ? ", the first at x = " + std::to_string(x[first_bad[m]]) + ", y = " +
                                                  std::to_string(y[first_bad[m]])
                                            : std::string()));
            CHECK(bad[m] == 0);
            CHECK(ulp[m] <= sw.bound);
        }
    }
}
