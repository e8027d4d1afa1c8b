// What a C++ user would write instead of the kernels: each model as a plain float loop with <cmath>, over the
// same fragment buffer, same directional light (radiance 1, no ambient) and camera position as the benchmark's
// kernel run, split over std::threads. Written from the papers' formulas (docs/models/), sharing no code with
// kernels/ or host/reference/; only the parameter values come from the catalogue (the material's defaults).
// Compiled with the benchmark's -O3 -march=native: whatever the compiler vectorises here, it does.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

namespace cpp_loops {

struct Vec3 {
    float x, y, z;
};
inline float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 add(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 scale(const Vec3& a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 normalize(const Vec3& a) { return scale(a, 1.0f / std::sqrt(dot(a, a))); }
inline float clamp01(float x) { return std::min(std::max(x, 0.0f), 1.0f); }

// The material as the loops see it: colours and the catalogue parameters by name.
struct Mat {
    float albedo[3];
    float specular[3];
    std::map<std::string, double> params;
    float p(const char* name) const {
        const auto it = params.find(name);
        if (it == params.end()) throw std::runtime_error(std::string("cpp loop: parameter '") + name + "' missing");
        return float(it->second);
    }
};

// Every model below returns rgb = albedo * d + specular * s (+ albedo^2 * d2 for Oren-Nayar's interreflection).
struct Rgb {
    float d = 0.0f, s = 0.0f, d2 = 0.0f;
};

// Lambert (1760): max(0, NoL).
struct Lambert {
    explicit Lambert(const Mat&) {}
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3&) const { return {std::max(dot(N, L), 0.0f)}; }
};

// Valve's half-Lambert: ((NoL + 1) / 2)^2, NoL unclamped.
struct HalfLambert {
    explicit HalfLambert(const Mat&) {}
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3&) const {
        const float h = 0.5f * dot(N, L) + 0.5f;
        return {h * h};
    }
};

// Wrap (seed 001): max(0, NoL a + 1 - a)^2.
struct Wrap {
    float a;
    explicit Wrap(const Mat& m) : a(m.p("wrap_value")) {}
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3&) const {
        const float h = std::max(dot(N, L) * a + 1.0f - a, 0.0f);
        return {h * h};
    }
};

// Phong (1975): max(0, NoL) + ks [NoL > 0] max(0, R.V)^n, R = 2 NoL N - L.
struct Phong {
    float n, ks;
    explicit Phong(const Mat& m) : n(m.p("n")), ks(m.p("ks")) {}
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3& V) const {
        const float NoL = dot(N, L);
        const Vec3 R = sub(scale(N, 2.0f * NoL), L);
        const float RoV = dot(R, V);
        const float spec = NoL > 0.0f && RoV > 0.0f ? ks * std::pow(std::min(RoV, 1.0f), n) : 0.0f;
        return {std::max(NoL, 0.0f), spec};
    }
};

// Blinn-Phong (1977): max(0, NoL) + ks [NoL > 0] max(0, N.H)^n, H = normalize(L + V).
struct BlinnPhong {
    float n, ks;
    explicit BlinnPhong(const Mat& m) : n(m.p("n")), ks(m.p("ks")) {}
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3& V) const {
        const float NoL = dot(N, L);
        const float NoH = dot(N, normalize(add(L, V)));
        const float spec = NoL > 0.0f && NoH > 0.0f ? ks * std::pow(std::min(NoH, 1.0f), n) : 0.0f;
        return {std::max(NoL, 0.0f), spec};
    }
};

// Banded Lambert (seed 001): floor(max(0, NoL) steps + 1/2) / steps.
struct Banded {
    float steps;
    explicit Banded(const Mat& m) : steps(m.p("steps")) {}
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3&) const {
        return {std::floor(std::max(dot(N, L), 0.0f) * steps + 0.5f) / steps};
    }
};

