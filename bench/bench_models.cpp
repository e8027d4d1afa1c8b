// Throughput of every model in every precision mode (issue #6, #13), as ratios measured in one run:
//   of STREAM the model's bandwidth against STREAM's triad on PoCL (kernels/bench/stream.cl: a[i] = b[i] + s c[i],
//            size_t index, no bounds check, arrays of the same length as the model's planes). The model's
//            bandwidth counts the bytes it needs: the normals (12 bytes) and the 3 output planes (12), plus the
//            positions (12) where the model reads the view vector or the position (perspective view: V depends on
//            P). STREAM copy and triad are printed for every size and re-timed before every row, so a change in
//            machine load between rows does not skew the ratio.
//   x C++    against a plain 2-thread C++ loop of the same formula in float with <cmath>, -O3 -march=native
//            (bench/cpp_loops.hpp; a representative of every family). The loop's output is checked against the
//            kernel's (max relative difference printed), so a wrong loop shows.
//   x ref    against the scalar double reference (host/reference/), single-threaded, on a subset.
//   vec      whether PoCL's work-item loop vectoriser widened the kernel, and to what width: read from the
//            LLVM remarks PoCL prints with POCL_VECTORIZER_REMARKS=1 while it compiles the kernel (the kernel
//            cache is switched off for that, POCL_KERNEL_CACHE=0, so every program is really compiled; --no-vec
//            skips it). "8" = vectorised 8 wide; "no: <reason>" = LLVM's reason for running one fragment at a time.
// Targets (figures, never assertions; issue #13): cheap models (lambert, half_lambert, banded, toon) >= 0.8 of
// STREAM; every model >= 0.25 of STREAM at 16M fragments; models that call transcendental functions, in
// precise mode, >= 5x the C++ loop; fast mode >= 1.3x precise where the two modes are different programs and
// never slower where they are the same code. A missed target prints "MISS: <value>, target <target>".
//
// What shapes the kernels here (measured on PoCL 3.1 / LLVM 15, CPU driver): PoCL's work-item loop vectoriser
// rejects every vector-typed instruction and every call it cannot widen, so the models are written float3-free
// (sl_v3 and sl_rgb in kernels/common.cl) and the trigonometric built-ins are common.cl's own polynomials.
//
// usage: bench_models [--smoke | --quick] [--sizes 1M,4M,16M] [--models a,b] [--modes precise,fast]
//                     [--repeats N] [--local N|auto] [--local-sizes] [--no-vec] [--csv FILE]
// Default sizes 1M, 4M, 16M fragments; --quick 1M; --smoke tiny (ctest bench.smoke: checks it runs, no timing).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <cstdlib>
#include <unistd.h>

#include "bench_util.hpp"
#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "cpp_loops.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"

using namespace shadelab;
using clock_type = std::chrono::steady_clock;

namespace {

// Models with no transcendental call in their kernel (only + - * /, sqrt, rsqrt, floor, clamp): the 0.8 target.
const std::set<std::string> kCheap = {"lambert", "half_lambert", "banded", "toon"};
// Models whose kernel calls pow, exp, sin, cos, tan, acos or atan2 (found by following every eval function
// through its helpers in kernels/models/*.cl): the ">= 5x the C++ loop in precise mode" target.
const std::set<std::string> kTranscendental = {
    "toon", "cook_torrance", "cook_torrance_exact_fresnel", "cook_torrance_seed004", "gradient", "minnaert_1941",
    "minnaert_unity", "minnaert_blender", "minnaert_b", "minnaert_normalized", "oren_nayar_full",
    "oren_nayar_blender", "eon", "phong", "phong_seed001", "phong_normalized", "blinn_phong", "blinn_phong_seed001",
    "blinn_phong_normalized", "blinn_phong_normalized_approx"};
// Models whose value depends on N and L only (no V, no P: `(void)V; (void)P;` in their eval): they need the
// normals and the output, 24 bytes a fragment; every other model also reads the position (36 bytes).
const std::set<std::string> kNormalsOnly = {"lambert", "half_lambert", "half_lambert_seed001", "wrap",
                                            "wrap_seed001", "wrap_energy", "banded", "banded_seed001"};
constexpr double kCheapTarget = 0.8, kStreamTarget = 0.25, kCppTarget = 5.0, kFastTarget = 1.3;
// The 0.25-of-STREAM target is set for 16M fragments (the size): smaller sizes partly run from cache.
constexpr std::size_t kStreamTargetSize = std::size_t(1) << 24;

double bytes_per_fragment(const std::string& model) { return kNormalsOnly.count(model) ? 24.0 : 36.0; }

struct Options {
    std::vector<std::size_t> sizes = {1u << 20, 1u << 22, 1u << 24};
    std::vector<std::string> models;   // empty: all
    std::vector<Precision> modes = {Precision::Precise, Precision::Fast};
    int repeats = 3;
    bool smoke = false;
    bool local_study = false;
    bool vec_report = true;
    std::size_t local = 0;             // 0: Shader's default
    std::string csv;
};

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream in(s);
    std::string item;
    while (std::getline(in, item, ','))
        if (!item.empty()) out.push_back(item);
    return out;
}

