// The house's shared pieces: the render path (host/pipeline/), the bounded Levenberg-Marquardt loop
// (host/core/lm.hpp), and the helpers of host/core (sizes, numbers, extensions, CSV).
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "core/lm.hpp"
#include "mesh/mesh.hpp"
#include "pipeline/pipeline.hpp"
#include "scene/scene.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

pipeline::JobMesh sphere_at(double x, const std::string& model, int level = 2) {
    Mesh m = make_icosphere(level);
    m.transform(glm::translate(glm::dmat4(1.0), glm::dvec3(x, 0.0, 0.0)));
    return pipeline::JobMesh{std::move(m), test::material(model), false};
}

pipeline::Job two_spheres_job(bool per_vertex, int width = 192, int height = 96) {
    pipeline::Job job;
    job.meshes.push_back(sphere_at(-1.2, "lambert"));
    job.meshes.push_back(sphere_at(1.2, "blinn_phong"));
    Bounds b;
    b.lo = glm::dvec3(-2.3, -1.1, -1.1);
    b.hi = glm::dvec3(2.3, 1.1, 1.1);
    job.camera = Camera::fit(b, glm::dvec3(0.0, 0.3, 1.0), 35.0, 2.0);
    job.width = width;
    job.height = height;
    job.lights = {Light{Light::Type::Directional, {1.0, 1.0, 1.0}, {1.0, 1.0, 1.0}, 1.0, 0.0}};
    job.ambient = glm::dvec3(0.02);
    job.per_vertex = per_vertex;
    return job;
}

// The same job with mesh `k` alone.
pipeline::Job alone(const pipeline::Job& job, std::size_t k) {
    pipeline::Job one = job;
    one.meshes = {job.meshes[k]};
    return one;
}

}  // namespace

// At 1280 x 640 the frame's fragments (about 70,000) are gathered and scattered in several chunks (one a thread,
// from 32K fragments on), and each chunk holds fragments of both meshes, row by row.
TEST_CASE("pipeline: each mesh of a merged job shades exactly as when rendered alone, per pixel and per vertex, "
          "on one chunk and on several",
          "[pipeline]") {
    Shader shader(test::runtime());
    for (const auto& [width, height, least] : {std::tuple{192, 96, 1000}, std::tuple{1280, 640, 40000}})
        for (bool per_vertex : {false, true}) {
            const pipeline::Job job = two_spheres_job(per_vertex, width, height);
            pipeline::StageTimes t;
            const pipeline::Frame frame = pipeline::raster(job, t);
            const Image both = pipeline::compose(job, frame, pipeline::shade(shader, job, frame, t), t);
            std::size_t compared = 0;
            for (std::size_t k = 0; k < 2; ++k) {
                const pipeline::Job one = alone(job, k);
                const pipeline::Frame f1 = pipeline::raster(one, t);
                const Image img = pipeline::compose(one, f1, pipeline::shade(shader, one, f1, t), t);
                // The spheres do not overlap on screen: every pixel one covers alone is that sphere's in the merge.
                for (std::size_t i = 0; i < f1.fb.size(); ++i) {
                    const std::size_t p = std::size_t(f1.fb.pixel[i]);
                    for (int c = 0; c < 4; ++c)
                        REQUIRE(both.pixels[p * 4 + std::size_t(c)] == img.pixels[p * 4 + std::size_t(c)]);
                    ++compared;
                }
            }
            CAPTURE(width, per_vertex);
            CHECK(compared == frame.fb.size());
            CHECK(compared > std::size_t(least));   // 1560 at 192 x 96: both spheres cover pixels
        }
}

