// bench_e2e's fragment stage: the same lighting models as kernels/models/*.cl, written again in GLSL from
// the formulas in docs/models/*.md (value convention of docs/notation.md: outgoing radiance per unit light
// radiance, with the incident cosine, white Lambert head-on = 1). One function per term.
//
// The program inserts above this file:
//   #version 330 core
//   #define MODEL_<NAME> 1     one of MODEL_LAMBERT, MODEL_BLINN_PHONG, MODEL_MINNAERT_1941, MODEL_OREN_NAYAR,
//                              MODEL_COOK_TORRANCE
//   #define NUM_LIGHTS <n>     1 to 4
// u_c holds the model's constants, derived once per material on the host from the catalogue's parameters
// (bench/bench_e2e.cpp, gl_model_constants).
in vec3 v_position;
in vec3 v_normal;

out vec4 o_colour;

uniform vec3 u_eye;              // camera position (world)
uniform vec3 u_albedo;           // diffuse colour, linear
uniform vec3 u_specular;         // specular colour, linear
uniform vec3 u_ambient;          // ambient light, multiplied by the albedo
uniform float u_c[8];            // model constants
uniform vec4 u_light_vec[4];     // xyz: unit direction TO the light (w = 0) or position (w = 1)
uniform vec4 u_light_radiance[4];// rgb: colour * intensity; a: range of a point light (0 = unbounded)

// ---- lights (docs/models/lights.md) ------------------------------------------------------------------------

// Karis 2013 ("Real Shading in Unreal Engine 4") range window of a point light: (1 - (d/range)^4)^2, clamped.
float range_window(float d2, float range) {
    if (range <= 0.0) return 1.0;
    float q = d2 / (range * range);
    float w = clamp(1.0 - q * q, 0.0, 1.0);
    return w * w;
}

// Incident radiance factor of light i at P and the unit direction L to it: a directional light is
// unattenuated; a point light falls off as 1 / d^2 (times the range window).
vec3 incident(int i, vec3 P, out vec3 L) {
    vec4 lv = u_light_vec[i];
    if (lv.w == 0.0) {
        L = lv.xyz;
        return u_light_radiance[i].rgb;
    }
    vec3 d = lv.xyz - P;
    float d2 = max(dot(d, d), 1e-12);
    L = d * inversesqrt(d2);
    return u_light_radiance[i].rgb * (range_window(d2, u_light_radiance[i].a) / d2);
}

// ---- Lambert (Lambert 1760, Photometria): value = albedo * max(0, NoL) ------------------------------------

float lambert_cosine(float NoL) { return max(NoL, 0.0); }

vec3 lambert(vec3 N, vec3 L, vec3 V) { return u_albedo * lambert_cosine(dot(N, L)); }

// ---- Blinn-Phong (Blinn 1977, docs/models/phong.md) ----------------------------------------------------------
//   value = albedo * max(0, NoL) + ks * specular * [NoL > 0] * max(0, NoH)^n,  H = normalize(L + V)
// u_c[0] = n, u_c[1] = ks.

// cos(theta_h) = N . normalize(L + V); 0 where L = -V leaves H undefined.
float half_vector_cosine(vec3 N, vec3 L, vec3 V) {
    vec3 h = L + V;
    float hh = dot(h, h);
    return hh > 1e-20 ? dot(N, h) * inversesqrt(hh) : 0.0;
}

// x^n for x > 0 (x capped at 1 against rounding), 0 for x <= 0.
float cosine_power(float x, float n) { return x > 0.0 ? pow(min(x, 1.0), n) : 0.0; }

vec3 blinn_phong(vec3 N, vec3 L, vec3 V) {
    float NoL = dot(N, L);
    float highlight = NoL > 0.0 ? u_c[1] * cosine_power(half_vector_cosine(N, L, V), u_c[0]) : 0.0;
    return u_albedo * lambert_cosine(NoL) + u_specular * highlight;
}

// ---- Minnaert 1941 (ApJ 93:403; docs/models/minnaert.md) ------------------------------------------------------
//   value = albedo * NoL^k * NoV^(k-1) = albedo * NoL * (NoL NoV)^(k-1)   for NoL > 0 and NoV > 0, else 0,
// with the limb guard of the docs for k < 1: each cosine c below eps = 1e-3 enters as eps^(k-1) * c / eps.
// u_c[0] = k - 1, u_c[1] = eps (0 for k >= 1), u_c[2] = 1 / eps (0 for k >= 1).

// The linear fade of the limb guard: c / eps below eps, else 1.
float limb_taper(float c) { return c < u_c[1] ? c * u_c[2] : 1.0; }

// (NoL NoV)^(k-1) with both cosines held at eps or above, times the two fades.
float minnaert_factor(float NoL, float NoV) {
    return pow(max(NoL, u_c[1]) * max(NoV, u_c[1]), u_c[0]) * limb_taper(NoL) * limb_taper(NoV);
}

vec3 minnaert_1941(vec3 N, vec3 L, vec3 V) {
    float NoL = dot(N, L), NoV = dot(N, V);
    return NoL > 0.0 && NoV > 0.0 ? u_albedo * (NoL * minnaert_factor(NoL, NoV)) : vec3(0.0);
}