std::size_t parse_count(const std::string& s) {
    std::size_t pos = 0;
    const double v = std::stod(s, &pos);
    double mult = 1.0;
    if (pos < s.size() && (s[pos] == 'M' || s[pos] == 'm')) mult = double(1u << 20), ++pos;
    else if (pos < s.size() && (s[pos] == 'K' || s[pos] == 'k')) mult = 1024.0, ++pos;
    if (pos != s.size() || !(v > 0)) throw Error("'" + s + "' is not a fragment count (e.g. 4096, 1M, 16M)");
    return std::size_t(v * mult);
}

std::string size_label(std::size_t n) {
    if (n % (1u << 20) == 0) return std::to_string(n >> 20) + "M";
    return std::to_string(n);
}

FragmentBuffer random_fragments(std::size_t n) {
    std::mt19937_64 g(1);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    FragmentBuffer fb;
    fb.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        float x, y, z, l;
        do { x = u(g); y = u(g); z = u(g); l = x * x + y * y + z * z; } while (l > 1.0f || l < 1e-4f);
        l = std::sqrt(l);
        fb.px[i] = x; fb.py[i] = y; fb.pz[i] = z;
        fb.nx[i] = x / l; fb.ny[i] = y / l; fb.nz[i] = z / l;
        fb.pixel[i] = int(i); fb.depth[i] = 1.0f;
    }
    return fb;
}

// STREAM copy and triad (kernels/bench/stream.cl) on device arrays of n floats, re-timed on demand (best of
// `repeats`). GB/s as STREAM counts them: 8 bytes per element for copy, 12 for triad.
class Stream {
public:
    Stream(Runtime& rt, std::size_t n) : rt_(rt), n_(round_up(n)) {
        prog_ = rt.build("bench/stream.cl", {});
        copy_ = cl::Kernel(prog_, "stream_copy");
        triad_ = cl::Kernel(prog_, "stream_triad");
        const std::size_t bytes = n_ * sizeof(float);
        for (auto& b : buf_) {
            b = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, bytes);
            rt.queue().enqueueFillBuffer(b, 1.0f, 0, bytes);   // touched once, before any timing
        }
        rt.queue().finish();
        copy_.setArg(0, buf_[0]);
        copy_.setArg(1, buf_[2]);
        triad_.setArg(0, buf_[0]);
        triad_.setArg(1, buf_[1]);
        triad_.setArg(2, buf_[2]);
        triad_.setArg(3, 3.0f);
    }
    double copy_gbs(int repeats, std::size_t local = Shader::kLocalSize) { return 8.0 * n_ / best_ms(copy_, repeats, local) * 1e-6; }
    double triad_gbs(int repeats, std::size_t local = Shader::kLocalSize) { return 12.0 * n_ / best_ms(triad_, repeats, local) * 1e-6; }

