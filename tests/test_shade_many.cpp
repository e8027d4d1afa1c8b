// Many models' shade kernels in one program (Shader::prepare_many, kernels/shade_many.cl): the same pixels as
// each model's own program, bit for bit, with fewer programs built; models with tables or children, and shades
// with other lights or precision, keep their own programs. (The whole catalogue's contact sheet, shared against
// per-model programs, is compared pixel for pixel by scripts/identical_renders.sh.)
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <set>
#include <utility>

#include "cl/runtime.hpp"
#include "models/catalogue.hpp"
#include "shade/shade_program.hpp"
#include "shade/shader.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

Material default_of(const std::string& model) {
    Material m;
    m.model = model;
    add_demo_children(m, find_model(model));
    return resolve_material(m);
}

FragmentBuffer random_fragments(std::size_t n, std::uint64_t seed) {
    std::mt19937_64 g(seed);
    FragmentBuffer fb;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 p = 2.0 * test::random_unit(g) * test::unit_double(g);
        const glm::dvec3 nn = test::random_unit(g);
        fb.push_back(float(p.x), float(p.y), float(p.z), float(nn.x), float(nn.y), float(nn.z), int(i), 1.0f);
    }
    return fb;
}

ShadeSetup setup_of(const Material& m, const std::vector<Light>& lights, Precision p) {
    ShadeSetup s;
    s.material = m;
    s.lights = lights;
    s.ambient = {0.03, 0.02, 0.01};
    s.view = {0.3, 0.5, 4.0, 1.0};
    s.precision = p;
    return s;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// The models whose fast build is other code than their precise one: those that call pow (common.cl, pow_nonneg).
bool fast_is_other_code(const ModelInfo& info) {
    return info.name.find("phong") != std::string::npos || info.name.find("minnaert") != std::string::npos ||
           info.name == "toon";
}

// One model of each of several families (skipped when the catalogue has no such model).
std::vector<std::string> family_models() {
    std::vector<std::string> out;
    for (const char* name : {"lambert", "wrap_energy", "blinn_phong", "toon", "minnaert_1941", "oren_nayar_full",
                             "cook_torrance_ggx", "hapke_hen"})
        for (const auto& info : model_catalogue())
            if (info.name == name) out.push_back(name);
    return out;
}

const std::vector<Light> kOneDirectional{Light{Light::Type::Directional, {1.0, 1.0, 1.0}, {1.0, 0.9, 0.8}, 1.0, 0.0}};
const std::vector<Light> kDirectionalAndPoint{
    Light{Light::Type::Directional, {1.0, 1.0, 1.0}, {1.0, 0.9, 0.8}, 1.0, 0.0},
    Light{Light::Type::Point, {-2.0, 3.0, 2.5}, {0.5, 0.6, 1.0}, 4.0, 8.0}};

}  // namespace

// Both kinds of shared program: one kernel per model, and one dispatching kernel for all (`dispatch`).
TEST_CASE("shade: one shared program gives each model's own program's pixels, bit for bit", "[shade][shade_many]") {
    const std::vector<std::string> models = family_models();
    REQUIRE(models.size() >= 4);
    const FragmentBuffer fb = random_fragments(1000, 7);   // not a multiple of the work-group size: padding too
    for (bool dispatch : {false, true})
        for (Precision p : {Precision::Precise, Precision::Fast})
            for (const auto* lights : {&kOneDirectional, &kDirectionalAndPoint}) {
                Runtime rt(RuntimeOptions{"", -1, "", "off"});
                Shader own(rt), shared(rt);
                std::vector<Material> mats;
                for (const auto& name : models) mats.push_back(default_of(name));
                const std::size_t before = rt.programs_built();
                REQUIRE(shared.prepare_many(mats, *lights, p, dispatch) == models.size());
                // one program for each kind of work-item among them: the normals-only models' programs take
                // fewer lanes and the sixteen-lane models' more (Shader::lanes_for), the two-chain models' two
                // chains (Shader::chains_for), and a program's models share its lanes and chains
                std::set<std::pair<std::size_t, std::size_t>> kinds;
                for (const Material& m : mats) {
                    const ModelInfo& info = find_model(m.model);
                    kinds.insert({Shader::lanes_for(info, rt.vector_width()), Shader::chains_for(info, rt.vector_width())});
                }
                const std::size_t programs = kinds.size();
                CHECK(rt.programs_built() == before + programs);
                for (const Material& m : mats) {
                    INFO("model " << m.model << ", " << precision_name(p) << ", " << lights->size() << " light(s)"
                                  << (dispatch ? ", dispatching kernel" : ""));
                    const std::vector<float> a = own.shade(fb, setup_of(m, *lights, p));
                    const std::vector<float> b = shared.shade(fb, setup_of(m, *lights, p));
                    REQUIRE(a.size() == 3 * fb.size());
                    CHECK(same_bits(a, b));
                }
                // `own` built one program per model, `shared` none beyond its own
                CHECK(rt.programs_built() == before + programs + models.size());
            }
}

