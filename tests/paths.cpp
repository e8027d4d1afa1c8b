// The folders of this build's source tree, for the test files (tests/support.hpp). The only test file the
// build's paths are compiled into (SHADELAB_SOURCE_DIR, SHADELAB_MESH_DIR, SHADELAB_TEST_DATA_DIR).
#include <string>

namespace shadelab::test {

std::string source_dir() { return SHADELAB_SOURCE_DIR; }
std::string mesh_dir() { return SHADELAB_MESH_DIR; }
std::string data_dir() { return SHADELAB_TEST_DATA_DIR; }

}  // namespace shadelab::test