// ---- Oren-Nayar 1994 qualitative model (SIGGRAPH '94; docs/models/oren_nayar.md) -----------------------------
//   value = albedo * NoL * (A + B * max(0, cos(phi_i - phi_r)) * sin(alpha) * tan(beta))
//         = albedo * NoL * (A + B * max(0, s) / max(NoL, NoV)),  s = LoV - NoL NoV   (the docs' s/t identity)
//   A = 1 - 0.5 sigma^2 / (sigma^2 + 0.33),  B = 0.45 sigma^2 / (sigma^2 + 0.09); 0 for NoL <= 0.
// A view below the horizon (NoV < 0) is a grazing view at the same azimuth (docs): NoV := 0 and
// s := dot(Lt, Vt) / |Vt| = s / sin(theta_r). u_c[0] = A, u_c[1] = B.

// s = sin(theta_i) sin(theta_r) cos(phi_i - phi_r); below the horizon divided by sin(theta_r) = |N x V|
// (0 at V = -N, where there is no azimuth).
float azimuth_term(vec3 N, vec3 V, float LoV, float NoL, float NoV) {
    float s = LoV - NoL * NoV;
    if (NoV >= 0.0) return s;
    float sin_r = length(cross(N, V));
    return sin_r > 1e-15 ? s / sin_r : 0.0;
}

vec3 oren_nayar(vec3 N, vec3 L, vec3 V) {
    float NoL = dot(N, L), NoV = dot(N, V);
    if (NoL <= 0.0) return vec3(0.0);
    float s = azimuth_term(N, V, dot(L, V), NoL, NoV);
    return u_albedo * (NoL * (u_c[0] + u_c[1] * max(s, 0.0) / max(NoL, max(NoV, 0.0))));
}

// ---- Cook-Torrance 1982 (ACM ToG 1(1); docs/models/cook_torrance.md) ------------------------------------------
//   value = kd * albedo * max(0, NoL) + ks * specular * F * D * G / NoV     (specular only for NoL, NoV > 0)
// u_c[0] = m^2, u_c[1] = 1 / (pi m^2), u_c[2] = f0, u_c[3] = kd, u_c[4] = ks.

// Beckmann (1963): D = exp(-tan^2(theta_h) / m^2) / (pi m^2 cos^4(theta_h)), tan^2 = (1 - NoH^2) / NoH^2.
// 0 below NoH^2 = 1e-4, where the exponential is already 0 in float for every m <= 1 (no 0/0).
float beckmann_distribution(float NoH) {
    float c2 = NoH * NoH;
    if (c2 < 1e-4) return 0.0;
    return exp(-(1.0 - c2) / (c2 * u_c[0])) * u_c[1] / (c2 * c2);
}

// Schlick (1994): F = f0 + (1 - f0) (1 - VoH)^5.
float schlick_fresnel(float VoH) {
    float x = 1.0 - VoH;
    float x2 = x * x;
    return u_c[2] + (1.0 - u_c[2]) * x2 * x2 * x;
}

// V-groove masking and shadowing (Torrance & Sparrow 1967; Blinn 1977): G = min(1, 2 NoH NoV / VoH, 2 NoH NoL / VoH).
float vgroove_geometry(float NoH, float NoV, float NoL, float VoH) {
    float k = 2.0 * NoH / VoH;
    return min(1.0, min(k * NoV, k * NoL));
}

vec3 cook_torrance(vec3 N, vec3 L, vec3 V) {
    float NoL = dot(N, L), NoV = dot(N, V);
    vec3 h = L + V;
    float hh = dot(h, h);
    float spec = 0.0;
    if (NoL > 0.0 && NoV > 0.0 && hh > 1e-12) {
        vec3 H = h * inversesqrt(hh);
        float NoH = max(dot(N, H), 0.0);
        float VoH = max(dot(V, H), 1e-7);
        spec = schlick_fresnel(VoH) * beckmann_distribution(NoH) * vgroove_geometry(NoH, NoV, NoL, VoH) / NoV;
    }
    return u_c[3] * u_albedo * lambert_cosine(NoL) + u_c[4] * u_specular * spec;
}

// ---- the pixel: ambient * albedo + sum over lights of incident * model (kernels/shade.cl, shade_fragments) ---

vec3 model(vec3 N, vec3 L, vec3 V) {
#if defined(MODEL_LAMBERT)
    return lambert(N, L, V);
#elif defined(MODEL_BLINN_PHONG)
    return blinn_phong(N, L, V);
#elif defined(MODEL_MINNAERT_1941)
    return minnaert_1941(N, L, V);
#elif defined(MODEL_OREN_NAYAR)
    return oren_nayar(N, L, V);
#elif defined(MODEL_COOK_TORRANCE)
    return cook_torrance(N, L, V);
#else
#error "no MODEL_<name> defined"
#endif
}

void main() {
    vec3 N = normalize(v_normal);
    vec3 P = v_position;
    vec3 V = normalize(u_eye - P);
    vec3 sum = u_ambient * u_albedo;
    for (int i = 0; i < NUM_LIGHTS; ++i) {
        vec3 L;
        vec3 E = incident(i, P, L);
        sum += E * model(N, L, V);
    }
    // No NaN or Inf in any image: non-finite values (only from invalid input) are written as 0, as the kernels do.
    if (any(isnan(sum)) || any(isinf(sum))) sum = vec3(0.0);
    o_colour = vec4(sum, 1.0);
}