// Every model of the catalogue (as the contact sheet shades them): the dispatching kernel, one switch over all the
// shareable models' eval functions, gives the per-model kernels' pixels, bit for bit.
TEST_CASE("shade: the dispatching kernel over the whole catalogue gives each model's kernel's pixels, bit for bit",
          "[shade][shade_many]") {
    Runtime rt(RuntimeOptions{"", -1, "", "off"});
    Shader per_model(rt), dispatching(rt);
    std::vector<Material> mats;
    for (const auto& info : model_catalogue()) mats.push_back(default_of(info.name));
    const std::size_t shared = per_model.prepare_many(mats, kOneDirectional, Precision::Precise, false);
    REQUIRE(shared > 8);
    REQUIRE(dispatching.prepare_many(mats, kOneDirectional, Precision::Precise, true) == shared);
    const FragmentBuffer fb = random_fragments(1000, 5);
    for (const Material& m : mats) {
        INFO("model " << m.model);
        const std::vector<float> a = per_model.shade(fb, setup_of(m, kOneDirectional, Precision::Precise));
        const std::vector<float> b = dispatching.shade(fb, setup_of(m, kOneDirectional, Precision::Precise));
        REQUIRE(a.size() == 3 * fb.size());
        CHECK(same_bits(a, b));
    }
}

TEST_CASE("shade: models with tables or children and other lights keep their own programs", "[shade][shade_many]") {
    Runtime rt(RuntimeOptions{"", -1, "", "off"});
    Shader shader(rt);
    // (two models of the same lanes, Shader::lanes_for: one shared program)
    std::vector<Material> mats{default_of("blinn_phong"), default_of("phong"), default_of("blinn_phong")};
    for (const auto& info : model_catalogue())
        if (has_tables(info) || info.children > 0) mats.push_back(default_of(info.name));
    REQUIRE(mats.size() >= 4);   // the catalogue has a table model or a blend
    CHECK(shader.prepare_many(mats, kOneDirectional, Precision::Precise) == 2);   // blinn_phong once, phong
    CHECK(shader.prepare_many(mats, kOneDirectional, Precision::Precise) == 0);   // already prepared
    CHECK(rt.programs_built() == 1);
    const FragmentBuffer fb = random_fragments(300, 11);
    shader.shade(fb, setup_of(mats[0], kOneDirectional, Precision::Precise));
    CHECK(rt.programs_built() == 1);
    shader.shade(fb, setup_of(mats[0], kDirectionalAndPoint, Precision::Precise));   // other lights: own program
    CHECK(rt.programs_built() == 2);
    shader.shade(fb, setup_of(mats[0], kOneDirectional, Precision::Fast));           // other precision: own
    CHECK(rt.programs_built() == 3);
    shader.shade(fb, setup_of(mats[3], kOneDirectional, Precision::Precise));        // a table or blend model
    CHECK(rt.programs_built() == 4);
}

// The view's kind (perspective or orthographic) is built into the shade programs (SL_PERSPECTIVE, kernels/
// shade_parts.cl): each kind gets its own program, a program prepared for one kind is not used for the other, and
// both kinds reach the kernel (their pixels differ for the models that depend on the view). That each kind's
// pixels are the reference's is tests/test_lights.cpp's check.
TEST_CASE("shade: the view's kind is part of the program, and each kind shades with its own", "[shade][shade_many]") {
    for (bool perspective : {true, false}) {
        const ProgramRequest req = shade_program(default_of("phong"), kOneDirectional, Precision::Precise, 8, perspective);
        CHECK(std::count(req.defines.begin(), req.defines.end(), perspective ? "SL_PERSPECTIVE=1" : "SL_PERSPECTIVE=0") == 1);
        CHECK(std::count(req.defines.begin(), req.defines.end(), perspective ? "SL_PERSPECTIVE=0" : "SL_PERSPECTIVE=1") == 0);
    }
    CHECK(is_perspective(glm::dvec4(0.0, 0.0, 3.0, 1.0)));
    CHECK_FALSE(is_perspective(glm::dvec4(0.0, 0.0, 1.0, 0.0)));
    const FragmentBuffer fb = random_fragments(1000, 13);
    for (const char* model : {"phong", "oren_nayar", "hapke_leg", "lambert"}) {
        INFO("model " << model);
        const Material m = default_of(model);
        ShadeSetup persp = setup_of(m, kOneDirectional, Precision::Precise), ortho = persp;
        ortho.view = {0.3, 0.5, 4.0, 0.0};   // the same point of view, as a direction (made unit by the shader)
        Runtime rt(RuntimeOptions{"", -1, "", "off"});
        Shader own(rt), shared(rt);
        REQUIRE(shared.prepare_many({m}, kOneDirectional, Precision::Precise, false, false) == 1);   // orthographic
        const std::size_t before = rt.programs_built();
        const std::vector<float> o_shared = shared.shade(fb, ortho);
        CHECK(rt.programs_built() == before);   // the prepared program
        const std::vector<float> p_shared = shared.shade(fb, persp);
        CHECK(rt.programs_built() == before + 1);   // not the orthographic one: its own program
        const std::vector<float> o_own = own.shade(fb, ortho);
        CHECK(rt.programs_built() == before + 2);
        CHECK(same_bits(o_shared, o_own));
        CHECK(same_bits(p_shared, own.shade(fb, persp)));
        if (find_model(model).normals_only) CHECK(same_bits(o_own, p_shared));
        else CHECK_FALSE(same_bits(o_own, p_shared));
    }
}