private:
    static std::size_t round_up(std::size_t n) { return (n + Shader::kLocalSize - 1) / Shader::kLocalSize * Shader::kLocalSize; }
    double best_ms(cl::Kernel& k, int repeats, std::size_t local) {
        double best = 1e30;
        for (int r = 0; r < repeats; ++r) {
            cl::Event ev;
            rt_.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n_),
                                             local == Shader::kLocalAuto ? cl::NullRange : cl::NDRange(local), nullptr,
                                             &ev);
            ev.wait();
            best = std::min(best, double(ev.getProfilingInfo<CL_PROFILING_COMMAND_END>() -
                                         ev.getProfilingInfo<CL_PROFILING_COMMAND_START>()) * 1e-6);
        }
        return best;
    }
    Runtime& rt_;
    std::size_t n_;
    cl::Program prog_;
    cl::Kernel copy_, triad_;
    cl::Buffer buf_[3];
};

// What the process writes to stdout and stderr (file descriptors 1 and 2) while f runs. PoCL's LLVM prints its
// optimisation remarks from inside the library (to stdout on PoCL 3.1), so they can only be caught at the
// descriptors.
template <class F>
std::string capture_output(F&& f) {
    std::cout.flush();
    std::fflush(stdout);
    std::fflush(stderr);
    std::FILE* tmp = std::tmpfile();
    if (!tmp) { f(); return ""; }
    const int saved_out = dup(1), saved_err = dup(2);
    dup2(fileno(tmp), 1);
    dup2(fileno(tmp), 2);
    auto restore = [&] {
        std::fflush(stdout);
        std::fflush(stderr);
        dup2(saved_out, 1);
        dup2(saved_err, 2);
        close(saved_out);
        close(saved_err);
    };
    try {
        f();
    } catch (...) {
        restore();
        std::fclose(tmp);
        throw;
    }
    restore();
    std::string text;
    std::rewind(tmp);
    char chunk[4096];
    std::size_t got;
    while ((got = std::fread(chunk, 1, sizeof chunk, tmp)) > 0) text.append(chunk, got);
    std::fclose(tmp);
    return text;
}

// The loop vectoriser's verdict from PoCL's remarks for one kernel compilation: "8" when every work-item loop
// it reports on was vectorised 8 wide; "no: <first reason>" when none was; "8/no: <reason>" when some were
// ("?" if it printed no remark on a loop, e.g. the kernel came from a cache).
std::string vectoriser_verdict(const std::string& remarks) {
    std::set<std::string> widths;
    std::string reason;
    const std::string vec = "vectorized loop (vectorization width: ", novec = "loop not vectorized: ";
    for (std::size_t p = remarks.find(vec); p != std::string::npos; p = remarks.find(vec, p + 1)) {
        const std::size_t q = p + vec.size();
        widths.insert(remarks.substr(q, remarks.find_first_not_of("0123456789", q) - q));
    }
    const std::size_t p = remarks.find(novec);
    if (p != std::string::npos) {
        const std::size_t q = p + novec.size();
        reason = remarks.substr(q, std::min(remarks.find("<unknown>", q), remarks.find('\n', q)) - q);
        while (!reason.empty() && (reason.back() == ' ' || reason.back() == '\n')) reason.pop_back();
    }
    std::string w;
    for (const auto& x : widths) w += (w.empty() ? "" : ",") + x;
    if (w.empty() && reason.empty()) return "?";
    if (reason.empty()) return w;
    return (w.empty() ? "" : w + "/") + "no: " + reason;
}

Material default_material(const ModelInfo& info) {
    Material m;
    m.model = info.name;
    for (int c = 0; c < info.children; ++c) m.children.push_back(Material{});
    return resolve_material(m);
}

const glm::dvec3 kLdir = glm::normalize(glm::dvec3(0.3, 0.8, 0.5));
const glm::dvec3 kEye(0.5, 1.0, 4.0);