TEST_CASE("pipeline: the merge of overlapping meshes keeps the nearest fragment of every pixel, the earlier mesh on "
          "a tie, as a per-pixel search over each mesh rasterised alone",
          "[pipeline]") {
    // Three spheres that overlap on screen, the second twice (every depth of the copy ties with the first's), and
    // one behind the camera (no fragments); 640x400 pixels: several threads' ranges and many of the merge's blocks.
    pipeline::Job job = two_spheres_job(false);
    job.meshes.insert(job.meshes.begin() + 1, sphere_at(0.0, "oren_nayar"));
    const pipeline::JobMesh copy_of_second = job.meshes[1];
    job.meshes.insert(job.meshes.begin() + 2, copy_of_second);
    job.meshes.push_back(sphere_at(0.0, "lambert"));   // its centre as far behind the eye as the target is before it
    job.meshes.back().mesh.transform(glm::translate(glm::dmat4(1.0), 2.0 * job.camera.eye - job.camera.target));
    job.width = 640;
    job.height = 400;
    for (const bool ids : {true, false}) {
        job.triangle_ids = ids;
        pipeline::StageTimes t;
        const pipeline::Frame frame = pipeline::raster(job, t);
        // the reference: every mesh alone, then per pixel the least depth, the first mesh that has it
        const std::size_t npix = std::size_t(job.width) * std::size_t(job.height);
        std::vector<float> best(npix, std::numeric_limits<float>::infinity());
        std::vector<int> mesh(npix, -1);
        std::vector<std::size_t> index(npix, 0);
        std::vector<pipeline::Frame> alone_frames;
        for (std::size_t k = 0; k < job.meshes.size(); ++k) {
            alone_frames.push_back(pipeline::raster(alone(job, k), t));
            const FragmentBuffer& f = alone_frames.back().fb;
            for (std::size_t i = 0; i < f.size(); ++i) {
                const std::size_t p = std::size_t(f.pixel[i]);
                if (f.depth[i] < best[p]) {
                    best[p] = f.depth[i];
                    mesh[p] = int(k);
                    index[p] = i;
                }
            }
        }
        CAPTURE(ids);
        REQUIRE(alone_frames.back().fb.size() == 0);   // the sphere behind the camera
        std::size_t covered = 0, second = 0, copy = 0;
        for (std::size_t p = 0; p < npix; ++p) {
            if (mesh[p] < 0) continue;
            REQUIRE(covered < frame.fb.size());
            const FragmentBuffer& f = alone_frames[std::size_t(mesh[p])].fb;
            const std::size_t i = index[p], k = covered++;
            REQUIRE(std::size_t(frame.fb.pixel[k]) == p);   // in pixel order, every covered pixel once
            REQUIRE(int(frame.mesh_of[k]) == mesh[p]);
            REQUIRE((frame.fb.depth[k] == f.depth[i] && frame.fb.px[k] == f.px[i] && frame.fb.py[k] == f.py[i] &&
                     frame.fb.pz[k] == f.pz[i] && frame.fb.nx[k] == f.nx[i] && frame.fb.ny[k] == f.ny[i] &&
                     frame.fb.nz[k] == f.nz[i]));
            if (ids) {
                REQUIRE((frame.fb.triangle[k] == f.triangle[i] && frame.fb.b1[k] == f.b1[i] &&
                         frame.fb.b2[k] == f.b2[i]));
            }
            second += mesh[p] == 1 ? 1 : 0;
            copy += mesh[p] == 2 ? 1 : 0;
        }
        CHECK(covered == frame.fb.size());
        CHECK(frame.fb.triangle.size() == (ids ? covered : 0));
        CHECK(second > 1000);   // the middle sphere is in front of the others where they overlap
        CHECK(copy == 0);       // its copy ties everywhere and loses
    }
}

TEST_CASE("pipeline: per vertex differs from per pixel on a coarse sphere, and the AOVs hold depth and normal",
          "[pipeline]") {
    Shader shader(test::runtime());
    pipeline::Job pix = two_spheres_job(false), pv = two_spheres_job(true);
    pipeline::StageTimes t;
    const pipeline::Frame f = pipeline::raster(pix, t);
    const auto a = pipeline::shade(shader, pix, f, t), b = pipeline::shade(shader, pv, f, t);
    double max_diff = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) max_diff = std::max(max_diff, double(std::abs(a[i] - b[i])));
    CHECK(max_diff > 1e-3);   // Gouraud on a level-2 icosphere misses the highlight

    const auto scratch = test::scratch_dir("pipeline_aov");
    pix.outputs.colour = {(scratch / "c.exr").string()};
    pix.outputs.depth = (scratch / "d.exr").string();
    pix.outputs.normal = (scratch / "n.exr").string();
    const auto images = pipeline::resolve(pix, f, a, t);
    REQUIRE(images.size() == 3);
    const Image& depth = images[1].linear;
    const Image& normal = images[2].linear;
    REQUIRE(depth.channels == 1);
    REQUIRE(normal.channels == 4);
    std::size_t covered = 0;
    for (std::size_t i = 0; i < f.fb.size(); ++i) {
        const std::size_t p = std::size_t(f.fb.pixel[i]);
        REQUIRE(depth.pixels[p] == f.fb.depth[i]);
        REQUIRE(depth.pixels[p] > 0.0f);
        REQUIRE(normal.pixels[p * 4] == f.fb.nx[i]);
        REQUIRE(normal.pixels[p * 4 + 3] == 1.0f);
        ++covered;
    }
    CHECK(covered == f.fb.size());
    pipeline::write(images, t);
    for (const auto& o : pix.outputs.all()) CHECK(std::filesystem::exists(o));
    CHECK(t.raster_ms > 0.0);
    CHECK(t.kernel_ms > 0.0);
    CHECK(t.write_ms > 0.0);
    CHECK(pipeline::describe(t).find("resolve") != std::string::npos);
}