// Each light's kind (directional, point, point with a range) is built into the shade programs (SL_POINT_LIGHTS,
// SL_RANGED_LIGHTS, kernels/shade_parts.cl): the masks follow the lights in order, a program prepared for one
// pattern of kinds is not used for another, and the pixels are those of the kinds read per light at run time
// (SHADELAB_LIGHT_KINDS=0, the kernel's way without the defines), bit for bit. That they are the reference's is
// tests/test_lights.cpp's check (its lights mix the three kinds).
TEST_CASE("shade: each light's kind is part of the program, with the pixels of the kinds read at run time",
          "[shade][shade_many]") {
    const Light dir{Light::Type::Directional, {1.0, 1.0, 1.0}, {1.0, 0.9, 0.8}, 1.0, 0.0};
    const Light point{Light::Type::Point, {-2.0, 3.0, 2.5}, {0.5, 0.6, 1.0}, 4.0, 0.0};
    const Light ranged{Light::Type::Point, {1.0, 2.0, -3.0}, {0.9, 0.6, 0.5}, 9.0, 6.0};
    const std::vector<Light> dprd{dir, point, ranged, dir};
    CHECK(light_kinds(dprd) == "dprd");
    CHECK(light_defines(dprd) == std::vector<std::string>{"SL_POINT_LIGHTS=0x6ul", "SL_RANGED_LIGHTS=0x4ul"});
    CHECK(light_defines(kOneDirectional) ==
          std::vector<std::string>{"SL_POINT_LIGHTS=0x0ul", "SL_RANGED_LIGHTS=0x0ul"});
    const std::vector<Light> many(64, ranged);
    CHECK(light_defines(many) == std::vector<std::string>{"SL_POINT_LIGHTS=0xfffffffffffffffful",
                                                          "SL_RANGED_LIGHTS=0xfffffffffffffffful"});
    CHECK(light_defines(std::vector<Light>(65, dir)).empty());   // more than the masks hold: read at run time
    {
        test::ScopedEnv off("SHADELAB_LIGHT_KINDS", "0");
        CHECK(light_defines(dprd).empty());
        CHECK_FALSE(light_kinds_in_programs());
    }
    {
        test::ScopedEnv bad("SHADELAB_LIGHT_KINDS", "yes");
        CHECK_THROWS_WITH(light_defines(dprd), Catch::Contains("SHADELAB_LIGHT_KINDS is 'yes'"));
    }
    const FragmentBuffer fb = random_fragments(1000, 17);
    const std::vector<Light> dp{dir, point}, pd{point, dir}, dr{dir, ranged};
    for (const char* model : {"lambert", "blinn_phong", "oren_nayar_full", "cook_torrance", "hapke_hen"}) {
        INFO("model " << model);
        const Material m = default_of(model);
        Runtime rt(RuntimeOptions{"", -1, "", "off"});
        Shader shared(rt), own(rt);
        REQUIRE(shared.prepare_many({m}, dp, Precision::Precise) == 1);
        const std::size_t before = rt.programs_built();
        const std::vector<float> dp_shared = shared.shade(fb, setup_of(m, dp, Precision::Precise));
        CHECK(rt.programs_built() == before);   // the prepared program
        for (const std::vector<Light>* lights : {&pd, &dr}) {   // the same count, other kinds: their own programs
            const std::size_t built = rt.programs_built();
            const std::vector<float> kinds_built = shared.shade(fb, setup_of(m, *lights, Precision::Precise));
            CHECK(rt.programs_built() == built + 1);
            test::ScopedEnv off("SHADELAB_LIGHT_KINDS", "0");
            CHECK(same_bits(kinds_built, own.shade(fb, setup_of(m, *lights, Precision::Precise))));
        }
        const std::vector<float> dprd_fast = own.shade(fb, setup_of(m, dprd, Precision::Fast));   // four lights
        test::ScopedEnv off("SHADELAB_LIGHT_KINDS", "0");
        const std::size_t built = rt.programs_built();
        CHECK(same_bits(dp_shared, own.shade(fb, setup_of(m, dp, Precision::Precise))));
        CHECK(same_bits(dprd_fast, own.shade(fb, setup_of(m, dprd, Precision::Fast))));
        // the kinds read at run time: one program for every pattern of a light count (the two-light one was built
        // in the loop above), the four lights' in fast mode new
        CHECK(rt.programs_built() == built + 1);
    }
}