ShadeSetup setup_for(const Material& m, Precision p, std::size_t local) {
    ShadeSetup s;
    s.material = m;
    s.lights = {Light{Light::Type::Directional, kLdir, {1, 1, 1}, 1.0, 0.0}};
    s.view = glm::dvec4(kEye, 1.0);
    s.precision = p;
    s.local_size = local;
    return s;
}

// Best kernel time of `repeats` shade() calls; `out` receives the last output.
double shade_best_ms(Shader& shader, const FragmentBuffer& fb, const ShadeSetup& s, int repeats, std::vector<float>& out) {
    double best = 1e30;
    for (int r = 0; r < repeats; ++r) {
        ShadeTiming t;
        out = shader.shade(fb, s, &t);
        best = std::min(best, t.kernel_ms);
    }
    return best;
}

// The scalar double reference, single-threaded, on the first nref fragments: fragments per second.
double reference_fps(const Material& m, const FragmentBuffer& fb, std::size_t nref, bool& finite) {
    const auto t0 = clock_type::now();
    double sink = 0.0;
    for (std::size_t i = 0; i < nref; ++i) {
        const glm::dvec3 P{fb.px[i], fb.py[i], fb.pz[i]}, N{fb.nx[i], fb.ny[i], fb.nz[i]};
        sink += ref::eval_material(N, kLdir, glm::normalize(kEye - P), P, m).y;
    }
    finite = finite && std::isfinite(sink);
    return double(nref) / std::chrono::duration<double>(clock_type::now() - t0).count();
}

struct LoopResult {
    double ms = 0.0;
    double max_rel = 0.0;      // max |loop - kernel| / |kernel| over values >= 1e-3 of the peak
    double share_off = 0.0;    // share of those values off by more than 1e-3 (band flips in banded/toon)
};

// The plain C++ loop: best time of `repeats` runs over 2 threads, and its agreement with the kernel output.
LoopResult cpp_loop(const Material& m, const FragmentBuffer& fb, const std::vector<float>& kernel_out, int repeats) {
    cpp_loops::Mat mat{};
    for (int c = 0; c < 3; ++c) {
        mat.albedo[c] = float(m.albedo[c]);
        mat.specular[c] = float(m.specular[c]);
    }
    mat.params = m.params;
    const std::size_t n = fb.size();
    std::vector<float> out(3 * n);
    const cpp_loops::Vec3 L{float(kLdir.x), float(kLdir.y), float(kLdir.z)}, eye{float(kEye.x), float(kEye.y), float(kEye.z)};
    LoopResult r;
    r.ms = 1e30;
    for (int rep = 0; rep < repeats; ++rep) {
        const auto t0 = clock_type::now();
        cpp_loops::run(m.model, mat, fb.px.data(), fb.py.data(), fb.pz.data(), fb.nx.data(), fb.ny.data(), fb.nz.data(),
                       n, L, eye, out.data(), 2);
        r.ms = std::min(r.ms, std::chrono::duration<double, std::milli>(clock_type::now() - t0).count());
    }
    double peak = 0.0;
    for (float v : kernel_out) peak = std::max(peak, double(std::fabs(v)));
    std::size_t counted = 0, off = 0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const double k = kernel_out[i];
        if (std::fabs(k) < 1e-3 * peak) continue;
        const double rel = std::isfinite(out[i]) ? std::fabs(double(out[i]) - k) / std::fabs(k) : 1e30;
        ++counted;
        if (rel > 1e-3) ++off;
        r.max_rel = std::max(r.max_rel, rel);
    }
    r.share_off = counted ? double(off) / double(counted) : 0.0;
    return r;
}

std::string fixed(double v, int digits) {
    std::ostringstream o;
    o << std::fixed << std::setprecision(digits) << v;
    return o.str();
}

struct Row {
    std::size_t n;
    std::string model, mode;
    double mfps, gbs, of_stream, x_cpp, x_ref;   // x_cpp < 0: no loop
    double x_precise;                            // fast rows: fast / precise Mfrag/s (< 0: not measured)
    std::string vec, target, verdict;
};

