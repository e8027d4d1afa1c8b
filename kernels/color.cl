// Colour science on the device: linear sRGB -> CIE XYZ (D65) -> CIE L*a*b*, and CIEDE2000.
// The same formulas as host/color/color.cpp (the double reference), written again here in float:
// IEC 61966-2-1 primaries; CIE 1976 L*a*b* with (Xn, Yn, Zn) = (0.95047, 1, 1.08883);
// CIEDE2000 after Sharma, Wu & Dalal (2005), eqs. (1)-(22), kL = kC = kH = 1.
#include "common.cl"

SL_INLINE float3 xyz_from_linear_srgb(float3 c) {
    return (float3)(0.4124564f * c.x + 0.3575761f * c.y + 0.1804375f * c.z,
                    0.2126729f * c.x + 0.7151522f * c.y + 0.0721750f * c.z,
                    0.0193339f * c.x + 0.1191920f * c.y + 0.9503041f * c.z);
}

// f(t) of CIE 1976: cube root above (6/29)^3, the linear segment below.
SL_INLINE float lab_f(float t) {
    const float d = 6.0f / 29.0f;
    return t > d * d * d ? cbrt(t) : t / (3.0f * d * d) + 4.0f / 29.0f;
}

SL_INLINE float3 lab_from_xyz(float3 xyz) {
    const float fx = lab_f(xyz.x / 0.95047f), fy = lab_f(xyz.y), fz = lab_f(xyz.z / 1.08883f);
    return (float3)(116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz));
}

SL_INLINE float hue_deg(float b, float ap) {
    if (b == 0.0f && ap == 0.0f) return 0.0f;   // eq. (7): h' = 0 when a' = b = 0
    const float h = degrees(atan2(b, ap));
    return h < 0.0f ? h + 360.0f : h;
}

SL_INLINE float delta_e2000(float3 lab1, float3 lab2) {
    const float C7_25 = 6103515625.0f;   // 25^7
    const float Cab = 0.5f * (hypot(lab1.y, lab1.z) + hypot(lab2.y, lab2.z));
    const float Cab7 = pown(Cab, 7);
    const float G = 0.5f * (1.0f - sqrt(Cab7 / (Cab7 + C7_25)));
    const float ap1 = (1.0f + G) * lab1.y, ap2 = (1.0f + G) * lab2.y;
    const float Cp1 = hypot(ap1, lab1.z), Cp2 = hypot(ap2, lab2.z);
    const float hp1 = hue_deg(lab1.z, ap1), hp2 = hue_deg(lab2.z, ap2);
    const float dLp = lab2.x - lab1.x, dCp = Cp2 - Cp1;
    float dhp = 0.0f;
    if (Cp1 * Cp2 != 0.0f) {
        dhp = hp2 - hp1;
        if (dhp > 180.0f) dhp -= 360.0f;
        else if (dhp < -180.0f) dhp += 360.0f;
    }
    const float dHp = 2.0f * sqrt(Cp1 * Cp2) * sin(radians(0.5f * dhp));
    const float Lbp = 0.5f * (lab1.x + lab2.x), Cbp = 0.5f * (Cp1 + Cp2);
    float hbp = hp1 + hp2;
    if (Cp1 * Cp2 != 0.0f) {
        if (fabs(hp1 - hp2) <= 180.0f) hbp *= 0.5f;
        else hbp = hbp < 360.0f ? 0.5f * (hbp + 360.0f) : 0.5f * (hbp - 360.0f);
    }
    const float T = 1.0f - 0.17f * cos(radians(hbp - 30.0f)) + 0.24f * cos(radians(2.0f * hbp)) +
                    0.32f * cos(radians(3.0f * hbp + 6.0f)) - 0.20f * cos(radians(4.0f * hbp - 63.0f));
    const float q = (hbp - 275.0f) / 25.0f;
    const float dtheta = 30.0f * exp(-q * q);
    const float Cbp7 = pown(Cbp, 7);
    const float RC = 2.0f * sqrt(Cbp7 / (Cbp7 + C7_25));
    const float L50 = (Lbp - 50.0f) * (Lbp - 50.0f);
    const float SL = 1.0f + 0.015f * L50 / sqrt(20.0f + L50);
    const float SC = 1.0f + 0.045f * Cbp;
    const float SH = 1.0f + 0.015f * Cbp * T;
    const float RT = -sin(radians(2.0f * dtheta)) * RC;
    const float tL = dLp / SL, tC = dCp / SC, tH = dHp / SH;
    return sqrt(fmax(0.0f, tL * tL + tC * tC + tH * tH + RT * tC * tH));
}

// Per pixel: Lab of both images (negative light clamped to 0, as on the host) and Delta E 2000.
__kernel void delta_e2000_rgb(__global const float* restrict a, __global const float* restrict b,
                              __global float* restrict de, const uint n) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const float3 la = lab_from_xyz(xyz_from_linear_srgb(fmax(vload3(i, a), 0.0f)));
    const float3 lb = lab_from_xyz(xyz_from_linear_srgb(fmax(vload3(i, b), 0.0f)));
    de[i] = delta_e2000(la, lb);
}

// Lab pairs in, Delta E 2000 out (tested against Sharma et al.'s published pairs).
__kernel void delta_e2000_lab(__global const float* restrict a, __global const float* restrict b,
                              __global float* restrict de, const uint n) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    de[i] = delta_e2000(vload3(i, a), vload3(i, b));
}
