// The memory limit: moves exactly the bytes shade_fragments moves (6 float arrays in, 3 planes out) with no
// arithmetic, so a model's time divided by this one's says how close it runs to the machine's bandwidth.
__kernel void copy_like_shade(__global const float* restrict px, __global const float* restrict py,
                              __global const float* restrict pz, __global const float* restrict nx,
                              __global const float* restrict ny, __global const float* restrict nz,
                              __global float* restrict out, const uint n) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    out[i] = px[i] + nx[i];
    out[n + i] = py[i] + ny[i];
    out[2 * n + i] = pz[i] + nz[i];
}
