// Uses the installed library the way its README promises: list models, shade directions on PoCL and check
// them against the double reference, render a bundled mesh to memory, compare, and fail loudly otherwise.
#include <cmath>
#include <cstdio>
#include <string>

#include <shadelab/shadelab.hpp>

int main(int argc, char** argv) {
    namespace sl = shadelab::api;
    if (argc < 2) {
        std::fprintf(stderr, "usage: consumer MESH\n");
        return 2;
    }
    if (sl::models().size() < 30) return std::fprintf(stderr, "too few models\n"), 1;
    sl::Engine engine;
    sl::Material m;
    m.model = "oren_nayar";
    m.params["sigma"] = 0.4;
    m.albedo = {1, 1, 1};
    const float N[] = {0, 0, 1, 0, 0, 1}, L[] = {0, 0, 1, 0.6f, 0, 0.8f}, V[] = {0, 0, 1, -0.6f, 0, 0.8f};
    float out[6];
    engine.shade(m, N, L, V, 2, out);
    for (int i = 0; i < 2; ++i) {
        const auto r = sl::reference(m, {N[3 * i], N[3 * i + 1], N[3 * i + 2]}, {L[3 * i], L[3 * i + 1], L[3 * i + 2]},
                                     {V[3 * i], V[3 * i + 1], V[3 * i + 2]});
        if (!(std::fabs(out[3 * i] - r[0]) < 1e-5 * std::fmax(1.0, r[0])))
            return std::fprintf(stderr, "kernel %g vs reference %g\n", out[3 * i], r[0]), 1;
    }
    sl::RenderOptions ro;
    ro.width = ro.height = 64;
    const sl::Image img = engine.render(argv[1], ro);
    std::size_t covered = 0;
    for (int p = 0; p < img.width * img.height; ++p) covered += img.pixels[std::size_t(p) * 4 + 3] > 0.5f;
    if (covered < 100) return std::fprintf(stderr, "render covered only %zu pixels\n", covered), 1;
    const sl::Comparison c = sl::compare(img, img);
    if (c.de_max != 0.0 || c.pixels != covered) return std::fprintf(stderr, "self-compare not exact\n"), 1;
    try {
        m.model = "no_such_model";
        engine.shade(m, N, L, V, 1, out);
        return std::fprintf(stderr, "unknown model accepted\n"), 1;
    } catch (const sl::Error& e) {
        if (std::string(e.what()).find("unknown model 'no_such_model'") == std::string::npos)
            return std::fprintf(stderr, "unexpected message: %s\n", e.what()), 1;
    }
    std::printf("shadelab %s on %s: %zu models, oren_nayar kernel = reference, %zu pixels rendered\n",
                sl::version().c_str(), engine.device().c_str(), sl::models().size(), covered);
    std::printf("kernels: %s\n", engine.kernel_dir().c_str());
    return 0;
}