// Toon (seed 004; Lake et al. 2000): NoL to 4 levels, Blinn-Phong max(0, NoH)^n to 3 levels, each edge a
// smoothstep over [t - width/2, t + width/2] (a hard step at width 0); the highlight only on the lit side.
struct Toon {
    float n, hw, dt[3], dl[4], st[2], sl[3];
    explicit Toon(const Mat& m)
        : n(m.p("n")), hw(0.5f * m.p("width")), dt{m.p("diffuse_t1"), m.p("diffuse_t2"), m.p("diffuse_t3")},
          dl{m.p("diffuse_l0"), m.p("diffuse_l1"), m.p("diffuse_l2"), m.p("diffuse_l3")},
          st{m.p("spec_t1"), m.p("spec_t2")}, sl{m.p("spec_l0"), m.p("spec_l1"), m.p("spec_l2")} {}
    float step(float x, float e) const {
        if (hw <= 0.0f) return x >= e ? 1.0f : 0.0f;
        const float t = clamp01((x - (e - hw)) / (2.0f * hw));
        return t * t * (3.0f - 2.0f * t);
    }
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3& V) const {
        const float NoL = dot(N, L);
        const float NoH = dot(N, normalize(add(L, V)));
        const float x = NoH > 0.0f ? std::pow(std::min(NoH, 1.0f), n) : 0.0f;
        const float d = dl[0] + (dl[1] - dl[0]) * step(NoL, dt[0]) + (dl[2] - dl[1]) * step(NoL, dt[1]) +
                        (dl[3] - dl[2]) * step(NoL, dt[2]);
        const float s = sl[0] + (sl[1] - sl[0]) * step(x, st[0]) + (sl[2] - sl[1]) * step(x, st[1]);
        return {d, step(NoL, 0.0f) * s};
    }
};

// Minnaert (1941): NoL^k NoV^(k-1) for NoL, NoV > 0, with the model's limb guard for k < 1: below
// eps = 1e-3 each cosine's power is held at eps and faded linearly to 0.
struct Minnaert1941 {
    float k, eps;
    explicit Minnaert1941(const Mat& m) : k(m.p("k")), eps(m.p("k") < 1.0f ? 1e-3f : 0.0f) {}
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3& V) const {
        const float NoL = dot(N, L), NoV = dot(N, V);
        if (NoL <= 0.0f || NoV <= 0.0f) return {};
        const float fade = (NoL < eps ? NoL / eps : 1.0f) * (NoV < eps ? NoV / eps : 1.0f);
        return {NoL * std::pow(std::max(NoL, eps) * std::max(NoV, eps), k - 1.0f) * fade};
    }
};

// MinnaertB (seed 002): NoL NoL^k (1 - NoV)^(1-k), NoV clamped to [0, 1]; 0 for NoL <= 0.
struct MinnaertB {
    float k;
    explicit MinnaertB(const Mat& m) : k(m.p("k")) {}
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3& V) const {
        const float NoL = dot(N, L), NoV = clamp01(dot(N, V));
        if (NoL <= 0.0f) return {};
        return {NoL * std::pow(NoL, k) * std::pow(1.0f - NoV, 1.0f - k)};
    }
};

// cos(phi_i - phi_r): the cosine between L and V projected onto the tangent plane (0 where undefined).
inline float cos_dphi(const Vec3& N, const Vec3& L, const Vec3& V, float NoL, float NoV) {
    const Vec3 Lt = sub(L, scale(N, NoL)), Vt = sub(V, scale(N, NoV));
    const float d = std::sqrt(dot(Lt, Lt) * dot(Vt, Vt));
    return d > 1e-15f ? dot(Lt, Vt) / d : 0.0f;
}

