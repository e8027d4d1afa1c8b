// What lets one header declare a struct for both the OpenCL C kernels and the C++ host (Blender Cycles'
// kernel/types.h habit): the structs the device reads are written once, as plain C with float fields, and
// the host checks their layout at compile time; tests/test_layout.cpp checks it once more on the device.
//
//   SL_SHARED_BEGIN / SL_SHARED_END   namespace shadelab { } on the host, nothing in OpenCL C
//   SL_SIZE_IS(T, n)                  T is n floats: no padding, nothing else
//   SL_FIELD_AT(T, field, k)          T.field starts at float k
// On the host the last two are static_asserts. In OpenCL C they are nothing, except when the file is built with
// SL_LAYOUT_PROBE (tests/test_layout.cpp only): each becomes a tiny kernel that writes what the device's compiler
// made of the layout (sizeof, offsetof) next to the expected number, so the host can compare the two.
#ifndef SHADELAB_CONSTS_SHARED_H
#define SHADELAB_CONSTS_SHARED_H

#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#define SL_SHARED_BEGIN
#define SL_SHARED_END
#if defined(SL_LAYOUT_PROBE)
#define SL_SIZE_IS(T, n) \
    __kernel void sl_probe_size_##T(__global uint* out) { out[0] = (uint)sizeof(T); out[1] = (uint)((n) * sizeof(float)); }
#define SL_FIELD_AT(T, field, k)                                              \
    __kernel void sl_probe_field_##T##_##field(__global uint* out) {          \
        out[0] = (uint)__builtin_offsetof(T, field); out[1] = (uint)((k) * sizeof(float)); }
#else
#define SL_SIZE_IS(T, n)
#define SL_FIELD_AT(T, field, k)
#endif
#else
#include <cstddef>
#define SL_SHARED_BEGIN namespace shadelab {
#define SL_SHARED_END }
#define SL_SIZE_IS(T, n) static_assert(sizeof(T) == (n) * sizeof(float), #T " must be " #n " floats, no padding");
#define SL_FIELD_AT(T, field, k) \
    static_assert(offsetof(T, field) == (k) * sizeof(float), #T "." #field " must start at float " #k);
#endif

#endif
