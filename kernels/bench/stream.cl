// STREAM's copy and triad (McCalpin, "Memory Bandwidth and Machine Balance in Current High Performance
// Computers", IEEE TCCA Newsletter, 1995; www.cs.virginia.edu/stream), on the OpenCL device: the memory
// bandwidth a kernel of the same shape as the shading kernels can reach. Written as shade_fragments is launched
// (kernels/shade.cl): a size_t index and no bounds check (the host rounds the arrays up to the launch size), so
// every access is a contiguous vector load or store once PoCL vectorises the work-item loop. A uint index would
// make them gathers, and a bounds check would put them under a condition (docs/speed.md).
//   copy:  c[i] = a[i]               8 bytes per element
//   triad: a[i] = b[i] + s c[i]      12 bytes per element (STREAM counts no write-allocate traffic)

__kernel void stream_copy(__global const float* restrict a, __global float* restrict c) {
    const size_t i = get_global_id(0);
    c[i] = a[i];
}

__kernel void stream_triad(__global float* restrict a, __global const float* restrict b,
                           __global const float* restrict c, const float s) {
    const size_t i = get_global_id(0);
    a[i] = b[i] + s * c[i];
}

// The same two with streaming (non-temporal) stores, as the shade kernels write planes past the cache
// (kernels/common.cl, sl_store_block): 16 elements a work-item, stored as one aligned float16 line with
// __builtin_nontemporal_store (x86 MOVNTPS), so a line is written without first being read (no write-allocate).
// STREAM's own C code, built with plain stores, pays that read; bench_models sets a model's bandwidth against
// the better of the two triads, so that a kernel's streaming stores do not make the yardstick look slow. The host
// launches n / 16 work-items over arrays aligned to 128 bytes (PoCL's buffers) of a multiple of 16 elements.
__kernel void stream_copy_nt(__global const float* restrict a, __global float* restrict c) {
    const size_t i = get_global_id(0);
    __builtin_nontemporal_store(vload16(i, a), (__global float16*)c + i);
}

__kernel void stream_triad_nt(__global float* restrict a, __global const float* restrict b,
                              __global const float* restrict c, const float s) {
    const size_t i = get_global_id(0);
    __builtin_nontemporal_store(vload16(i, b) + s * vload16(i, c), (__global float16*)a + i);
}