// Models whose fast build can be a different computation from the precise one: they call pow (fast:
// sl_fast_pow, plain float; precise: sl_pow, float-float), unless the device is one where both modes use
// sl_pow_cr (kernels/common.cl, SL_FAST_POW_SAME: 512-bit vector devices), which fast_pow_differs() asks the
// device. Every other mapping of SL_FAST is the same code on PoCL's CPU driver (native_exp, _log, _sqrt, _rsqrt
// are its full functions; the trigonometry is common.cl's own in both modes), so elsewhere fast mode can only
// be "not slower".
const std::set<std::string> kFastDiffers = {
    "toon", "minnaert_1941", "minnaert_unity", "minnaert_blender", "minnaert_b", "minnaert_normalized", "phong",
    "phong_seed001", "phong_normalized", "blinn_phong", "blinn_phong_seed001", "blinn_phong_normalized",
    "blinn_phong_normalized_approx"};
bool g_fast_pow_differs = true;   // set in main from the device

// Whether fast mode's pow is another function than precise mode's on this device (common.cl's SL_FAST_POW_SAME).
bool fast_pow_differs(Runtime& rt) {
    const char* src = "#include \"common.cl\"\n__kernel void f(__global int* o) {\n#ifdef SL_FAST_POW_SAME\n"
                      "o[0] = 0;\n#else\no[0] = 1;\n#endif\n}\n";
    cl::Program p(rt.context(), src);
    const std::string opts = "-cl-std=CL1.2 -I " + rt.kernel_dir() + " -DSL_FAST=1 " + Shader::options_for(Precision::Fast);
    p.build({rt.device()}, opts.c_str());
    cl::Buffer b(rt.context(), CL_MEM_WRITE_ONLY, sizeof(cl_int));
    cl::Kernel k(p, "f");
    k.setArg(0, b);
    rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1), cl::NullRange);
    cl_int v = 0;
    rt.queue().enqueueReadBuffer(b, CL_TRUE, 0, sizeof v, &v);
    return v != 0;
}

// "Not slower" allows for the timing noise of a shared machine: two builds of the same code measured 0.93-1.07x
// of each other in one run, so below 0.9x is a miss.
constexpr double kSameCodeFloor = 0.9;

// Targets that apply to a row, and the verdict ("ok" or every miss with its size).
void judge(Row& row, bool precise) {
    std::vector<std::string> targets, misses;
    const bool cheap = kCheap.count(row.model) > 0;
    if (cheap || row.n >= kStreamTargetSize) {
        const double target = cheap ? kCheapTarget : kStreamTarget;
        targets.push_back("of_stream>=" + fixed(target, 2));
        if (row.of_stream < target)
            misses.push_back("MISS: " + fixed(row.of_stream, 2) + " of STREAM, target " + fixed(target, 2));
    }
    if (precise && kTranscendental.count(row.model) && row.x_cpp >= 0.0) {
        targets.push_back("x_cpp>=" + fixed(kCppTarget, 0));
        if (row.x_cpp < kCppTarget)
            misses.push_back("MISS: " + fixed(row.x_cpp, 2) + "x C++, target " + fixed(kCppTarget, 0) + "x");
    }
    if (!precise && row.x_precise >= 0.0) {
        const bool differs = g_fast_pow_differs && kFastDiffers.count(row.model) > 0;
        const double target = differs ? kFastTarget : kSameCodeFloor;
        targets.push_back(std::string(differs ? "x_precise>=" : "x_precise(same code)>=") + fixed(target, 1));
        if (row.x_precise < target)
            misses.push_back("MISS: fast " + fixed(row.x_precise, 2) + "x precise, target " + fixed(target, 1) + "x");
    }
    if (row.vec.rfind("no", 0) == 0 || row.vec.find("/no") != std::string::npos)
        misses.push_back("MISS: not vectorised (" + row.vec + ")");
    row.target.clear();
    for (const auto& t : targets) row.target += (row.target.empty() ? "" : " & ") + t;
    row.verdict.clear();
    for (const auto& m : misses) row.verdict += (row.verdict.empty() ? "" : "; ") + m;
    if (row.verdict.empty()) row.verdict = "ok";
}

