// Many models' fragment-shading kernels in one program (Shader::prepare_many, host/shade/shader.hpp): one
// shade_fragments kernel per model, named shade_fragments_<its eval function> (shade_fragments_lambert_eval),
// the same code as kernels/shade.cl's single-model program builds for that model. A process that shades many
// models (the contact sheet) builds this once instead of one program per model: PoCL's cost of a program is
// mostly fixed (its builtin library linked in, common.cl parsed), about 0.25 s of CPU, against about 0.1 s for
// each kernel's first launch (docs/speed.md, "The whole process").
// Defines, besides SL_NUM_LIGHTS, SL_ALL_DIRECTIONAL and SL_FAST as for shade.cl (the same for every model):
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