// Oren & Nayar (1994), qualitative model: NoL (A + B max(0, cos dphi) sin(alpha) tan(beta)),
// A = 1 - 0.5 s2 / (s2 + 0.33), B = 0.45 s2 / (s2 + 0.09), alpha = max(theta_i, theta_r), beta = min.
struct OrenNayar {
    float A, B;
    explicit OrenNayar(const Mat& m) {
        const float s2 = m.p("sigma") * m.p("sigma");
        A = 1.0f - 0.5f * s2 / (s2 + 0.33f);
        B = 0.45f * s2 / (s2 + 0.09f);
    }
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3& V) const {
        const float NoL = dot(N, L), NoV = std::max(dot(N, V), 0.0f);
        if (NoL <= 0.0f) return {};
        const float ti = std::acos(std::min(NoL, 1.0f)), tr = std::acos(std::min(NoV, 1.0f));
        const float alpha = std::max(ti, tr), beta = std::min(ti, tr);
        const float c = std::max(cos_dphi(N, L, V, NoL, dot(N, V)), 0.0f);
        return {NoL * (A + B * c * std::sin(alpha) * std::tan(beta))};
    }
};

// Oren & Nayar (1994), full model with interreflections (their eqs. 30-31):
//   L1 = C1 + cos dphi C2 tan(beta) + (1 - |cos dphi|) C3 tan((alpha + beta) / 2)
//   L2 = 0.17 rho s2 / (s2 + 0.13) (1 - cos dphi (2 beta / pi)^2)
//   value = NoL (rho L1 + rho^2 L2 / rho)  (the rho^2 part is returned as d2)
struct OrenNayarFull {
    float c1, c2, c3, c4;
    explicit OrenNayarFull(const Mat& m) {
        const float s2 = m.p("sigma") * m.p("sigma");
        c1 = 1.0f - 0.5f * s2 / (s2 + 0.33f);
        c2 = 0.45f * s2 / (s2 + 0.09f);
        c3 = 0.125f * s2 / (s2 + 0.09f);
        c4 = 0.17f * s2 / (s2 + 0.13f);
    }
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3& V) const {
        const float NoL = dot(N, L), NoV = std::max(dot(N, V), 0.0f);
        if (NoL <= 0.0f) return {};
        const float pi = 3.14159265f;
        const float ti = std::acos(std::min(NoL, 1.0f)), tr = std::acos(std::min(NoV, 1.0f));
        const float alpha = std::max(ti, tr), beta = std::min(ti, tr);
        const float c = cos_dphi(N, L, V, NoL, dot(N, V));
        const float tb = 2.0f * beta / pi;
        const float C2 = c2 * (c >= 0.0f ? std::sin(alpha) : std::sin(alpha) - tb * tb * tb);
        const float q = 4.0f * alpha * beta / (pi * pi);
        const float C3 = c3 * q * q;
        const float L1 = c1 + c * C2 * std::tan(beta) + (1.0f - std::fabs(c)) * C3 * std::tan(0.5f * (alpha + beta));
        const float L2 = c4 * (1.0f - c * tb * tb);
        return {NoL * L1, 0.0f, NoL * L2};
    }
};

// Cook & Torrance (1982): kd max(0, NoL) + ks F D G / NoV (the value convention's pi f_r NoL), with
// F Schlick (1994), G = min(1, 2 NoH NoV / VoH, 2 NoH NoL / VoH), D Beckmann exp(-tan^2 / m^2) / (pi m^2 cos^4)
// or GGX (Walter et al. 2007) m^2 / (pi (NoH^2 (m^2 - 1) + 1)^2).
template <bool GGX>
struct CookTorrance {
    float m, f0, kd, ks;
    explicit CookTorrance(const Mat& mat) : m(mat.p("m")), f0(mat.p("f0")), kd(mat.p("kd")), ks(mat.p("ks")) {}
    Rgb operator()(const Vec3& N, const Vec3& L, const Vec3& V) const {
        const float NoL = dot(N, L), NoV = dot(N, V);
        Rgb r{kd * std::max(NoL, 0.0f)};
        if (NoL <= 0.0f || NoV <= 0.0f) return r;
        const Vec3 H = normalize(add(L, V));
        const float NoH = std::max(dot(N, H), 0.0f), VoH = std::min(dot(V, H), 1.0f);
        const float F = f0 + (1.0f - f0) * std::pow(1.0f - VoH, 5.0f);
        const float c2 = NoH * NoH, m2 = m * m;
        float D;
        if (GGX) {
            const float d = c2 * (m2 - 1.0f) + 1.0f;
            D = m2 / (3.14159265f * d * d);
        } else {
            D = c2 > 1e-4f ? std::exp(-(1.0f - c2) / (c2 * m2)) / (3.14159265f * m2 * c2 * c2) : 0.0f;
        }
        const float G = std::min(1.0f, std::min(2.0f * NoH * NoV / VoH, 2.0f * NoH * NoL / VoH));
        r.s = ks * F * D * G / NoV;
        return r;
    }
};

