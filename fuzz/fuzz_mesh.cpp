// libFuzzer target: the mesh loaders (structural check, NaN scans, OpenMesh, validation and repair).
// The first byte picks the format (OBJ, PLY, OFF, STL); the rest is the file. Every input must end in a
// mesh or a shadelab::Error: any other exception, a crash, a sanitizer report or a hang (-timeout) is a bug.
#include <cstddef>
#include <cstdint>

#include "core/error.hpp"
#include "fuzz_common.hpp"
#include "mesh/mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* const kExt[] = {".obj", ".ply", ".off", ".stl"};
    const std::string path = shadelab::fuzz::scratch_path(std::string("mesh") + kExt[data[0] % 4]);
    shadelab::fuzz::write_file(path, data + 1, size - 1);
    try {
        shadelab::MeshLoadReport report;
        shadelab::MeshCacheUse no_cache;   // every input through the full loader, and no cache files written
        no_cache.setting = "off";
        const shadelab::Mesh m = shadelab::load_mesh(path, &report, &no_cache);
        // What the loader promises of every mesh it returns.
        if (m.triangles.empty() || m.normals.size() != m.positions.size()) __builtin_trap();
        for (const auto& t : m.triangles)
            for (int k = 0; k < 3; ++k)
                if (t[k] >= m.positions.size()) __builtin_trap();
    } catch (const shadelab::Error&) {
    }
    return 0;
}
