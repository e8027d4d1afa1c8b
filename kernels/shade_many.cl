// Many models' fragment-shading kernels in one program (Shader::prepare_many, host/shade/shader.hpp): one
// shade_fragments kernel per model, named shade_fragments_<its eval function> (shade_fragments_lambert_eval),
// the same code as kernels/shade.cl's single-model program builds for that model. A process that shades many
// models (the contact sheet) builds this once instead of one program per model: PoCL's cost of a program is
// mostly fixed (its builtin library linked in, common.cl parsed), about 0.25 s of CPU, against about 0.1 s for
// each kernel's first launch (docs/speed.md, "The whole process").
// Defines, besides SL_NUM_LIGHTS, SL_POINT_LIGHTS, SL_RANGED_LIGHTS and SL_FAST as for shade.cl (the same for
// every model):
//   SL_HEADER_0 .. SL_HEADER_15  the models' headers, e.g. <models/phong.cl> (each family file once)
//   SL_EVAL_0 .. SL_EVAL_63      the models' eval functions, e.g. phong_eval
// Models with a table (SL_TABLE) or children (SL_CHILD*) keep their own programs. The slots below are written
// out one by one (the preprocessor has no loop); Shader::kManyModels is their count.
#if defined(SL_TABLE) || defined(SL_CHILD0_EVAL)
#error "shade_many.cl holds models without tables or children only: build shade.cl for those"
#endif
#if defined(SL_EVAL_64) || defined(SL_HEADER_16)
#error "shade_many.cl has slots for 64 models and 16 headers: split the models over several programs"
#endif
#include "common.cl"
#ifdef SL_HEADER_0
#include SL_HEADER_0
#endif
#ifdef SL_HEADER_1
#include SL_HEADER_1
#endif
#ifdef SL_HEADER_2
#include SL_HEADER_2
#endif
#ifdef SL_HEADER_3
#include SL_HEADER_3
#endif
#ifdef SL_HEADER_4
#include SL_HEADER_4
#endif
#ifdef SL_HEADER_5
#include SL_HEADER_5
#endif
#ifdef SL_HEADER_6
#include SL_HEADER_6
#endif
#ifdef SL_HEADER_7
#include SL_HEADER_7
#endif
#ifdef SL_HEADER_8
#include SL_HEADER_8
#endif
#ifdef SL_HEADER_9
#include SL_HEADER_9
#endif
#ifdef SL_HEADER_10
#include SL_HEADER_10
#endif
#ifdef SL_HEADER_11
#include SL_HEADER_11
#endif
#ifdef SL_HEADER_12
#include SL_HEADER_12
#endif
#ifdef SL_HEADER_13
#include SL_HEADER_13
#endif
#ifdef SL_HEADER_14
#include SL_HEADER_14
#endif
#ifdef SL_HEADER_15
#include SL_HEADER_15
#endif
#include "shade_parts.cl"

