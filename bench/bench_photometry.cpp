// bench_photometry: Hapke (HapkeHen with roughness, ISIS's unit-test parameters) evaluations per second on PoCL
// (kernels/photometry.cl, the `photometry eval` kernel) against a plain 2-thread C++ loop of the same formula in
// float, and against the single-threaded double reference; then a 5-parameter Hapke fit (photometry fit) of one
// 512x512 disc image; also the PoCL throughput of the other planetary laws on the same rows. Prints figures, asserts
// nothing about speed. Besides evaluations per (wall-clock) second, each PoCL row gives evaluations per CPU second
// of this process (PoCL's threads included), which a loaded machine changes much less: on an idle machine with
// 2 cores the wall-clock rate approaches twice it.
//   bench_photometry [--n N] [--smoke] [--baseline-kernels DIR [--baseline-width W]]
// --baseline-kernels times the laws' kernels built from another kernels/ folder as well, in the same run, for a
// before/after comparison (e.g. DIR from `git archive BASE kernels | tar -x -C SOMEWHERE`, then SOMEWHERE/kernels).
// The baseline runs --baseline-width rows a work-item (default 1: kernels from before SL_VECTOR_WIDTH, which
// evaluate one row a work-item whatever the width, are launched as they were).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <random>
#include <sys/resource.h>
#include <string>
#include <thread>
#include <vector>

#include "bench_util.hpp"
#include "cl/runtime.hpp"
#include "models/catalogue.hpp"
#include "moon/disc.hpp"
#include "moon/fit.hpp"
#include "photometry/fit.hpp"
#include "photometry/isis.hpp"
#include "reference/planetary_ref.hpp"

using namespace shadelab;
using clock_type = std::chrono::steady_clock;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Rows {
    std::vector<float> mu0, mu, si, se, cg, tg, tp;
    std::vector<photometry::Geometry> deg;
};

// Consistent geometries: cos i, cos e uniform in (0, 1], azimuth uniform in [0, 180].
Rows make_rows(std::size_t n) {
    std::mt19937_64 gen(1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Rows r;
    for (auto* v : {&r.mu0, &r.mu, &r.si, &r.se, &r.cg, &r.tg, &r.tp}) v->resize(n);
    r.deg.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const double c0 = 1.0 - u(gen), c1 = 1.0 - u(gen), psi = kPi * u(gen);
        const double s0 = std::sqrt(1 - c0 * c0), s1 = std::sqrt(1 - c1 * c1);
        const double cg = std::clamp(c0 * c1 + s0 * s1 * std::cos(psi), -1.0, 1.0), g = std::acos(cg);
        r.mu0[k] = float(c0);
        r.mu[k] = float(c1);
        r.si[k] = float(s0);
        r.se[k] = float(s1);
        r.cg[k] = float(cg);
        r.tg[k] = float(std::tan(0.5 * g));
        r.tp[k] = float(std::tan(0.5 * psi));
        r.deg[k] = {g * 180 / kPi, std::acos(c0) * 180 / kPi, std::acos(c1) * 180 / kPi};
    }
    return r;
}

// The C++ loop a user would write from Hapke (1981, 1984, 1986) in float, std:: functions, two lobes of HG.
struct HapkeParams {
    float w, b0, h, theta_deg, b, c;
};