// Runs model F over fragments [i0, i1): N, P from the buffer, V = normalize(eye - P), L fixed.
template <class F>
void run_range(const F& f, const Mat& mat, const float* px, const float* py, const float* pz, const float* nx,
               const float* ny, const float* nz, std::size_t n, Vec3 L, Vec3 eye, float* out, std::size_t i0,
               std::size_t i1) {
    for (std::size_t i = i0; i < i1; ++i) {
        const Vec3 N{nx[i], ny[i], nz[i]};
        const Vec3 V = normalize(sub(eye, Vec3{px[i], py[i], pz[i]}));
        const Rgb r = f(N, L, V);
        for (int c = 0; c < 3; ++c)
            out[std::size_t(c) * n + i] = mat.albedo[c] * r.d + mat.specular[c] * r.s + mat.albedo[c] * mat.albedo[c] * r.d2;
    }
}

template <class F>
void run_threads(const Mat& mat, const float* px, const float* py, const float* pz, const float* nx, const float* ny,
                 const float* nz, std::size_t n, Vec3 L, Vec3 eye, float* out, unsigned threads) {
    const F f(mat);
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t)
        pool.emplace_back([&, t] {
            run_range(f, mat, px, py, pz, nx, ny, nz, n, L, eye, out, n * t / threads, n * (t + 1) / threads);
        });
    run_range(f, mat, px, py, pz, nx, ny, nz, n, L, eye, out, 0, n / threads);
    for (auto& th : pool) th.join();
}

// The models that have a loop (a representative of every family).
inline const std::vector<std::string>& models() {
    static const std::vector<std::string> names = {
        "lambert", "half_lambert", "wrap",          "phong",           "blinn_phong",   "banded",           "toon",
        "minnaert_1941", "minnaert_b", "oren_nayar", "oren_nayar_full", "cook_torrance", "cook_torrance_ggx"};
    return names;
}
inline bool has_loop(const std::string& model) {
    return std::find(models().begin(), models().end(), model) != models().end();
}

// Shades n fragments with `model` into out (three planes of n floats). Returns false if there is no loop.
inline bool run(const std::string& model, const Mat& mat, const float* px, const float* py, const float* pz,
                const float* nx, const float* ny, const float* nz, std::size_t n, Vec3 L, Vec3 eye, float* out,
                unsigned threads) {
    const auto go = [&](auto tag) {
        using F = typename decltype(tag)::type;
        run_threads<F>(mat, px, py, pz, nx, ny, nz, n, L, eye, out, threads);
        return true;
    };
    if (model == "lambert") return go(std::common_type<Lambert>{});
    if (model == "half_lambert") return go(std::common_type<HalfLambert>{});
    if (model == "wrap") return go(std::common_type<Wrap>{});
    if (model == "phong") return go(std::common_type<Phong>{});
    if (model == "blinn_phong") return go(std::common_type<BlinnPhong>{});
    if (model == "banded") return go(std::common_type<Banded>{});
    if (model == "toon") return go(std::common_type<Toon>{});
    if (model == "minnaert_1941") return go(std::common_type<Minnaert1941>{});
    if (model == "minnaert_b") return go(std::common_type<MinnaertB>{});
    if (model == "oren_nayar") return go(std::common_type<OrenNayar>{});
    if (model == "oren_nayar_full") return go(std::common_type<OrenNayarFull>{});
    if (model == "cook_torrance") return go(std::common_type<CookTorrance<false>>{});
    if (model == "cook_torrance_ggx") return go(std::common_type<CookTorrance<true>>{});
    return false;
}

}  // namespace cpp_loops
