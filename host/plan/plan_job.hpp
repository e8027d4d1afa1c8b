// Planning a job of the render path (host/pipeline/): `render --tolerance` and `batch --tolerance`.
#pragma once
#include "pipeline/pipeline.hpp"
#include "plan/planner.hpp"

namespace shadelab {

// Plans the job (docs/planner.md) and rewrites it to the chosen configuration (materials, kept lights, precision,
// per vertex); per-vertex candidates only when options.allow_per_vertex. The planning time goes to times.plan_ms.
Plan plan_job(Runtime& runtime, pipeline::Job& job, PlanOptions options, pipeline::StageTimes& times);

}  // namespace shadelab
