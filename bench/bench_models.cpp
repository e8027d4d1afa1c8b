// Throughput of every model in every precision mode, as ratios measured in one run:
//   against a copy kernel moving the same bytes (the memory limit), against a plain 2-thread C++ loop
//   (-O3 -march=native, std maths; Lambert and Minnaert 1941 only), and against the scalar double reference.
// A benchmark, not a test: it prints figures. --smoke runs tiny sizes so the suite can check it still works.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"

using namespace shadelab;
using clock_type = std::chrono::steady_clock;

namespace {

FragmentBuffer random_fragments(std::size_t n) {
    std::mt19937_64 g(1);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    FragmentBuffer fb;
    fb.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        float x, y, z, l;
        do { x = u(g); y = u(g); z = u(g); l = x * x + y * y + z * z; } while (l > 1.0f || l < 1e-4f);
        l = std::sqrt(l);
        fb.px[i] = x; fb.py[i] = y; fb.pz[i] = z;
        fb.nx[i] = x / l; fb.ny[i] = y / l; fb.nz[i] = z / l;
        fb.pixel[i] = int(i); fb.depth[i] = 1.0f;
    }
    return fb;
}

double copy_kernel_ms(Runtime& rt, const FragmentBuffer& fb, int repeats) {
    const std::size_t n = fb.size(), bytes = n * sizeof(float);
    cl::Program prog = rt.build("bench/copy.cl", {});
    cl::Kernel k(prog, "copy_like_shade");
    auto ro = [&](const std::vector<float>& v) {
        return cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, const_cast<float*>(v.data()));
    };
    cl::Buffer a = ro(fb.px), b = ro(fb.py), c = ro(fb.pz), d = ro(fb.nx), e = ro(fb.ny), f = ro(fb.nz);
    cl::Buffer out(rt.context(), CL_MEM_WRITE_ONLY, 3 * bytes);
    k.setArg(0, a); k.setArg(1, b); k.setArg(2, c); k.setArg(3, d); k.setArg(4, e); k.setArg(5, f);
    k.setArg(6, out); k.setArg(7, cl_uint(n));
    double best = 1e30;
    const std::size_t local = Shader::kLocalSize;
    for (int r = 0; r < repeats; ++r) {
        cl::Event ev;
        rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange((n + local - 1) / local * local), cl::NDRange(local),
                                        nullptr, &ev);
        ev.wait();
        best = std::min(best, double(ev.getProfilingInfo<CL_PROFILING_COMMAND_END>() -
                                     ev.getProfilingInfo<CL_PROFILING_COMMAND_START>()) * 1e-6);
    }
    return best;
}

// What a C++ user would write: the formula in float with the standard library, over 2 threads.
double cpp_loop_ms(const std::string& model, const FragmentBuffer& fb, const glm::vec3& L, const glm::vec3& eye,
                   std::vector<float>& out, int repeats) {
    const std::size_t n = fb.size();
    out.assign(3 * n, 0.0f);
    const float k = 0.7f;
    auto work = [&](std::size_t i0, std::size_t i1) {
        for (std::size_t i = i0; i < i1; ++i) {
            const float NoL = std::max(0.0f, fb.nx[i] * L.x + fb.ny[i] * L.y + fb.nz[i] * L.z);
            float v = NoL;
            if (model == "minnaert_1941") {
                float vx = eye.x - fb.px[i], vy = eye.y - fb.py[i], vz = eye.z - fb.pz[i];
                const float inv = 1.0f / std::sqrt(vx * vx + vy * vy + vz * vz);
                const float NoV = std::max(1e-3f, (fb.nx[i] * vx + fb.ny[i] * vy + fb.nz[i] * vz) * inv);
                v = NoL > 0.0f ? std::pow(NoL, k) * std::pow(NoV, k - 1.0f) : 0.0f;
            }
            out[i] = 0.8f * v; out[n + i] = 0.8f * v; out[2 * n + i] = 0.8f * v;
        }
    };
    double best = 1e30;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = clock_type::now();
        std::thread t(work, n / 2, n);
        work(0, n / 2);
        t.join();
        best = std::min(best, std::chrono::duration<double, std::milli>(clock_type::now() - t0).count());
    }
    return best;
}

