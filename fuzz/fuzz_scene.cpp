// libFuzzer target: scene files (JSON parse with its depth guard, every key's checks, outputs, placeholders).
// The input is the scene; a mesh 'm.obj' lies beside it so that mesh paths can resolve.
#include <cstddef>
#include <cstdint>
#include <fstream>

#include "core/error.hpp"
#include "fuzz_common.hpp"
#include "scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string mesh = [] {
        const std::string p = shadelab::fuzz::scratch_path("m.obj");
        std::ofstream(p) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        return p;
    }();
    (void)mesh;
    const std::string path = shadelab::fuzz::scratch_path("scene.json");
    shadelab::fuzz::write_file(path, data, size);
    try {
        shadelab::SceneLoadOptions o;
        o.out_dir = "fuzz-out";   // nothing is written: outputs are only named
        (void)shadelab::load_scene(path, o);
    } catch (const shadelab::Error&) {
    }
    return 0;
}