// y = A exp(-k x) + c on 200 points; the loop must find (A, k, c) from starts all over the box, and hold a
// coordinate on its bound when the optimum lies beyond it.
namespace {
struct ExpFit {
    std::vector<double> xs, ys;
    std::vector<double> x;   // the current point (A, k, c)
    std::vector<std::vector<double>> proposed, evaluated;
    std::vector<double> lo, hi;

    static double f(const std::vector<double>& p, double x) { return p[0] * std::exp(-p[1] * x) + p[2]; }
    double cost(const std::vector<double>& p) const {
        double s = 0.0;
        for (std::size_t i = 0; i < xs.size(); ++i) s += (f(p, xs[i]) - ys[i]) * (f(p, xs[i]) - ys[i]);
        return s;
    }
    lm::Outcome run(std::vector<double> start) {
        x = std::move(start);
        lm::Settings s;
        s.trials = [](double l) { return std::vector<double>{l / 10.0, l, l * 10.0}; };
        s.attempts = 8;
        s.retry_next_iteration = true;
        s.max_iterations = 2000;
        lm::Callbacks cb;
        cb.normal = [this](lm::Normal& ne) {
            ne.A.assign(9, 0.0);
            ne.g.assign(3, 0.0);
            for (std::size_t i = 0; i < xs.size(); ++i) {
                const double e = std::exp(-x[1] * xs[i]);
                const double J[3] = {e, -x[0] * xs[i] * e, 1.0};
                const double r = f(x, xs[i]) - ys[i];
                for (int a = 0; a < 3; ++a) {
                    ne.g[std::size_t(a)] -= J[a] * r;
                    for (int b = 0; b < 3; ++b) ne.A[std::size_t(a * 3 + b)] += J[a] * J[b];
                }
            }
            ne.x = x;
            ne.lo = lo;
            ne.hi = hi;
            ne.bounded.assign(3, true);
        };
        cb.propose = [this](const std::vector<double>& y) {
            if (y == x) return false;
            proposed.push_back(y);
            return true;
        };
        cb.evaluate = [this] {
            evaluated = std::move(proposed);
            proposed.clear();
            std::vector<double> c;
            for (const auto& p : evaluated) c.push_back(cost(p));
            return c;
        };
        cb.accept = [this](std::size_t i) {
            x = evaluated[i];
            return cost(x);
        };
        cb.converged = [](double before, double after) { return before - after <= 1e-14 * before; };
        return lm::minimise(s, cb, cost(x));
    }
};
}  // namespace

TEST_CASE("lm: the bounded loop recovers y = A exp(-k x) + c from 50 starts over the box, and stops on a bound",
          "[lm]") {
    ExpFit p;
    const std::vector<double> truth{2.0, 1.3, 0.25};
    for (int i = 0; i < 200; ++i) {
        p.xs.push_back(0.025 * i);
        p.ys.push_back(ExpFit::f(truth, p.xs.back()));
    }
    p.lo = {0.0, 0.0, -1.0};
    p.hi = {10.0, 10.0, 1.0};
    std::mt19937 g(7);
    std::uniform_real_distribution<double> A(0.1, 10.0), k(0.05, 5.0), c(-1.0, 1.0);
    double worst = 0.0;
    for (int s = 0; s < 50; ++s) {
        const std::vector<double> start{A(g), k(g), c(g)};
        const lm::Outcome o = p.run(start);
        CAPTURE(start[0], start[1], start[2], o.iterations, p.x[0], p.x[1], p.x[2]);
        CHECK(o.converged);
        for (int j = 0; j < 3; ++j) worst = std::max(worst, std::abs(p.x[std::size_t(j)] - truth[std::size_t(j)]));
        CHECK(o.cost <= 1e-16);
    }
    CAPTURE(worst);
    CHECK(worst < 1e-6);

    // c held at most 0.1 while the data want 0.25: the fit ends on c = 0.1 exactly and beats every nearby c.
    p.hi[2] = 0.1;
    const lm::Outcome o = p.run({1.0, 1.0, 0.0});
    CHECK(o.converged);
    CHECK(p.x[2] == 0.1);
    for (double dc : {-1e-3, -1e-2}) {
        std::vector<double> q = p.x;
        q[2] += dc;
        CHECK(p.cost(q) > o.cost);
    }
}

