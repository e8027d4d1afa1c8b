// Catch2 (v2, Debian's catch2 package) test runner.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <cstdlib>

int main(int argc, char* argv[]) {
    // No test depends on what a user's mesh cache holds (an entry left by another build would give its mesh instead
    // of the loader's): meshes load from their files, in this process and the commands it runs. The cache's own
    // tests (tests/test_mesh_cache.cpp) name a scratch folder explicitly.
    ::setenv("SHADELAB_MESH_CACHE", "off", 1);
    return Catch::Session().run(argc, argv);
}