// --local-sizes: Mfrag/s of a few models at several work-group sizes (and the runtime's own choice).
void local_size_study(Runtime& rt, Shader& shader, const Options& opt) {
    const std::vector<std::string> models = opt.models.empty()
                                                ? std::vector<std::string>{"lambert", "minnaert_1941", "oren_nayar",
                                                                           "cook_torrance"}
                                                : opt.models;
    const std::vector<std::size_t> locals = {Shader::kLocalAuto, 16, 64, 128, 256, 512, 1024, 4096};
    for (std::size_t n : opt.sizes) {
        const FragmentBuffer fb = random_fragments(n);
        Stream stream(rt, n);
        std::cout << "\n== local-size study, " << size_label(n) << " fragments, precise mode, Mfrag/s (STREAM triad: "
                     "Melements/s at the same local size)\n"
                  << std::left << std::setw(16) << "model" << std::right;
        for (std::size_t l : locals) std::cout << std::setw(9) << (l == Shader::kLocalAuto ? "auto" : std::to_string(l));
        std::cout << "\n";
        std::vector<std::string> names = models;
        names.insert(names.begin(), "triad");
        for (const auto& name : names) {
            std::cout << std::left << std::setw(16) << name << std::right;
            for (std::size_t l : locals) {
                double ms;
                if (name == "triad") {
                    ms = 12.0 * double(n) / stream.triad_gbs(opt.repeats, l) * 1e-6;
                } else {
                    std::vector<float> out;
                    ms = shade_best_ms(shader, fb, setup_for(default_material(find_model(name)), Precision::Precise, l),
                                       opt.repeats, out);
                }
                std::cout << std::setw(9) << fixed(double(n) / ms * 1e-3, 1) << std::flush;
            }
            std::cout << "\n";
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    try {
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            auto value = [&]() -> std::string {
                if (i + 1 >= argc) throw Error("option " + a + " needs a value (see the usage line)");
                return argv[++i];
            };
            if (a == "--smoke") { opt.smoke = true; opt.sizes = {4096}; opt.repeats = 1; }
            else if (a == "--quick") opt.sizes = {1u << 20};
            else if (a == "--sizes") { opt.sizes.clear(); for (const auto& s : split(value())) opt.sizes.push_back(parse_count(s)); }
            else if (a == "--models") { opt.models = split(value()); for (const auto& m : opt.models) find_model(m); }
            else if (a == "--modes") { opt.modes.clear(); for (const auto& m : split(value())) opt.modes.push_back(parse_precision(m)); }
            else if (a == "--repeats") opt.repeats = std::max(1, std::stoi(value()));
            else if (a == "--local") { const std::string v = value(); opt.local = v == "auto" ? Shader::kLocalAuto : parse_count(v); }
            else if (a == "--local-sizes") opt.local_study = true;
            else if (a == "--no-vec") opt.vec_report = false;
            else if (a == "--csv") opt.csv = value();
            else throw Error("unknown option '" + a + "'");
        }
    } catch (const std::exception& e) {
        std::cerr << "bench_models: " << e.what()
                  << "\nusage: bench_models [--smoke | --quick] [--sizes 1M,4M,16M] [--models a,b] [--modes precise,fast]"
                     " [--repeats N] [--local N|auto] [--local-sizes] [--no-vec] [--csv FILE]\n";
        return 2;
    }
    try {
        // Before the runtime exists: PoCL reads its switches when it starts. Remarks need a real compilation of
        // every kernel, hence no kernel cache (kernel times are not affected: compilation precedes the launch).
        if (opt.vec_report && !opt.local_study) {
            setenv("POCL_VECTORIZER_REMARKS", "1", 1);
            setenv("POCL_KERNEL_CACHE", "0", 1);
        }
        std::ofstream csv;
        if (!opt.csv.empty()) {
            csv.open(opt.csv);
            if (!csv) throw Error("cannot write the CSV file '" + opt.csv + "': check the folder exists and is writable");
            csv << "n,model,mode,mfrag_per_s,gb_per_s,of_stream,x_cpp,x_ref,fast_x_precise,vectorised,target,verdict\n";
        }
        Runtime rt;
        Shader shader(rt);
        capture_output([&] { g_fast_pow_differs = fast_pow_differs(rt); });   // its build's remarks unprinted
        std::cout << "machine: " << std::thread::hardware_concurrency() << " threads, " << bench::cpu_name() << "\n"
                  << "device:  " << rt.device_description() << "\n"
                  << "pow:     " << (g_fast_pow_differs ? "fast mode's sl_fast_pow differs from precise mode's sl_pow"
                                                        : "both modes use sl_pow_cr on this device (fast = same code)")
                  << "\n"
                  << "ratios are measured in this run; kernel times are device times from profiling events, best of "
                  << opt.repeats << "; STREAM is re-timed before every row\n";
        if (opt.local_study) {
            local_size_study(rt, shader, opt);
            return 0;
        }
        bool finite = true, loops_agree = true;
        std::vector<Row> misses;
        std::map<std::string, std::string> vec_of;   // model + mode -> verdict (first size; the code is the same)
        for (std::size_t n : opt.sizes) {
            const FragmentBuffer fb = random_fragments(n);
            Stream stream(rt, n);
            const double copy0 = stream.copy_gbs(opt.repeats), triad0 = stream.triad_gbs(opt.repeats);
            std::cout << "\n== " << size_label(n) << " fragments: STREAM copy " << fixed(copy0, 1) << " GB/s, triad "
                      << fixed(triad0, 1) << " GB/s (PoCL, arrays of " << size_label(n) << " floats)\n";
            std::cout << std::left << std::setw(31) << "model" << std::setw(8) << "mode" << std::right << std::setw(9)
                      << "Mfrag/s" << std::setw(7) << "GB/s" << std::setw(10) << "of STREAM" << std::setw(8) << "x C++"
                      << std::setw(10) << "x ref(1t)" << std::setw(9) << "x prec" << std::setw(6) << "vec"
                      << "  loop vs kernel      verdict\n";
            const std::size_t nref = std::min<std::size_t>(n, opt.smoke ? 4096 : 100000);
            for (const auto& info : model_catalogue()) {
                if (!opt.models.empty() && std::find(opt.models.begin(), opt.models.end(), info.name) == opt.models.end())
                    continue;
                const Material m = default_material(info);
                const double ref_fps = reference_fps(m, fb, nref, finite);
                LoopResult loop;
                bool have_loop = false;
                double precise_mfps = -1.0;
                for (Precision p : opt.modes) {
                    const double triad = stream.triad_gbs(opt.repeats);
                    std::vector<float> out;
                    const ShadeSetup setup = setup_for(m, p, opt.local);
                    const std::string key = info.name + "/" + precision_name(p);
                    if (opt.vec_report && !vec_of.count(key)) {   // the first call compiles the kernel
                        const std::string remarks = capture_output([&] { out = shader.shade(fb, setup); });
                        vec_of[key] = vectoriser_verdict(remarks);
                    }
                    const double ms = shade_best_ms(shader, fb, setup, opt.repeats, out);
                    for (float v : out) finite = finite && std::isfinite(v);
                    if (!have_loop && cpp_loops::has_loop(info.name)) {
                        loop = cpp_loop(m, fb, out, opt.repeats);
                        have_loop = true;
                        if (loop.share_off > 1e-3) loops_agree = false;
                    }
                    const double mfps = double(n) / ms * 1e-3;
                    const double gbs = bytes_per_fragment(info.name) * double(n) / ms * 1e-6;
                    Row row{n, info.name, precision_name(p), mfps, gbs, gbs / triad,
                            have_loop ? loop.ms / ms : -1.0, double(n) / ms * 1e3 / ref_fps,
                            p == Precision::Fast && precise_mfps > 0 ? mfps / precise_mfps : -1.0,
                            opt.vec_report ? vec_of[key] : "-", "", ""};
                    if (p == Precision::Precise) precise_mfps = mfps;
                    judge(row, p == Precision::Precise);
                    std::string agree = "-";
                    if (have_loop) {
                        std::ostringstream a;
                        a << std::scientific << std::setprecision(1) << loop.max_rel;
                        if (loop.share_off > 0) a << " (" << std::fixed << std::setprecision(3) << 100 * loop.share_off << "%>1e-3)";
                        agree = a.str();
                    }
                    std::cout << std::left << std::setw(31) << row.model << std::setw(8) << row.mode << std::right
                              << std::setw(9) << fixed(row.mfps, 1) << std::setw(7) << fixed(row.gbs, 1) << std::setw(10)
                              << fixed(row.of_stream, 2) << std::setw(8) << (have_loop ? fixed(row.x_cpp, 2) : "-")
                              << std::setw(10) << fixed(row.x_ref, 0) << std::setw(9)
                              << (row.x_precise >= 0 ? fixed(row.x_precise, 2) : "-") << std::setw(6)
                              << (row.vec.size() > 5 ? row.vec.substr(0, row.vec.find(':')) : row.vec) << "  " << std::left
                              << std::setw(20) << agree << row.verdict << std::right << "\n"
                              << std::flush;
                    if (csv)
                        csv << n << "," << row.model << "," << row.mode << "," << fixed(row.mfps, 2) << ","
                            << fixed(row.gbs, 2) << "," << fixed(row.of_stream, 3) << ","
                            << (have_loop ? fixed(row.x_cpp, 3) : "") << "," << fixed(row.x_ref, 1) << ","
                            << (row.x_precise >= 0 ? fixed(row.x_precise, 3) : "") << ",\"" << row.vec << "\",\""
                            << row.target << "\",\"" << row.verdict << "\"\n";
                    if (row.verdict != "ok") misses.push_back(row);
                }
            }
        }
        if (opt.vec_report) {
            int vectorised[2] = {0, 0}, total[2] = {0, 0};
            for (const auto& [key, verdict] : vec_of) {
                const int fast = key.size() > 5 && key.compare(key.size() - 5, 5, "/fast") == 0;
                ++total[fast];
                vectorised[fast] += verdict != "?" && verdict.find("no") == std::string::npos;
            }
            std::cout << "\nvectorised (PoCL's remarks): precise " << vectorised[0] << " of " << total[0] << ", fast "
                      << vectorised[1] << " of " << total[1] << "\n";
            for (const auto& [key, verdict] : vec_of)
                if (verdict == "?" || verdict.find("no") != std::string::npos)
                    std::cout << "  not vectorised: " << key << ": " << verdict << "\n";
        }
        std::cout << "\nloop vs kernel: max relative difference over values >= 1e-3 of the peak (share above 1e-3)\n"
                  << "bytes a fragment: 24 for models of N and L only (" << kNormalsOnly.size()
                  << " models), 36 for the others (they read the position)\n"
                  << "targets: cheap models >= " << kCheapTarget << " of STREAM triad; every model >= " << kStreamTarget
                  << " of STREAM triad at " << size_label(kStreamTargetSize) << "; transcendental models (precise) >= "
                  << kCppTarget << "x C++; fast >= " << kFastTarget << "x precise where the code differs (pow), >= "
                  << kSameCodeFloor << "x where it is the same code; every kernel vectorised\n"
                  << misses.size() << " rows miss a target" << (misses.empty() ? "" : " (MISS lines above)") << "\n"
                  << (finite ? "all outputs finite" : "NON-FINITE OUTPUT FOUND") << "\n"
                  << (loops_agree ? "every C++ loop agrees with its kernel"
                                  : "A C++ LOOP DISAGREES WITH ITS KERNEL (more than 0.1% of values off by > 1e-3)")
                  << "\n";
        return finite && loops_agree ? 0 : 1;
    } catch (const std::exception& e) {
        std::cerr << "bench_models: error: " << e.what() << "\n";
        return 1;
    }
}
