#include "reference/reference.hpp"

namespace shadelab::ref {

// Filled in by the model-catalogue work (issue: the model catalogue).
void add_cook_torrance_references(Table& t) { (void)t; }

}  // namespace shadelab::ref
