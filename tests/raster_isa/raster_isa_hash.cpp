// The rasteriser's fragments, hashed, for cases that take every path of host/raster/raster.cpp: dense meshes
// whose triangles are smaller than a pixel (set-up in lanes, triangles settled in set-up), wide ones (spans),
// triangle ids, back-face culling, the near plane through the mesh (clipping), odd sizes, one and two threads.
// CMake builds this driver three times, with the rasteriser compiled for this CPU (-march=native: AVX-512 code on
// an AVX-512 host), for an AVX2 CPU (-march=haswell) and for generic x86-64; tests/raster_isa/check.sh requires
// the three to print the same lines. The native build is held to the brute-force evaluation by test_raster.cpp,
// so the other two are held to it too, whatever CPU runs the tests.
// Usage: raster_isa_hash MESH...   (one line per case: mesh, size, options, threads, fragments, hash)
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"
#include "raster/camera.hpp"
#include "raster/raster.hpp"

namespace {

// FNV-1a over the bytes of one array.
template <class V>
void fnv(std::uint64_t& h, const V& v) {
    const unsigned char* p = reinterpret_cast<const unsigned char*>(v.data());
    for (std::size_t i = 0; i < v.size() * sizeof(v[0]); ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
}

std::uint64_t hash_of(const shadelab::FragmentBuffer& fb) {
    std::uint64_t h = 1469598103934665603ull;
    fnv(h, fb.px);
    fnv(h, fb.py);
    fnv(h, fb.pz);
    fnv(h, fb.nx);
    fnv(h, fb.ny);
    fnv(h, fb.nz);
    fnv(h, fb.depth);
    fnv(h, fb.pixel);
    fnv(h, fb.triangle);
    fnv(h, fb.b1);
    fnv(h, fb.b2);
    return h;
}

struct Case {
    const char* name;
    bool ids, cull;
    double zoom, near;   // eye at zoom times the fitted distance; z_near = near times that distance (0: the fit's)
};

}  // namespace

int main(int argc, char** argv) try {
    using namespace shadelab;
    const Case cases[] = {{"plain", false, false, 1.0, 0.0},
                          {"ids", true, false, 1.0, 0.0},
                          {"ids+cull", true, true, 1.0, 0.0},
                          {"ids+clipped", true, false, 1.0, 0.95},
                          {"close+cull", false, true, 0.2, 0.6}};
    const int sizes[][2] = {{512, 512}, {333, 97}, {1920, 1080}};
    for (int a = 1; a < argc; ++a) {
        const Mesh mesh = load_mesh(argv[a]);
        for (const auto& size : sizes)
            for (const Case& c : cases)
                for (int threads = 1; threads <= 2; ++threads) {
                    Camera cam = Camera::fit(mesh.bounds(), {0.0, 0.25, 1.0}, 35.0, double(size[0]) / double(size[1]));
                    cam.eye = cam.target + (cam.eye - cam.target) * c.zoom;
                    if (c.near > 0.0) cam.z_near = c.near * glm::length(cam.eye - cam.target);
                    RasterOptions o;
                    o.width = size[0];
                    o.height = size[1];
                    o.threads = threads;
                    o.triangle_ids = c.ids;
                    o.cull_backfaces = c.cull;
                    const FragmentBuffer fb = rasterize(mesh, cam, o);
                    std::printf("%s %dx%d %s threads=%d fragments=%zu hash=%016llx\n", mesh.source.c_str(), size[0],
                                size[1], c.name, threads, fb.size(), static_cast<unsigned long long>(hash_of(fb)));
                }
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "raster_isa_hash: %s\n", e.what());
    return 1;
}