std::string cpu_name() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::size_t> sizes = {1u << 20, 1u << 22, 1u << 24};
    int repeats = 3;
    bool smoke = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--smoke")) { smoke = true; sizes = {4096}; repeats = 1; }
        else if (!std::strcmp(argv[i], "--quick")) sizes = {1u << 20};
        else { std::cerr << "usage: bench_models [--smoke | --quick]\n"; return 2; }
    }
    try {
        Runtime rt;
        Shader shader(rt);
        std::cout << "machine: " << std::thread::hardware_concurrency() << " threads, " << cpu_name() << "\n"
                  << "device:  " << rt.device_description() << "\n"
                  << "ratios are measured in this run; kernel times are device times from profiling events, best of "
                  << repeats << "\n";
        const glm::dvec3 Ldir = glm::normalize(glm::dvec3(0.3, 0.8, 0.5)), eye(0.5, 1.0, 4.0);
        bool ok = true;
        for (std::size_t n : sizes) {
            const FragmentBuffer fb = random_fragments(n);
            const double copy_ms = copy_kernel_ms(rt, fb, repeats);
            const double bytes = double(n) * 36.0;
            std::cout << "\n== " << n << " fragments: copy kernel " << std::fixed << std::setprecision(3) << copy_ms
                      << " ms (" << std::setprecision(1) << bytes / copy_ms * 1e-6 << " GB/s, "
                      << double(n) / copy_ms * 1e-3 << " Mfrag/s)\n";
            std::cout << std::left << std::setw(32) << "model" << std::setw(9) << "mode" << std::right << std::setw(11)
                      << "Mfrag/s" << std::setw(11) << "of copy" << std::setw(11) << "x C++" << std::setw(12) << "x ref(1t)"
                      << "\n";
            // The scalar double reference on a subset, single-threaded: fragments per second.
            const std::size_t nref = std::min<std::size_t>(n, smoke ? 4096 : 100000);
            for (const auto& info : model_catalogue()) {
                Material m;
                m.model = info.name;
                for (int c = 0; c < info.children; ++c) m.children.push_back(Material{});
                m = resolve_material(m);
                const auto t0 = clock_type::now();
                double sink = 0.0;
                for (std::size_t i = 0; i < nref; ++i) {
                    const glm::dvec3 P{fb.px[i], fb.py[i], fb.pz[i]}, N{fb.nx[i], fb.ny[i], fb.nz[i]};
                    sink += ref::eval_material(N, Ldir, glm::normalize(eye - P), P, m).y;
                }
                const double ref_fps = double(nref) / std::chrono::duration<double>(clock_type::now() - t0).count();
                if (!std::isfinite(sink)) ok = false;
                for (Precision p : {Precision::Precise, Precision::Fast}) {
                    ShadeSetup s;
                    s.material = m;
                    s.lights = {Light{Light::Type::Directional, Ldir, {1, 1, 1}, 1.0, 0.0}};
                    s.view = glm::dvec4(eye, 1.0);
                    s.precision = p;
                    double best = 1e30;
                    std::vector<float> out;
                    for (int r = 0; r < repeats; ++r) {
                        ShadeTiming t;
                        out = shader.shade(fb, s, &t);
                        best = std::min(best, t.kernel_ms);
                    }
                    for (float v : out) ok = ok && std::isfinite(v);
                    const double fps = double(n) / best * 1e3;
                    std::string cpp = "-";
                    if ((info.name == "lambert" || info.name == "minnaert_1941") && p == Precision::Precise) {
                        std::vector<float> loop;
                        const double ms = cpp_loop_ms(info.name, fb, glm::vec3(Ldir), glm::vec3(eye), loop, repeats);
                        std::ostringstream x;
                        x << std::setprecision(2) << std::fixed << ms / best;
                        cpp = x.str();
                    }
                    std::cout << std::left << std::setw(32) << info.name << std::setw(9) << precision_name(p) << std::right
                              << std::setw(11) << std::setprecision(1) << fps * 1e-6 << std::setw(11) << std::setprecision(2)
                              << copy_ms / best << std::setw(11) << cpp << std::setw(12) << std::setprecision(0)
                              << fps / ref_fps << "\n";
                }
            }
        }
        std::cout << "\n" << (ok ? "all outputs finite" : "NON-FINITE OUTPUT FOUND") << "\n";
        return ok ? 0 : 1;
    } catch (const std::exception& e) {
        std::cerr << "bench_models: error: " << e.what() << "\n";
        return 1;
    }
}