#if defined(SL_DISPATCH) && SL_DISPATCH
// SL_DISPATCH=1: one kernel for all the models, shade_fragments_any, whose last argument `sl_model` (the same for
// every work-item) picks the eval function SL_EVAL_<sl_model>. PoCL compiles a kernel's work-group function at
// its first launch, about 0.09 s of CPU each whatever its size: one kernel for the contact sheet's 43 models
// pays that once. The eval functions are the same code as in the per-model kernels, called the same way, so the
// results are bit for bit theirs (tests/test_shade_many.cpp); the branch on sl_model is uniform but inside the
// work-item loop, which keeps it from being vectorised: for a cold run of many small launches only (the contact
// sheet), not for speed.
SL_INLINE sl_rgb sl_eval_any(uint model, sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    switch (model) {
#ifdef SL_EVAL_0
    case 0: return SL_EVAL_0(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_1
    case 1: return SL_EVAL_1(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_2
    case 2: return SL_EVAL_2(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_3
    case 3: return SL_EVAL_3(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_4
    case 4: return SL_EVAL_4(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_5
    case 5: return SL_EVAL_5(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_6
    case 6: return SL_EVAL_6(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_7
    case 7: return SL_EVAL_7(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_8
    case 8: return SL_EVAL_8(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_9
    case 9: return SL_EVAL_9(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_10
    case 10: return SL_EVAL_10(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_11
    case 11: return SL_EVAL_11(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_12
    case 12: return SL_EVAL_12(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_13
    case 13: return SL_EVAL_13(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_14
    case 14: return SL_EVAL_14(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_15
    case 15: return SL_EVAL_15(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_16
    case 16: return SL_EVAL_16(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_17
    case 17: return SL_EVAL_17(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_18
    case 18: return SL_EVAL_18(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_19
    case 19: return SL_EVAL_19(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_20
    case 20: return SL_EVAL_20(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_21
    case 21: return SL_EVAL_21(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_22
    case 22: return SL_EVAL_22(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_23
    case 23: return SL_EVAL_23(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_24
    case 24: return SL_EVAL_24(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_25
    case 25: return SL_EVAL_25(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_26
    case 26: return SL_EVAL_26(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_27
    case 27: return SL_EVAL_27(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_28
    case 28: return SL_EVAL_28(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_29
    case 29: return SL_EVAL_29(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_30
    case 30: return SL_EVAL_30(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_31
    case 31: return SL_EVAL_31(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_32
    case 32: return SL_EVAL_32(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_33
    case 33: return SL_EVAL_33(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_34
    case 34: return SL_EVAL_34(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_35
    case 35: return SL_EVAL_35(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_36
    case 36: return SL_EVAL_36(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_37
    case 37: return SL_EVAL_37(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_38
    case 38: return SL_EVAL_38(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_39
    case 39: return SL_EVAL_39(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_40
    case 40: return SL_EVAL_40(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_41
    case 41: return SL_EVAL_41(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_42
    case 42: return SL_EVAL_42(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_43
    case 43: return SL_EVAL_43(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_44
    case 44: return SL_EVAL_44(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_45
    case 45: return SL_EVAL_45(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_46
    case 46: return SL_EVAL_46(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_47
    case 47: return SL_EVAL_47(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_48
    case 48: return SL_EVAL_48(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_49
    case 49: return SL_EVAL_49(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_50
    case 50: return SL_EVAL_50(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_51
    case 51: return SL_EVAL_51(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_52
    case 52: return SL_EVAL_52(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_53
    case 53: return SL_EVAL_53(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_54
    case 54: return SL_EVAL_54(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_55
    case 55: return SL_EVAL_55(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_56
    case 56: return SL_EVAL_56(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_57
    case 57: return SL_EVAL_57(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_58
    case 58: return SL_EVAL_58(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_59
    case 59: return SL_EVAL_59(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_60
    case 60: return SL_EVAL_60(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_61
    case 61: return SL_EVAL_61(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_62
    case 62: return SL_EVAL_62(N, L, V, P, mc);
#endif
#ifdef SL_EVAL_63
    case 63: return SL_EVAL_63(N, L, V, P, mc);
#endif
    default: return sl_rgb_make(0.0f, 0.0f, 0.0f);   // not reached: Shader::prepare_many passes a slot in use
    }
}
#define SL_SHADE_KERNEL shade_fragments_any
#define SL_SHADE_EXTRA_ARGS , const uint sl_model
#define SL_EVAL(N, L, V, P, mc) sl_eval_any(sl_model, N, L, V, P, mc)
#include "shade_fragments.cl"
#else
#define SL_CAT_(a, b) a##b
#define SL_CAT(a, b) SL_CAT_(a, b)
#define SL_SHADE_KERNEL SL_CAT(shade_fragments_, SL_EVAL)
#ifdef SL_EVAL_0
#define SL_EVAL SL_EVAL_0
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_1
#define SL_EVAL SL_EVAL_1
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_2
#define SL_EVAL SL_EVAL_2
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_3
#define SL_EVAL SL_EVAL_3
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_4
#define SL_EVAL SL_EVAL_4
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_5
#define SL_EVAL SL_EVAL_5
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_6
#define SL_EVAL SL_EVAL_6
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_7
#define SL_EVAL SL_EVAL_7
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_8
#define SL_EVAL SL_EVAL_8
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_9
#define SL_EVAL SL_EVAL_9
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_10
#define SL_EVAL SL_EVAL_10
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_11
#define SL_EVAL SL_EVAL_11
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_12
#define SL_EVAL SL_EVAL_12
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_13
#define SL_EVAL SL_EVAL_13
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_14
#define SL_EVAL SL_EVAL_14
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_15
#define SL_EVAL SL_EVAL_15
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_16
#define SL_EVAL SL_EVAL_16
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_17
#define SL_EVAL SL_EVAL_17
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_18
#define SL_EVAL SL_EVAL_18
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_19
#define SL_EVAL SL_EVAL_19
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_20
#define SL_EVAL SL_EVAL_20
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_21
#define SL_EVAL SL_EVAL_21
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_22
#define SL_EVAL SL_EVAL_22
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_23
#define SL_EVAL SL_EVAL_23
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_24
#define SL_EVAL SL_EVAL_24
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_25
#define SL_EVAL SL_EVAL_25
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_26
#define SL_EVAL SL_EVAL_26
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_27
#define SL_EVAL SL_EVAL_27
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_28
#define SL_EVAL SL_EVAL_28
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_29
#define SL_EVAL SL_EVAL_29
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_30
#define SL_EVAL SL_EVAL_30
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_31
#define SL_EVAL SL_EVAL_31
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_32
#define SL_EVAL SL_EVAL_32
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_33
#define SL_EVAL SL_EVAL_33
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_34
#define SL_EVAL SL_EVAL_34
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_35
#define SL_EVAL SL_EVAL_35
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_36
#define SL_EVAL SL_EVAL_36
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_37
#define SL_EVAL SL_EVAL_37
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_38
#define SL_EVAL SL_EVAL_38
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_39
#define SL_EVAL SL_EVAL_39
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_40
#define SL_EVAL SL_EVAL_40
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_41
#define SL_EVAL SL_EVAL_41
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_42
#define SL_EVAL SL_EVAL_42
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_43
#define SL_EVAL SL_EVAL_43
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_44
#define SL_EVAL SL_EVAL_44
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_45
#define SL_EVAL SL_EVAL_45
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_46
#define SL_EVAL SL_EVAL_46
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_47
#define SL_EVAL SL_EVAL_47
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_48
#define SL_EVAL SL_EVAL_48
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_49
#define SL_EVAL SL_EVAL_49
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_50
#define SL_EVAL SL_EVAL_50
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_51
#define SL_EVAL SL_EVAL_51
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_52
#define SL_EVAL SL_EVAL_52
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_53
#define SL_EVAL SL_EVAL_53
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_54
#define SL_EVAL SL_EVAL_54
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_55
#define SL_EVAL SL_EVAL_55
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_56
#define SL_EVAL SL_EVAL_56
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_57
#define SL_EVAL SL_EVAL_57
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_58
#define SL_EVAL SL_EVAL_58
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_59
#define SL_EVAL SL_EVAL_59
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_60
#define SL_EVAL SL_EVAL_60
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_61
#define SL_EVAL SL_EVAL_61
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_62
#define SL_EVAL SL_EVAL_62
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#ifdef SL_EVAL_63
#define SL_EVAL SL_EVAL_63
#include "shade_fragments.cl"
#undef SL_EVAL
#endif
#endif