TEST_CASE("shade: a shared program that does not build throws and leaves shade() to the models' own programs",
          "[shade][shade_many]") {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("shadelab-shade-many-" + std::to_string(std::random_device{}()));
    fs::create_directories(dir);
    fs::copy(Runtime::find_kernel_dir(), dir, fs::copy_options::recursive);
    std::ofstream(dir / "shade_many.cl") << "#error broken on purpose\n";
    {
        Runtime rt(RuntimeOptions{"", -1, dir.string(), "off"});
        Shader shader(rt);
        const Material m = default_of("lambert");
        REQUIRE_THROWS_WITH(shader.prepare_many({m}, kOneDirectional), Catch::Contains("shade_many.cl"));
        const std::vector<float> v = shader.shade(random_fragments(10, 3), setup_of(m, kOneDirectional, Precision::Precise));
        CHECK(v.size() == 30);
    }
    fs::remove_all(dir);
}

// The fragment loop (kernels/common.cl, SL_FRAGS_PER_ITEM): a work-item shades the device's vector width of
// fragments (Shader::lanes_for), launched as n / width work-items. Every model of the catalogue gives the pixels of one fragment a
// work-item (the form PoCL's own work-item loop vectorises), bit for bit, with a tail (1000 is not a multiple of
// the work-group) and two lights; fast mode for the models whose fast build is other code (the pow models).
TEST_CASE("shade: the fragment loop at the device's vector width gives one-fragment-a-work-item pixels, bit for bit",
          "[shade][vector_width]") {
    Runtime one(RuntimeOptions{"", -1, "", "off", 1}), wide(RuntimeOptions{"", -1, "", "off"});
    REQUIRE(one.vector_width() == 1);
    INFO("device vector width " << wide.vector_width());
    REQUIRE((wide.vector_width() >= 1 && wide.vector_width() <= 16));
    Shader a(one), b(wide);
    const FragmentBuffer fb = random_fragments(1000, 13);
    std::size_t compared = 0;
    for (const auto& info : model_catalogue()) {
        const Material m = default_of(info.name);
        for (Precision p : {Precision::Precise, Precision::Fast}) {
            if (p == Precision::Fast && !fast_is_other_code(info)) continue;
            INFO("model " << m.model << ", " << precision_name(p));
            const std::vector<float> x = a.shade(fb, setup_of(m, kDirectionalAndPoint, p));
            const std::vector<float> y = b.shade(fb, setup_of(m, kDirectionalAndPoint, p));
            REQUIRE(x.size() == 3 * fb.size());
            CHECK(same_bits(x, y));
            ++compared;
        }
    }
    CHECK(compared > model_catalogue().size());
}

TEST_CASE("shade: a work-group size that is not a multiple of the vector width is refused with one line",
          "[shade][vector_width]") {
    Runtime rt(RuntimeOptions{"", -1, "", "off", 16});
    Shader shader(rt);
    // Oren-Nayar: one chain of 16 lanes. Half-Lambert reads normals only: 8 fragments a work-item
    // (Shader::lanes_for), so 24 is a whole number of them. Phong runs two chains of 16 lanes (Shader::chains_for).
    const struct {
        const char* model;
        int chains;
        std::size_t per_item, refused, taken;   // fragments a work-item, a work-group size refused, one taken
    } cases[] = {{"oren_nayar", 1, 16, 24, 32}, {"half_lambert", 1, 8, 12, 24}, {"phong", 2, 32, 48, 64}};
    for (const auto& c : cases) {
        INFO("model " << c.model);
        REQUIRE(find_model(c.model).chains == c.chains);
        ShadeSetup s = setup_of(default_of(c.model), kOneDirectional, Precision::Precise);
        s.local_size = c.refused;
        REQUIRE_THROWS_WITH(shader.shade(random_fragments(100, 3), s),
                            Catch::Contains("work-group size " + std::to_string(c.refused)) &&
                                Catch::Contains("multiple of the " + std::to_string(c.per_item) + " fragments"));
        s.local_size = c.taken;
        CHECK(shader.shade(random_fragments(100, 3), s).size() == 300);
    }
    CHECK_THROWS_WITH(Runtime(RuntimeOptions{"", -1, "", "off", 3}), Catch::Contains("vector width 3"));
}