TEST_CASE("lm: solve refuses singular and non-finite systems and solves a pivoting one", "[lm]") {
    std::vector<double> x;
    CHECK_FALSE(lm::solve({1.0, 2.0, 2.0, 4.0}, {1.0, 2.0}, 2, x));
    CHECK_FALSE(lm::solve({0.0, 0.0, 0.0, 0.0}, {1.0, 2.0}, 2, x));
    REQUIRE(lm::solve({1.0, 2.0, 3.0, 4.0}, {5.0, 6.0}, 2, x, 0.0));   // pivots on the 3
    CHECK_THAT(x[0], Catch::Matchers::WithinAbs(-4.0, 1e-14));
    CHECK_THAT(x[1], Catch::Matchers::WithinAbs(4.5, 1e-14));
}

TEST_CASE("format: sizes, numbers and extensions, one line naming the option for every bad size", "[format]") {
    const ImageSize s = parse_size("640x480", "--size", 1, 16384);
    CHECK(s.width == 640);
    CHECK(s.height == 480);
    CHECK(parse_size("8X8", "--size", 8, 16).width == 8);
    for (const char* bad : {"", "640", "640x", "x480", "640x480x2", "640*480", "abc", "640x480 "}) {
        CAPTURE(bad);
        try {
            parse_size(bad, "--size", 1, 16384);
            FAIL("accepted");
        } catch (const Error& e) {
            CHECK(std::string(e.what()).find("--size expects WIDTHxHEIGHT") == 0);
        }
    }
    for (const char* out : {"0x10", "10x0", "7x8", "17x8"}) {
        CAPTURE(out);
        try {
            parse_size(out, "--size", 8, 16);
            FAIL("accepted");
        } catch (const Error& e) {
            CHECK(std::string(e.what()) == std::string("--size ") + out + ": each side must be in [8, 16]");
        }
    }
    CHECK(num(1.0 / 3.0) == "0.333333");
    CHECK(num(1e6) == "1e+06");
    CHECK(num(2.5, 2) == "2.5");
    CHECK(fixed(3.14159, 2) == "3.14");
    CHECK(fixed(2.0, 0) == "2");
    CHECK(lower_ext("a/B.PNG") == ".png");
    CHECK(lower_ext("dir.d/file") == "");
}

TEST_CASE("csv: RFC 4180 quoting where asked, words kept free of separators, no NaN or Inf written", "[csv]") {
    CsvTable t({"a", "b", "c", "d"});
    t.row().add_quoted("x,y \"q\"").add("w,o\"rd").add_fixed(1.23456, 3).add_count(42);
    CHECK(t.text() == "a,b,c,d\n\"x,y \"\"q\"\"\",w;o;rd,1.235,42\n");
    t.row();
    CHECK_THROWS_AS(t.add(std::numeric_limits<double>::quiet_NaN()), Error);
    CHECK_THROWS_AS(t.add_fixed(std::numeric_limits<double>::infinity(), 2), Error);
    const auto dir = test::scratch_dir("csv");
    CHECK_THROWS_AS(t.write((dir / "short_row.csv").string()), Error);   // the second row has no field
}

TEST_CASE("scene: per_vertex reaches the batch's job, and a non-boolean is refused naming the key", "[pipeline][scene]") {
    nlohmann::json doc = {{"meshes", {{{"path", test::kMeshes + "/spot.obj"}}}}, {"per_vertex", true}};
    CHECK(parse_scene(doc, "inline.json").per_vertex);
    doc.erase("per_vertex");
    CHECK_FALSE(parse_scene(doc, "inline.json").per_vertex);
    doc["per_vertex"] = 1;
    try {
        parse_scene(doc, "inline.json");
        FAIL("accepted");
    } catch (const Error& e) {
        CHECK(std::string(e.what()) == "scene 'inline.json': per_vertex: expected true or false, got number 1");
    }
}
