// The lights and the view as the shading kernels read them (kernels/shade.cl); the host fills them in
// host/shade/shader.cpp (pack_lights, Shader::shade) from the user's scene.
//
// Plain floats, not float4: a float4 field read one component at a time is a vector load plus an extract, and
// a vector instruction stops PoCL's work-item loop vectoriser (kernels/common.cl says more).
#ifndef SHADELAB_CONSTS_SCENE_H
#define SHADELAB_CONSTS_SCENE_H
#include "consts/shared.h"

SL_SHARED_BEGIN

// One light, in a __constant array.
typedef struct {
    float pos_or_dir[4];   // directional: unit direction TO the light; point: world position ([3] unused)
    float radiance[4];     // rgb = colour * intensity ([3] unused)
    float type;            // 0 directional, 1 point
    float range;           // point lights: 0 = unbounded inverse square; > 0 = windowed to 0 at range
    float unused_[2];      // keeps the struct 48 bytes, as it was with float4 fields
} DeviceLight;
SL_SIZE_IS(DeviceLight, 12)
SL_FIELD_AT(DeviceLight, pos_or_dir, 0)
SL_FIELD_AT(DeviceLight, radiance, 4)
SL_FIELD_AT(DeviceLight, type, 8)
SL_FIELD_AT(DeviceLight, range, 9)

// The viewer, passed by value.
typedef struct {
    float pos_or_dir[3];   // perspective: camera position; orthographic: unit direction to the viewer
    float perspective;     // 1 perspective (the direction to the viewer varies per fragment), 0 orthographic
} DeviceView;
SL_SIZE_IS(DeviceView, 4)
SL_FIELD_AT(DeviceView, pos_or_dir, 0)
SL_FIELD_AT(DeviceView, perspective, 3)

SL_SHARED_END

#endif