float hapke_cpp(const HapkeParams& p, float mu0, float mu, float si, float se, float cg, float tg, float tp) {
    if (!(mu0 > 0 && mu > 0)) return 0.0f;
    const float pi = 3.14159265f, gamma = std::sqrt(1 - p.w);
    auto H = [&](float x) { return (1 + 2 * x) / (1 + 2 * x * gamma); };
    const float B = p.h > 0 ? p.b0 / (1 + tg / p.h) : 0.0f;
    const float b2 = p.b * p.b;
    const float P = (1 - p.c) * (1 - b2) / std::pow(1 + b2 + 2 * p.b * cg, 1.5f) +
                    p.c * (1 - b2) / std::pow(1 + b2 - 2 * p.b * cg, 1.5f);
    const float t = p.theta_deg * pi / 180, tan_t = std::tan(t), cot_t = 1 / tan_t;
    const float chi = 1 / std::sqrt(1 + pi * tan_t * tan_t);
    const float cot_i = mu0 / std::max(si, 1e-10f), cot_e = mu / std::max(se, 1e-10f);
    auto E1 = [&](float x) { return std::exp(-2 / pi * cot_t * x); };
    auto E2 = [&](float x) { return std::exp(-1 / pi * cot_t * cot_t * x * x); };
    const float psi = 2 * std::atan(tp), cpsi = std::cos(psi), s2 = std::sin(psi / 2) * std::sin(psi / 2);
    const float f = std::exp(-2 * tp);
    const float eta_i = chi * (mu0 + si * tan_t * E2(cot_i) / (2 - E1(cot_i)));
    const float eta_e = chi * (mu + se * tan_t * E2(cot_e) / (2 - E1(cot_e)));
    float mu0e, mue, q;
    if (mu0 >= mu) {
        const float den = 2 - E1(cot_e) - psi / pi * E1(cot_i);
        mu0e = chi * (mu0 + si * tan_t * (cpsi * E2(cot_e) + s2 * E2(cot_i)) / den);
        mue = chi * (mu + se * tan_t * (E2(cot_e) - s2 * E2(cot_i)) / den);
        q = chi * mu0 / eta_i;
    } else {
        const float den = 2 - E1(cot_i) - psi / pi * E1(cot_e);
        mu0e = chi * (mu0 + si * tan_t * (E2(cot_i) - s2 * E2(cot_e)) / den);
        mue = chi * (mu + se * tan_t * (cpsi * E2(cot_i) + s2 * E2(cot_e)) / den);
        q = chi * mu / eta_e;
    }
    const float S = mue / eta_e * mu0 / eta_i * chi / (1 - f + f * q);
    return p.w / 4 * mu0e / (mu0e + mue) * ((1 + B) * P - 1 + H(mu0e) * H(mue)) * S;
}