// The chains are chosen per kind of device (ModelInfo::chains_avx2): on a device of 8 lanes (an AVX2 host's) Oren-Nayar
// runs two chains, 16 fragments a work-item, where 16 lanes run it as one; lunar_lambert keeps one chain on both.
// The launch, the program's SL_CHAINS and the pixels agree: on the 8-lane device a work-group of one and a half
// work-items' fragments is refused (24 for Oren-Nayar), 32 taken, and the pixels are the 16-lane device's, bit for bit.
TEST_CASE("shade: chains per kind of device, launched as the program was built", "[shade][vector_width]") {
    Runtime eight(RuntimeOptions{"", -1, "", "off", 8}), sixteen(RuntimeOptions{"", -1, "", "off", 16});
    const FragmentBuffer fb = random_fragments(100, 5);
    const struct {
        const char* model;
        std::size_t per_item_8, per_item_16;
    } cases[] = {{"oren_nayar", 16, 16}, {"eon", 16, 16}, {"lunar_lambert", 8, 16}, {"phong", 16, 32}};
    for (const auto& c : cases) {
        INFO("model " << c.model);
        const ModelInfo& info = find_model(c.model);
        REQUIRE(Shader::frags_per_item(info, 8) == c.per_item_8);
        REQUIRE(Shader::frags_per_item(info, 16) == c.per_item_16);
        ShadeSetup s = setup_of(default_of(c.model), kOneDirectional, Precision::Precise);
        s.local_size = c.per_item_8 + c.per_item_8 / 2;
        REQUIRE_THROWS_WITH(Shader(eight).shade(fb, s), Catch::Contains("multiple of the " +
                                                                        std::to_string(c.per_item_8) + " fragments"));
        s.local_size = 32;
        const std::vector<float> a = Shader(eight).shade(fb, s), b = Shader(sixteen).shade(fb, s);
        REQUIRE(a.size() == 300);
        CHECK(same_bits(a, b));
    }
}

// Sixteen lanes on a device of 8 (ModelInfo::lanes_avx2, Shader::lanes_for): the models registered with them are
// built with SL_MODEL_LANES=16 and launched with 16 fragments a chain, a work-group of one and a half work-items
// refused; their pixels are those of 8 lanes (SHADELAB_WIDE_LANES=0) and of a 16-lane device, bit for bit, in both
// modes. SHADELAB_WIDE_LANES=1 gives every model not of N and L only sixteen, and any other value is one line.
TEST_CASE("shade: sixteen lanes on an 8-lane device for the models registered with them", "[shade][vector_width]") {
    Runtime eight(RuntimeOptions{"", -1, "", "off", 8}), sixteen(RuntimeOptions{"", -1, "", "off", 16});
    const FragmentBuffer fb = random_fragments(100, 9);
    std::size_t wide = 0;
    for (const auto& info : model_catalogue()) {
        if (info.lanes_avx2 != 16) continue;
        ++wide;
        INFO("model " << info.name);
        const std::size_t chains = Shader::chains_for(info, 8), per_item = 16 * chains;
        REQUIRE(Shader::frags_per_item(info, 8) == per_item);
        const ProgramRequest req = shade_program(default_of(info.name), kOneDirectional, Precision::Precise, 8, true);
        CHECK(std::count(req.defines.begin(), req.defines.end(), "SL_MODEL_LANES=16") == 1);
        for (Precision p : {Precision::Precise, Precision::Fast}) {
            ShadeSetup s = setup_of(default_of(info.name), kOneDirectional, p);
            s.local_size = per_item + per_item / 2;
            REQUIRE_THROWS_WITH(Shader(eight).shade(fb, s),
                                Catch::Contains("multiple of the " + std::to_string(per_item) + " fragments"));
            s.local_size = 64;
            const std::vector<float> a = Shader(eight).shade(fb, s), b = Shader(sixteen).shade(fb, s);
            std::vector<float> c;
            {
                test::ScopedEnv env("SHADELAB_WIDE_LANES", "0");
                CHECK(Shader::frags_per_item(info, 8) == 8 * chains);
                c = Shader(eight).shade(fb, s);
            }
            REQUIRE(a.size() == 300);
            CHECK(same_bits(a, b));
            CHECK(same_bits(a, c));
        }
    }
    CHECK(wide >= 1);
    {
        test::ScopedEnv env("SHADELAB_WIDE_LANES", "1");
        for (const auto& info : model_catalogue())
            CHECK(Shader::lanes_for(info, 8) == (info.normals_only ? 8 : 16));
    }
    test::ScopedEnv env("SHADELAB_WIDE_LANES", "3");
    CHECK_THROWS_WITH(Shader::lanes_for(find_model("phong"), 8), Catch::Contains("SHADELAB_WIDE_LANES"));
}

