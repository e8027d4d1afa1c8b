// The OpenCL runtime layer: device choice, kernel discovery, build errors, error names.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <unistd.h>
#include <fstream>

#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "shade/shade_program.hpp"
#include "support.hpp"

using namespace shadelab;
namespace fs = std::filesystem;

using test::ScopedEnv;

TEST_CASE("runtime picks the PoCL CPU device by default", "[runtime]") {
    Runtime rt;
    const std::string d = rt.device_description();
    INFO(d);
    CHECK(d.find("Portable Computing Language") != std::string::npos);
    CHECK((rt.device().getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_CPU) != 0);
    CHECK(fs::exists(fs::path(rt.kernel_dir()) / "shade.cl"));
}

TEST_CASE("runtime error codes are shown by name", "[runtime]") {
    CHECK(cl_error_name(CL_BUILD_PROGRAM_FAILURE) == "CL_BUILD_PROGRAM_FAILURE");
    CHECK(cl_error_name(CL_INVALID_KERNEL_NAME) == "CL_INVALID_KERNEL_NAME");
    CHECK(cl_error_name(-1001) == "CL_PLATFORM_NOT_FOUND_KHR");
    CHECK(cl_error_name(-12345) == "CL_UNKNOWN_ERROR(-12345)");
}

TEST_CASE("runtime says clearly when the platform or device asked for does not exist", "[runtime]") {
    {
        ScopedEnv e("SHADELAB_CL_PLATFORM", "no-such-platform-xyz");
        REQUIRE_THROWS_AS(Runtime(), Error);
        REQUIRE_THROWS_WITH(Runtime(), Catch::Contains("no OpenCL platform matches 'no-such-platform-xyz'") &&
                                           Catch::Contains("Portable Computing Language"));
    }
    {
        ScopedEnv e("SHADELAB_CL_DEVICE", "99");
        REQUIRE_THROWS_WITH(Runtime(), Catch::Contains("SHADELAB_CL_DEVICE=99"));
    }
    {
        ScopedEnv e("SHADELAB_CL_DEVICE", "first");
        REQUIRE_THROWS_WITH(Runtime(), Catch::Contains("not a device index"));
    }
}

TEST_CASE("runtime reports a missing kernel folder with the places it looked", "[runtime]") {
    ScopedEnv e("SHADELAB_KERNELS", "/nonexistent/shadelab/kernels");
    REQUIRE_THROWS_WITH(Runtime(), Catch::Contains("SHADELAB_KERNELS") && Catch::Contains("shade.cl"));
}

TEST_CASE("a kernel build failure carries the build log, the options and the device", "[runtime]") {
    const fs::path dir = test::scratch_dir("badkernel");
    {
        std::ofstream f(dir / "shade.cl");
        f << "// line 1\n__kernel void broken(__global float* x) {\n  x[0] = undeclared_name;\n}\n";
    }
    Runtime rt(RuntimeOptions{"", -1, dir.string()});
    try {
        rt.build("shade.cl", {"SL_TEST_DEFINE=1"});
        FAIL("the broken kernel built");
    } catch (const Error& err) {
        const std::string msg = err.what();
        INFO(msg);
        CHECK(msg.find("CL_BUILD_PROGRAM_FAILURE") != std::string::npos);
        CHECK(msg.find("undeclared_name") != std::string::npos);   // the log
        CHECK(msg.find("shade.cl:3") != std::string::npos);        // line numbers match the file
        CHECK(msg.find("-DSL_TEST_DEFINE=1") != std::string::npos); // the options
        CHECK(msg.find("pthread") != std::string::npos);           // the device name
    }
    fs::remove_all(dir);
}

TEST_CASE("programs are built once per model and option set", "[runtime]") {
    Runtime rt;
    Material m = resolve_material(Material{});
    const auto defs = Shader::defines_for(m, 1);
    rt.build("shade.cl", defs);
    rt.build("shade.cl", defs);
    CHECK(rt.programs_built() == 1);
    rt.build("shade.cl", Shader::defines_for(m, 2));
    CHECK(rt.programs_built() == 2);
}

TEST_CASE("prebuild builds each distinct program once, on several threads, and shade() then reuses it", "[runtime]") {
    RuntimeOptions ro;
    ro.program_cache = "off";   // every program from source: the counts below are builds, not cache loads
    Runtime rt(ro);
    const std::vector<Light> one{Light{Light::Type::Directional, {0, 0, 1}, {1, 1, 1}, 1.0, 0.0}};
    std::vector<ProgramRequest> requests;
    for (const char* model : {"lambert", "half_lambert", "lambert"})   // one twice: built once
        requests.push_back(shade_program(resolve_material(Material{model}), one, Precision::Precise, rt.vector_width(), true));
    prebuild(rt, requests, 3);
    CHECK(rt.programs_built() == 2);
    // shade() asks for exactly the program prebuild made: no further build, and the shading is right.
    Shader shader(rt);
    FragmentBuffer fb;
    fb.width = 1;
    fb.height = 1;
    fb.push_back(0, 0, 0, 0, 0, 1, 0, 1.0f);
    ShadeSetup s;
    s.material = resolve_material(Material{"lambert"});
    s.lights = one;
    s.view = glm::dvec4(0.0, 0.0, 3.0, 1.0);
    const auto out = shader.shade(fb, s);
    CHECK(rt.programs_built() == 2);
    REQUIRE(out.size() == 3);
    const glm::dvec3 want = ref::shade_point({0, 0, 0}, {0, 0, 1}, {0, 0, 1}, s.material, one, glm::dvec3(0.0));
    CHECK(want.x > 0.0);
    CHECK(out[0] == Approx(want.x).epsilon(1e-5));
}

TEST_CASE("a failing prebuild names the file once every thread has finished", "[runtime]") {
    RuntimeOptions ro;
    ro.program_cache = "off";
    Runtime rt(ro);
    std::vector<ProgramRequest> requests{{"shade.cl", {"SL_NO_SUCH_MODEL_EVAL=1"}, ""},
                                                  {"no_such_file.cl", {}, ""}};
    REQUIRE_THROWS_WITH(prebuild(rt, requests, 2), Catch::Contains(".cl"));
    // The runtime is still usable: a good program builds afterwards.
    const Material m = resolve_material(Material{});
    rt.build("shade.cl", Shader::defines_for(m, 1));
    CHECK(rt.programs_built() >= 1);
}

TEST_CASE("materials are validated with one clear line", "[runtime][models]") {
    Material m;
    m.model = "no_such_model";
    REQUIRE_THROWS_WITH(resolve_material(m, "scene 'x.json'"),
                        Catch::Contains("scene 'x.json'") && Catch::Contains("unknown model 'no_such_model'") &&
                            Catch::Contains("lambert"));
    m.model = "lambert";
    m.params["sigma"] = 0.3;
    REQUIRE_THROWS_WITH(resolve_material(m), Catch::Contains("has no parameter 'sigma'"));
    m.params.clear();
    m.albedo = {0.5, -1.0, 0.5};
    REQUIRE_THROWS_WITH(resolve_material(m), Catch::Contains("albedo"));
}
