// What every family's registration fills the same way for each of its models (host/models/<family>.cpp): its
// names, its source and the kernel function in the family's kernel file. The family name and the doc page are
// set from the ModelFamily the model is registered in (catalogue.cpp), so they are not repeated here.
#pragma once
#include "models/catalogue.hpp"

namespace shadelab {

inline ModelInfo model_info(const char* header, const char* name, const char* summary, const char* source,
                            const char* eval) {
    ModelInfo m;
    m.name = name;
    m.summary = summary;
    m.source = source;
    m.header = header;
    m.eval = eval;
    return m;
}

}  // namespace shadelab
