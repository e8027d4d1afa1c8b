// The one atomic writer (host/core/atomic_file.hpp) behind images, FITS, CSV tables and batch reports:
// content appears whole or not at all, no temporary is left behind on any path, and each failure is one
// line naming the file and what to do.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "support.hpp"

using namespace shadelab;
namespace fs = std::filesystem;

namespace {

std::string read_all(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Names in `dir` that look like a temporary of the atomic writer.
std::size_t temporaries_in(const fs::path& dir) {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.path().filename().string().find(".tmp") != std::string::npos;
    return n;
}

}  // namespace

TEST_CASE("atomic writer: creates the folder, writes the bytes as given, replaces an old file, leaves no temporary",
          "[atomic_file]") {
    const fs::path dir = test::scratch_dir("atomic_ok");
    const fs::path target = dir / "new" / "deeper" / "table.csv";
    const std::string bytes = std::string("a,b\n1,2\n") + '\0' + "\r\n";
    write_text_atomically(target.string(), "table", bytes);
    CHECK(read_all(target) == bytes);
    write_text_atomically(target.string(), "table", "replaced\n");
    CHECK(read_all(target) == "replaced\n");
    CHECK(temporaries_in(target.parent_path()) == 0);
}

TEST_CASE("atomic writer: a failed or throwing fill leaves the old file and no temporary - the error names the file",
          "[atomic_file]") {
    const fs::path dir = test::scratch_dir("atomic_fail");
    const fs::path target = dir / "report.json";
    write_text_atomically(target.string(), "report", "old\n");
    std::string seen_tmp;
    const auto failing = [&](const std::string& tmp, std::string& why) {
        seen_tmp = tmp;
        std::ofstream(tmp) << "half";
        why = "the encoder gave up";
        return false;
    };
    REQUIRE_THROWS_WITH(write_file_atomically(target.string(), "report", failing),
                        Catch::Contains("writing '" + target.string() + "' failed: the encoder gave up") &&
                            Catch::Contains("is the disk full or the folder read-only?"));
    CHECK(fs::path(seen_tmp).parent_path() == dir);   // beside the target, so the rename is atomic
    CHECK(fs::path(seen_tmp).filename().string().rfind(".report.json.tmp", 0) == 0);   // hidden
    CHECK(read_all(target) == "old\n");
    CHECK(temporaries_in(dir) == 0);

    const auto throwing = [](const std::string& tmp, std::string&) -> bool {
        std::ofstream(tmp) << "half";
        throw std::runtime_error("boom");
    };
    REQUIRE_THROWS_WITH(write_file_atomically(target.string(), "report", throwing), "boom");
    CHECK(read_all(target) == "old\n");
    CHECK(temporaries_in(dir) == 0);

    // The suffix ends the temporary's name (writers that choose the format from the extension need it).
    write_file_atomically(
        (dir / "image.png").string(), "image",
        [&](const std::string& tmp, std::string&) {
            seen_tmp = tmp;
            std::ofstream(tmp) << "png";
            return true;
        },
        ".png");
    CHECK(fs::path(seen_tmp).extension() == ".png");
    CHECK(read_all(dir / "image.png") == "png");
    CHECK(temporaries_in(dir) == 0);
}

TEST_CASE("atomic writer: a folder that cannot be made or a target that is a folder is one clear error", "[atomic_file]") {
    const fs::path dir = test::scratch_dir("atomic_bad");
    std::ofstream(dir / "plain_file") << "x";
    const std::string under_file = (dir / "plain_file" / "out.csv").string();
    REQUIRE_THROWS_AS(write_text_atomically(under_file, "table", "a\n"), Error);
    REQUIRE_THROWS_WITH(write_text_atomically(under_file, "table", "a\n"),
                        Catch::Contains("cannot create folder '" + (dir / "plain_file").string() + "' for '" + under_file + "'"));

    fs::create_directories(dir / "taken" / "inside");
    const std::string taken = (dir / "taken").string();
    REQUIRE_THROWS_WITH(write_text_atomically(taken, "table", "a\n"),
                        Catch::Contains("cannot move the finished table into place at '" + taken + "'"));
    CHECK(fs::is_directory(dir / "taken" / "inside"));
    CHECK(temporaries_in(dir) == 0);
}
