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
