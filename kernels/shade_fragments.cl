// The fragment-shading kernel, named SL_SHADE_KERNEL, for the model SL_EVAL: kernels/shade.cl includes it
// once (as shade_fragments), kernels/shade_many.cl once per model (as shade_fragments_<eval function>).
// No include guard on purpose. Needs kernels/shade_parts.cl and the model's header included before it.
// SL_SHADE_EXTRA_ARGS, when defined, adds arguments after `count` (shade_many.cl's dispatching kernel: its model).
#ifndef SL_SHADE_EXTRA_ARGS
#define SL_SHADE_EXTRA_ARGS
#endif
// One fragment: sum over lights of incident * model, plus ambient * albedo; SL_FRAGS_PER_ITEM fragments a work-item.
__kernel void SL_SHADE_KERNEL(__global const float* restrict px, __global const float* restrict py,
                              __global const float* restrict pz, __global const float* restrict nx,
                              __global const float* restrict ny, __global const float* restrict nz,
                              __global float* restrict out, const uint stride, const DeviceView view,
                              __constant const ModelConsts* mc_arg, __constant const DeviceLight* lights_arg,
                              const float4 ambient, __global const float* restrict tab,
                              const uint stream, const uint count SL_SHADE_EXTRA_ARGS) {
    (void)tab;
    // No bounds check: the launch covers whole work-groups, and a work-item whose fragments would run past the
    // `count` (>= SL_FRAGS_PER_ITEM) that the buffers hold shades the last SL_FRAGS_PER_ITEM of them instead
    // (`first` below): the same values again, stored to the same places, with plain stores (a moved block
    // need not start on a line). So every load is in the buffers and no operation is under a condition. A
    // bounds check would put the loads of the constants (albedo, lights, the model's c[]) under one, where
    // PoCL's work-item loop cannot hoist them: vectorised, each became a gather per fragment. size_t, not
    // uint: a 32-bit index that may wrap makes px[i] a gather.
    SL_PRIVATE_CONSTS(mc, mc_arg);   // the constants and lights as private copies: see common.cl's SL_CONSTS
    DeviceLight lights[SL_NUM_LIGHTS];
    for (int l = 0; l < SL_NUM_LIGHTS; ++l) lights[l] = lights_arg[l];
    // common.cl: SL_FRAGS_PER_ITEM and the loop. A constant trip count (k, not i < first + n, which may wrap):
    // at one fragment a work-item the loop is gone before PoCL builds its work-item loop.
    const size_t nominal = get_global_id(0) * SL_FRAGS_PER_ITEM;
    const size_t first = min(nominal, (size_t)count - SL_FRAGS_PER_ITEM);
    const uint streamed = first == nominal ? stream : 0u;   // a moved block is off the planes' lines
    float out_r[SL_FRAGS_PER_ITEM] SL_BLOCK_ALIGN, out_g[SL_FRAGS_PER_ITEM] SL_BLOCK_ALIGN,   // sl_store_block's
          out_b[SL_FRAGS_PER_ITEM] SL_BLOCK_ALIGN;
    SL_FRAGMENT_LOOP
    for (uint k = 0; k < SL_FRAGS_PER_ITEM; ++k) {
        const size_t i = first + k;
        const sl_v3 P = sl_v3_make(px[i], py[i], pz[i]);
        const sl_v3 N = sl_v3_make(nx[i], ny[i], nz[i]);
        const sl_v3 V = view_dir_v3(view, P);
        float r = ambient.x * mc->albedo[0], g = ambient.y * mc->albedo[1], b = ambient.z * mc->albedo[2];
#pragma unroll
        for (int l = 0; l < SL_NUM_LIGHTS; ++l) {
            sl_v3 L;
            const float e = light_incident_v3(&lights[l], l, P, &L);
            // Each light's evaluation after the previous light's (common.cl's sl_after): the unrolled loop makes
            // the model's code once per light, and LLVM's SLP vectoriser packs two such copies into <2 x float>,
            // which stops the loop vectoriser (minnaert_1941 and oren_nayar_full with two lights did).
            L.x = sl_after(L.x, r);
            const sl_rgb v = SL_EVAL_AT(N, L, V, P, mc);
            const float* rad = lights[l].radiance;
            r += (rad[0] * e) * v.r;
            g += (rad[1] * e) * v.g;
            b += (rad[2] * e) * v.b;
        }
        const uint keep = sl_finite_mask3(r, g, b);   // common.cl: a fragment with a non-finite channel is black
        out_r[k] = as_float(as_uint(r) & keep);
        out_g[k] = as_float(as_uint(g) & keep);
        out_b[k] = as_float(as_uint(b) & keep);
    }
    // common.cl: each plane streamed past the cache when its bit of `stream` is set
    sl_store_block(out + first, out_r, streamed & SL_STREAM_PLANE(0));
    sl_store_block(out + stride + first, out_g, streamed & SL_STREAM_PLANE(1));
    sl_store_block(out + 2 * (size_t)stride + first, out_b, streamed & SL_STREAM_PLANE(2));
}
