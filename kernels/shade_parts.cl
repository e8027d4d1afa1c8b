// What every shading kernel shares (kernels/shade.cl, kernels/shade_many.cl): the light and view helpers and
// SL_EVAL_AT, which calls the model named by SL_EVAL (expanded where a kernel uses it, so shade_many.cl can
// name another model before each kernel).
#ifndef SHADELAB_SHADE_PARTS_CL
#define SHADELAB_SHADE_PARTS_CL
#include "common.cl"

#ifndef SL_NUM_LIGHTS
#define SL_NUM_LIGHTS 1
#endif
// SL_POINT_LIGHTS and SL_RANGED_LIGHTS (set by shade_program from the scene's lights, host/shade/shader.cpp
// light_defines): bit l of each (an unsigned long, up to 64 lights) is set when light l is a point light, and when
// it is a point light with a range (> 0). The light loop is unrolled, so each light's kind is then known when the
// program is built: a directional light costs no point-light arithmetic, and a point light without a range no
// window. Without them the kind is read per light at run time, and the vectorised work-item loop, which cannot
// branch on it, computes both kinds and selects: with the point path's square root and three divisions Lambert
// ran 330-440 Mfrag/s, without 550-710 (4M fragments, one directional light, two alternating runs); with a
// directional and a point light, most models ran 1.1-1.8x as fast (medians of three rounds, 1M and 4M) with the
// kinds in the program (docs/speed.md, "Light kinds at build time").
#if defined(SL_POINT_LIGHTS) != defined(SL_RANGED_LIGHTS)
#error "SL_POINT_LIGHTS and SL_RANGED_LIGHTS are set together"
#endif

// Every kernel below takes the material's table buffer `tab` as its last argument (a 1-float buffer, never read,
// for the models without a table); only a table model's eval is handed it.
#if defined(SL_TABLE) && SL_TABLE
#define SL_EVAL_AT(N, L, V, P, mc) SL_EVAL(N, L, V, P, mc, tab)
#else
#define SL_EVAL_AT(N, L, V, P, mc) SL_EVAL(N, L, V, P, mc)
#endif

// sl_finite_or_zero (kernels/common.cl) writes a non-finite channel as 0.

// Every model's eval is written float3-free (common.cl's sl_v3 / sl_rgb), so the whole kernel is scalar code
// and PoCL's loop vectoriser runs 8 fragments per instruction ("vectorized loop (vectorization width: 8)" with
// POCL_VECTORIZER_REMARKS=1; docs/precision.md, "Vectorised kernels", lists what it took and what is not).

// Irradiance-like factor and direction of light `li` (light number `l` of the scene) at P, in scalars: returns
// the factor that scales the light's radiance and sets *L to the unit direction to it. Directional lights are
// unattenuated (factor 1); point lights fall off with the inverse square of distance, optionally windowed to zero
// at `range` with (1 - (d/range)^4)^2 (Karis 2013, "Real Shading in Unreal Engine 4") so they can be culled.
SL_INLINE float light_incident_v3(const DeviceLight* li, int l, sl_v3 P, sl_v3* L) {
    const sl_v3 pos = sl_v3_make(li->pos_or_dir[0], li->pos_or_dir[1], li->pos_or_dir[2]);
    const float range = li->range;   // read before the branch: a load under it would not be hoisted (a gather)
#if defined(SL_POINT_LIGHTS)
    const int point = (int)((SL_POINT_LIGHTS >> l) & 1ul), ranged = (int)((SL_RANGED_LIGHTS >> l) & 1ul);
#else
    (void)l;
    const int point = li->type != 0.0f, ranged = 1;
#endif
    if (!point) {
        *L = pos;
        return 1.0f;
    }
    const sl_v3 d = sl_sub(pos, P);
    const float d2 = fmax(sl_dot(d, d), 1e-12f);   // a light exactly at the surface point: no direction
    *L = sl_scale(d, rsqrt(d2));
    float window = 1.0f;
    if (ranged && range > 0.0f) {
        const float q = d2 / (range * range);
        window = sl_saturate(1.0f - q * q);
        window *= window;
    }
    return window / d2;
}

// The unit vector to the viewer at P: perspective: view.pos_or_dir is the camera position; orthographic: it is
// the unit direction to the viewer, the same for every fragment (used for the moon disc).
// SL_PERSPECTIVE=1 or 0 (set by shade_program from the view the program is built for) makes the choice when the
// program is built: chosen per fragment from view.perspective, the vectorised loop loaded P with masked loads and
// blended two directions, and the view-dependent models ran 1.1-1.4x slower at 1M fragments (docs/speed.md,
// "The view's kind at build time"). Without the define (a program that is not told), the choice is made here.
SL_INLINE sl_v3 view_dir_v3(DeviceView view, sl_v3 P) {
    const sl_v3 eye = sl_v3_make(view.pos_or_dir[0], view.pos_or_dir[1], view.pos_or_dir[2]);
#if defined(SL_PERSPECTIVE)
    (void)view.perspective;
    (void)P;
    return SL_PERSPECTIVE ? sl_normalize(sl_sub(eye, P)) : eye;
#else
    return view.perspective != 0.0f ? sl_normalize(sl_sub(eye, P)) : eye;
#endif
}

#endif