double seconds(clock_type::time_point a, clock_type::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// User + system CPU seconds of this process so far (all threads).
double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct KernelRun {
    double rate = 0.0;       // evaluations per second, best of 5 launches
    double cpu_rate = 0.0;   // evaluations per CPU second over the 5 launches
    std::vector<float> out;
};

// The `photometry eval` kernel (kernels/photometry.cl eval_photometric) for `law` on device-resident rows (build
// and upload excluded), 5 launches.
KernelRun run_kernel(Runtime& rt, const Rows& r, const photometry::Law& law) {
    const std::size_t n = r.mu0.size();
    // built and launched as `photometry eval` builds and launches it (its defines, its chains a work-item)
    cl::Program prog = rt.build("photometry.cl", photometry::pho_defines(law, Precision::Precise, false, rt.vector_width()));
    const auto consts = pack_material(law.material);
    std::vector<cl::Buffer> in;
    for (const auto* v : {&r.mu0, &r.mu, &r.si, &r.se, &r.cg, &r.tg, &r.tp})
        in.emplace_back(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(float),
                        const_cast<float*>(v->data()));
    cl::Buffer out(rt.context(), CL_MEM_WRITE_ONLY, n * sizeof(float));
    cl::Buffer bc(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, consts.size() * sizeof(ModelConsts),
                  const_cast<ModelConsts*>(consts.data()));
    cl::Kernel k(prog, "eval_photometric");
    for (cl_uint i = 0; i < 7; ++i) k.setArg(i, in[i]);
    k.setArg(7, out);
    k.setArg(8, cl_uint(n));
    k.setArg(9, bc);
    // make_rows pads to a multiple of 256 (the kernel has no bounds check); the first launch compiles
    photometry::enqueue_rows(rt, k, law, n, 256);
    rt.queue().finish();
    double best = 1e30;
    const double c0 = cpu_seconds();
    for (int rep = 0; rep < 5; ++rep) {
        const auto t0 = clock_type::now();
        photometry::enqueue_rows(rt, k, law, n, 256);
        rt.queue().finish();
        best = std::min(best, seconds(t0, clock_type::now()));
    }
    KernelRun run;
    run.cpu_rate = 5.0 * double(n) / std::max(1e-9, cpu_seconds() - c0);
    run.rate = double(n) / best;
    run.out.resize(n);
    rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, n * sizeof(float), run.out.data());
    return run;
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t n = std::size_t(1) << 24;
    bool smoke = false;
    std::string baseline_dir;
    CLI::App app{"bench_photometry: Hapke on PoCL against a 2-thread C++ loop and the double reference"};
    app.add_flag("--smoke", smoke, "Tiny run for the test suite (4096 geometries), no timing claims");
    std::size_t baseline_width = 1;
    app.add_option("--baseline-width", baseline_width, "Rows a work-item for the baseline's kernels (1, 2, 4, 8, 16)")
        ->check(CLI::IsMember({1, 2, 4, 8, 16}));
    app.add_option("--baseline-kernels", baseline_dir, "Also time the laws with the kernels of this folder (before/after)")
        ->check(CLI::ExistingDirectory);
    app.add_option("--n", n, "Geometries per run")->check(CLI::Range(std::size_t(256), std::size_t(1) << 28));
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);
        std::cerr << "bench_photometry: error: " << e.what() << " (see bench_photometry --help)\n";
        return 2;
    }
    if (smoke) n = 1 << 12;
    const HapkeParams hp{0.52f, 1.0f, 1.0f, 30.0f, 0.213f, 1.0f};
    const photometry::Law law = photometry::law_from_model(
        "hapke_hen", {{"wh", 0.52}, {"b0", 1.0}, {"hh", 1.0}, {"theta", 30.0}, {"hg1", 0.213}, {"hg2", 1.0}});
    n = (n + 255) / 256 * 256;
    const Rows r = make_rows(n);
    std::printf("bench_photometry: Hapke (HapkeHen, theta-bar 30, ISIS's unit-test parameters), %zu geometries\n"
                "cpu: %s\n",
                n, bench::cpu_name().c_str());

    Runtime rt;
    const KernelRun kr = run_kernel(rt, r, law);
    const std::vector<float>& k_out = kr.out;
    const double best_cl = double(n) / kr.rate;

    // The C++ loop on 2 threads, best of 5.
    std::vector<float> c_out(n);
    auto run = [&](std::size_t a, std::size_t b) {
        for (std::size_t j = a; j < b; ++j)
            c_out[j] = hapke_cpp(hp, r.mu0[j], r.mu[j], r.si[j], r.se[j], r.cg[j], r.tg[j], r.tp[j]);
    };
    double best_cpp = 1e30;
    for (int rep = 0; rep < 5; ++rep) {
        const auto t0 = clock_type::now();
        std::thread other(run, n / 2, n);
        run(0, n / 2);
        other.join();
        best_cpp = std::min(best_cpp, seconds(t0, clock_type::now()));
    }

    // The double reference, one thread, on the first min(n, 1M) rows.
    const std::size_t nr = std::min<std::size_t>(n, 1000000);
    double sink = 0.0;
    const auto t0 = clock_type::now();
    for (std::size_t j = 0; j < nr; ++j)
        sink += photometry::evaluate_reference(law, r.deg[j]);
    const double t_ref = seconds(t0, clock_type::now());

    double max_rel_k = 0.0, max_rel_c = 0.0;
    for (std::size_t j = 0; j < std::min<std::size_t>(nr, 20000); ++j) {
        const double ref = photometry::evaluate_reference(law, r.deg[j]);
        if (ref < 1e-4) continue;
        max_rel_k = std::max(max_rel_k, std::abs(k_out[j] - ref) / ref);
        max_rel_c = std::max(max_rel_c, std::abs(c_out[j] - ref) / ref);
    }
    const double cl_rate = double(n) / best_cl, cpp_rate = double(n) / best_cpp, ref_rate = double(nr) / t_ref;
    std::printf("%-44s %12s %10s %14s\n", "", "evals/s", "vs C++", "max rel (20k)");
    std::printf("%-44s %12.3g %10.2f %14.2g   (%.3g per CPU second)\n", "PoCL kernel (float)", cl_rate,
                cl_rate / cpp_rate, max_rel_k, kr.cpu_rate);
    std::printf("%-44s %12.3g %10.2f %14.2g\n", "C++ loop, float, 2 threads (-O3 -march=native)", cpp_rate, 1.0, max_rel_c);
    std::printf("%-44s %12.3g %10.2f %14s\n", "double reference, 1 thread", ref_rate, ref_rate / cpp_rate, "-");
    std::printf("PoCL vs double reference: %.1fx   (checksum %.6g)\n", cl_rate / ref_rate, sink);

    // The other laws' kernels on the same rows (ISIS's unit-test parameters where it has them).
    std::unique_ptr<Runtime> base_rt;
    if (!baseline_dir.empty())
        base_rt = std::make_unique<Runtime>(RuntimeOptions{"", -1, baseline_dir, "", baseline_width});
    std::printf("\nPoCL throughput of every photometric law on the same %zu rows%s:\n%-28s %12s %16s", n,
                base_rt ? " (this tree's kernels, then the baseline's)" : "", "law", "evals/s", "evals/CPU-s");
    if (base_rt) std::printf(" %14s %16s %8s", "baseline/s", "baseline/CPU-s", "speedup");
    std::printf("\n");
    const std::vector<std::pair<std::string, std::map<std::string, double>>> laws = {
        {"lommel_seeliger", {}},
        {"lunar_lambert", {{"l", 0.5}}},
        {"lunar_lambert_mcewen", {}},
        {"lunar_lambert_mcewen_ratio", {}},
        {"hapke_hen", {{"wh", 0.52}, {"b0", 1.0}, {"hh", 1.0}, {"theta", 30.0}, {"hg1", 0.213}, {"hg2", 1.0}}},
        {"hapke_leg", {{"wh", 0.52}, {"b0", 1.0}, {"hh", 1.0}, {"theta", 30.0}, {"bh", 0.0}, {"ch", 0.0}}},
        {"hapke_2012", {{"wh", 0.52}, {"b0", 1.0}, {"hh", 1.0}, {"theta", 30.0}, {"hg1", 0.213}, {"phi", 0.41},
                        {"bc0", 0.5}, {"hc", 0.05}}},
    };
    for (const auto& [name, params] : laws) {
        const photometry::Law l = photometry::law_from_model(name, params);
        const KernelRun run = run_kernel(rt, r, l);
        std::printf("%-28s %12.3g %16.3g", name.c_str(), run.rate, run.cpu_rate);
        if (base_rt) {
            const KernelRun before = run_kernel(*base_rt, r, l);
            std::printf(" %14.3g %16.3g %8.2f", before.rate, before.cpu_rate, run.cpu_rate / before.cpu_rate);
        }
        std::printf("\n");
    }

    // A 5-parameter Hapke fit (wh, b0, hh, theta, hg1) of one disc image, 512x512 (smoke: 64x64), phase 30.
    // (smoke: the --smoke flag above)
    moon::DiscRenderOptions o;
    o.width = o.height = smoke ? 64 : 512;
    o.disc = moon::Disc{0.5 * o.width, 0.5 * o.height, 0.47 * o.width};
    o.material = photometry::law_from_model(
        "hapke_hen", {{"wh", 0.25}, {"b0", 1.2}, {"hh", 0.08}, {"theta", 18.0}, {"hg1", 0.25}}).material;
    o.sun = moon::sun_geometry(30.0, 70.0);
    o.noise_sigma = 0.001;
    const Image img = moon::render_disc(rt, o);
    photometry::FitData d;
    d.images = 1;
    for (const auto& p : moon::disc_pixels(img, o.disc, o.sun)) {
        d.geometry.push_back({p.a.g_deg, p.a.i_deg, p.a.e_deg});
        d.value.push_back(p.I);
        d.image.push_back(0);
    }
    const photometry::FitResult f = photometry::fit_law(rt, d, {"hapke_hen", {}, {}});
    std::printf("Hapke fit, %dx%d image at phase 30 (%zu pixels), 5 parameters: %.2f s, %d iterations (%s), "
                "%zu evaluations at %.3g per second in the launches\n",
                o.width, o.height, d.value.size(), f.seconds, f.iterations, f.converged ? "converged" : "not converged",
                f.evaluations, double(f.evaluations) / f.kernel_seconds);
    return 0;
}