// ModelInfo::normals_only is what decides a model's lanes (Shader::lanes_for) and bench_models' bytes a fragment;
// it must be true of the kernel: the same normals under another view and at other positions give the same pixels
// (a directional light, whose direction does not depend on the position). And it must be the whole truth: every
// model not marked depends on the view or the positions (minnaert_blender at darkness 0.5: its default, 1, is
// Lambert).
TEST_CASE("shade: the models marked normals-only are those whose pixels do not depend on the view or the positions",
          "[shade][vector_width]") {
    Runtime rt(RuntimeOptions{"", -1, "", "off"});
    Shader shader(rt);
    const FragmentBuffer a = random_fragments(1000, 21);
    FragmentBuffer b = random_fragments(1000, 22);   // other positions, a's normals
    b.nx = a.nx;
    b.ny = a.ny;
    b.nz = a.nz;
    std::size_t marked = 0;
    for (const auto& info : model_catalogue()) {
        INFO("model " << info.name << (info.normals_only ? " (marked normals-only)" : " (not marked)"));
        Material m = default_of(info.name);
        if (info.name == "minnaert_blender") m.params["darkness"] = 0.5;
        ShadeSetup sa = setup_of(m, kOneDirectional, Precision::Precise), sb = sa;
        sb.view = {-2.0, 1.0, 3.0, 1.0};
        const bool same = same_bits(shader.shade(a, sa), shader.shade(b, sb));
        CHECK(same == info.normals_only);
        CHECK(Shader::lanes_for(info.normals_only, 16) == (info.normals_only ? Shader::kNormalsOnlyLanes : 16));
        CHECK(Shader::lanes_for(info.normals_only, 4) == 4);
        CHECK(Shader::frags_per_item(info, 16) ==
              Shader::lanes_for(info.normals_only, 16) * std::size_t(info.chains > 1 ? 2 : 1));
        CHECK(Shader::lanes_for(info, 16) == Shader::lanes_for(info.normals_only, 16));
        CHECK(Shader::lanes_for(info, 8) == (info.lanes_avx2 == 16 ? 16 : 8));
        CHECK(Shader::lanes_for(info, 4) == 4);
        CHECK(Shader::frags_per_item(info, 8) == Shader::lanes_for(info, 8) * std::size_t(info.chains_avx2 > 1 ? 2 : 1));
        CHECK(Shader::frags_per_item(info, 1) == 1);   // no fragment loop at one lane: no second chain
        marked += info.normals_only ? 1 : 0;
    }
    CHECK(marked >= 8);   // Lambert, the wrap family, banded
}

// Two chains a work-item (kernels/common.cl, SL_CHAINS; ModelInfo::chains chooses per model): the loop interleaved
// twice over 2 x lanes fragments gives the pixels of one chain, bit for bit, for every model of the catalogue (and
// fast mode where it is other code), with a tail and two lights. SHADELAB_CHAINS sets the chains of every model,
// as for measuring the choice; a value of it other than 1 or 2 is refused with one line.
TEST_CASE("shade: two chains a work-item give one chain's pixels, bit for bit, for every model",
          "[shade][vector_width]") {
    Runtime rt(RuntimeOptions{"", -1, "", "off"});
    const FragmentBuffer fb = random_fragments(1000, 17);
    std::size_t compared = 0;
    for (const auto& info : model_catalogue())
        for (Precision p : {Precision::Precise, Precision::Fast}) {
            if (p == Precision::Fast && !fast_is_other_code(info)) continue;
            INFO("model " << info.name << ", " << precision_name(p) << ", device width " << rt.vector_width());
            const ShadeSetup s = setup_of(default_of(info.name), kDirectionalAndPoint, p);
            std::vector<float> one, two;
            {
                test::ScopedEnv env("SHADELAB_CHAINS", "1");
                CHECK(Shader::frags_per_item(info, 16) == Shader::lanes_for(info.normals_only, 16));
                one = Shader(rt).shade(fb, s);
            }
            {
                test::ScopedEnv env("SHADELAB_CHAINS", "2");
                CHECK(Shader::frags_per_item(info, 16) == 2 * Shader::lanes_for(info.normals_only, 16));
                two = Shader(rt).shade(fb, s);
            }
            REQUIRE(one.size() == 3 * fb.size());
            CHECK(same_bits(one, two));
            ++compared;
        }
    CHECK(compared > model_catalogue().size());
    test::ScopedEnv env("SHADELAB_CHAINS", "3");
    CHECK_THROWS_WITH(Shader::chains_for(model_catalogue().front(), 16),
                      Catch::Contains("SHADELAB_CHAINS is '3'") && Catch::Contains("use 1 or 2"));
}

