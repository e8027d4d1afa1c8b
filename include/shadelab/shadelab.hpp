// shadelab: classic lighting models as OpenCL kernels on PoCL, each checked against a double-precision
// reference. The whole public API (link shadelab::shadelab, or `pkg-config --cflags --libs shadelab`).
#pragma once
#include "shadelab/compare.hpp"
#include "shadelab/engine.hpp"
#include "shadelab/error.hpp"
#include "shadelab/models.hpp"
#include "shadelab/moon.hpp"
#include "shadelab/types.hpp"
