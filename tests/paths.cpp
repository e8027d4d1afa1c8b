// The folders of this build's source tree, for the test files (tests/support.hpp). The only test file the
// build's paths are compiled into (SHADELAB_SOURCE_DIR, SHADELAB_MESH_DIR, SHADELAB_TEST_DATA_DIR).
#include <string>

namespace shadelab::test {

extern const std::string kSourceDir = SHADELAB_SOURCE_DIR;
extern const std::string kScenes = std::string(SHADELAB_SOURCE_DIR) + "/scenes";
extern const std::string kMeshes = SHADELAB_MESH_DIR;
extern const std::string kData = SHADELAB_TEST_DATA_DIR;

}  // namespace shadelab::test