// The launch's last work-items (kernels/shade_fragments.cl, `count`): a frame whose fragment count is not a
// multiple of the work-group is one launch, whose work-items past the end shade the last block of fragments again.
// Checked against the same fragments shaded on their own, at the start of a buffer of whole blocks (no block
// moved there) and, fewer than a work-item shades, through the padded second launch: bit for bit, at counts that
// end anywhere in a block and a work-group, for models of N and L only (8 lanes), with two chains, with a
// table, with children, and the dispatching program's kernel.
TEST_CASE("shade: a launch's last block, moved back to the end of the fragments, gives their own pixels",
          "[shade][stream]") {
    Runtime rt(RuntimeOptions{"", -1, "", "off"});
    const std::size_t lanes = rt.vector_width();
    std::size_t compared = 0;
    for (const char* name : {"lambert", "phong", "oren_nayar", "hapke_hen", "minnaert_empirical", "gradient"}) {
        const ModelInfo& info = find_model(name);
        const std::size_t per_item = Shader::frags_per_item(info, lanes);
        for (std::size_t n : {per_item, per_item + 1, 2 * per_item - 1, std::size_t(255), std::size_t(257),
                              std::size_t(1000), std::size_t(4109)}) {
            INFO("model " << name << ", " << n << " fragments, " << per_item << " a work-item");
            const FragmentBuffer fb = random_fragments(n, 41 + n);
            const ShadeSetup s = setup_of(default_of(name), kDirectionalAndPoint, Precision::Precise);
            test::ScopedEnv plain("SHADELAB_STREAM_STORES", "0");
            const std::vector<float> whole = Shader(rt).shade(fb, s);
            REQUIRE(whole.size() == 3 * n);
            // the last `m` fragments alone: m a multiple of the work-item's fragments (no block moved), and 3
            // (fewer than a work-item: the padded launch)
            for (std::size_t m : {std::min(n / per_item * per_item, 4 * per_item), std::min(std::size_t(3), n)}) {
                FragmentBuffer part;
                for (std::size_t i = n - m; i < n; ++i)
                    part.push_back(fb.px[i], fb.py[i], fb.pz[i], fb.nx[i], fb.ny[i], fb.nz[i], int(i), 1.0f);
                const std::vector<float> alone = Shader(rt).shade(part, s);
                REQUIRE(alone.size() == 3 * m);
                bool same = true;
                for (std::size_t c = 0; c < 3; ++c)
                    same = same && std::memcmp(alone.data() + c * m, whole.data() + c * n + (n - m),
                                               m * sizeof(float)) == 0;
                CHECK(same);
                ++compared;
            }
        }
    }
    CHECK(compared == 6 * 7 * 2);
    // The dispatching kernel (Shader::prepare_many) takes `count` too: its pixels are the model's own program's.
    const FragmentBuffer fb = random_fragments(1000, 7);
    const ShadeSetup s = setup_of(default_of("phong"), kDirectionalAndPoint, Precision::Precise);
    const std::vector<float> own = Shader(rt).shade(fb, s);
    Shader many(rt);
    many.prepare_many({s.material}, s.lights, s.precision, true);
    CHECK(same_bits(many.shade(fb, s), own));
}

// A fragment whose result has a non-finite channel (only from invalid input: here NaN and infinite normals and
// positions) is written black, all three channels 0 (kernels/common.cl, sl_finite_mask3), and its neighbours in
// the same vectors keep their own values, bit for bit. Lambert at a normal with N.y = +inf under the light from
// (1, 1, 1) is +inf (NoL = +inf), so those fragments must be black; a NaN normal gives NoL = NaN, which the
// model's max(NoL, 0) turns into 0 (the ambient term alone, finite): every model's output must be finite.
TEST_CASE("shade: a fragment with a non-finite result is written black, its neighbours unchanged", "[shade]") {
    Runtime rt(RuntimeOptions{"", -1, "", "off"});
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::size_t infinite[] = {17, 18, 299}, broken[] = {0, 17, 18, 40, 150, 299};
    for (const char* name : {"lambert", "phong", "oren_nayar", "hapke_hen", "cook_torrance"}) {
        INFO("model " << name);
        const FragmentBuffer good = random_fragments(300, 5);
        FragmentBuffer bad = good;
        for (std::size_t i : infinite) bad.ny[i] = inf;
        bad.nx[0] = nan;
        bad.nz[40] = -inf;
        bad.px[150] = nan;   // the point light's direction and the view direction from it
        const ShadeSetup s = setup_of(default_of(name), kOneDirectional, Precision::Precise);
        const std::vector<float> want = Shader(rt).shade(good, s), got = Shader(rt).shade(bad, s);
        REQUIRE(got.size() == want.size());
        const std::size_t n = good.size();
        std::size_t finite = 0, same = 0, black = 0;
        for (std::size_t i = 0; i < n; ++i) {
            bool zero = true, equal = true;
            for (std::size_t c = 0; c < 3; ++c) {
                finite += std::isfinite(got[c * n + i]) ? 1 : 0;
                zero = zero && got[c * n + i] == 0.0f;
                equal = equal && std::memcmp(&got[c * n + i], &want[c * n + i], sizeof(float)) == 0;
            }
            const bool is_broken = std::find(std::begin(broken), std::end(broken), i) != std::end(broken);
            const bool is_infinite = std::find(std::begin(infinite), std::end(infinite), i) != std::end(infinite);
            same += !is_broken && equal ? 1 : 0;
            black += is_infinite && zero ? 1 : 0;
        }
        CHECK(finite == 3 * n);
        CHECK(same == n - std::size(broken));
        if (std::string(name) == "lambert") CHECK(black == std::size(infinite));
    }
}

