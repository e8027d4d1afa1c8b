// The double reference over a whole fragment buffer (ref::shade_fragments): what renders are scored against.
#include <algorithm>
#include <thread>

#include "reference/reference.hpp"

namespace shadelab::ref {

std::vector<float> shade_fragments(const FragmentBuffer& fb, const Material& m, const std::vector<Light>& lights,
                                   const dvec3& ambient, const dvec3& eye) {
    const std::size_t n = fb.size();
    std::vector<float> out(3 * n);
    auto run = [&](std::size_t lo, std::size_t hi) {
        for (std::size_t i = lo; i < hi; ++i) {
            const dvec3 P{fb.px[i], fb.py[i], fb.pz[i]}, N{fb.nx[i], fb.ny[i], fb.nz[i]};
            const dvec3 v = shade_point(P, N, glm::normalize(eye - P), m, lights, ambient);
            for (std::size_t c = 0; c < 3; ++c) out[c * n + i] = float(v[int(c)]);
        }
    };
    const std::size_t threads = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(run, n * t / threads, n * (t + 1) / threads);
    run(0, n / threads);
    for (auto& th : pool) th.join();
    return out;
}

}  // namespace shadelab::ref