// Streaming stores (kernels/common.cl, sl_store_block; Shader::streams_output): with SHADELAB_STREAM_STORES=1 every
// launch streams its aligned blocks, and the body starts at the first fragment whose red output begins a 64-byte
// line, the fragments before it going with the tail into the padded second launch. The pixels are those of
// plain stores, bit for bit, for every model of the catalogue, at fragment counts that put the green and blue
// planes on and off a line boundary (4096: all three planes aligned alike; 4109: not), below one work-group and
// below one head (7). The default streams only outputs of kStreamOutputBytes or more; another value of the
// variable is refused with one line.
TEST_CASE("shade: streaming stores give plain stores' pixels, bit for bit, for every model and head/tail split",
          "[shade][stream]") {
    Runtime rt(RuntimeOptions{"", -1, "", "off"});
    std::size_t compared = 0;
    for (std::size_t n : {std::size_t(4109), std::size_t(4096), std::size_t(7)}) {
        const FragmentBuffer fb = random_fragments(n, 23 + n);
        for (const auto& info : model_catalogue()) {
            if (n != 4109 && !(info.name == "lambert" || info.name == "phong" || info.name == "oren_nayar" ||
                               info.name == "half_lambert"))
                continue;
            INFO("model " << info.name << ", " << n << " fragments, device width " << rt.vector_width());
            const ShadeSetup s = setup_of(default_of(info.name), kDirectionalAndPoint, Precision::Precise);
            std::vector<float> plain, streamed;
            {
                test::ScopedEnv env("SHADELAB_STREAM_STORES", "0");
                CHECK_FALSE(Shader::streams_output(n));
                plain = Shader(rt).shade(fb, s);
            }
            {
                test::ScopedEnv env("SHADELAB_STREAM_STORES", "1");
                CHECK(Shader::streams_output(n));
                Shader sh(rt);
                sh.shade_into(fb, s, streamed);
                REQUIRE(streamed.size() == 3 * n);
                CHECK(same_bits(plain, streamed));
                std::fill(streamed.begin(), streamed.end(), -1.0f);   // again into the reused (same) memory
                sh.shade_into(fb, s, streamed);
            }
            REQUIRE(plain.size() == 3 * n);
            CHECK(same_bits(plain, streamed));
            ++compared;
        }
    }
    CHECK(compared >= model_catalogue().size() + 8);
    {
        test::ScopedEnv env("SHADELAB_STREAM_STORES", "");
        CHECK_FALSE(Shader::streams_output(1 << 20));   // 12 MB of output: kept in the cache
        CHECK(Shader::streams_output((Shader::kStreamOutputBytes + 11) / 12));
        // a model registered with plain stores (ModelInfo::plain_stores) keeps them past the threshold; the others
        // stream there, and the variable still sets every model's
        const std::size_t big = (Shader::kStreamOutputBytes + 11) / 12;
        std::size_t plain_models = 0;
        for (const auto& info : model_catalogue()) {
            INFO("model " << info.name);
            CHECK(Shader::streams_output(info, big) == !info.plain_stores);
            CHECK_FALSE(Shader::streams_output(info, 1 << 20));
            // a work-item's block of whole 64-byte lines (16 or 32 floats) streams; 8 floats (half a line) or
            // one does not, except for the models of N and L only
            CHECK(Shader::streams_output(info, big, 16) == !info.plain_stores);
            CHECK(Shader::streams_output(info, big, 32) == !info.plain_stores);
            CHECK(Shader::streams_output(info, big, 8) == (info.normals_only && !info.plain_stores));
            CHECK(Shader::streams_output(info, big, 1) == (info.normals_only && !info.plain_stores));
            plain_models += info.plain_stores ? 1 : 0;
        }
        CHECK(find_model("hapke_leg").plain_stores);
        CHECK_FALSE(find_model("lambert").plain_stores);
        CHECK(plain_models < model_catalogue().size() / 2);
        test::ScopedEnv on("SHADELAB_STREAM_STORES", "1");
        CHECK(Shader::streams_output(find_model("hapke_leg"), 1));
        CHECK(Shader::streams_output(find_model("lambert"), 1, 8));   // the variable sets half-line blocks' too
    }
    test::ScopedEnv env("SHADELAB_STREAM_STORES", "yes");
    CHECK_THROWS_WITH(Shader::streams_output(1), Catch::Contains("SHADELAB_STREAM_STORES is 'yes'") &&
                                                     Catch::Contains("use 0 or 1"));
}
