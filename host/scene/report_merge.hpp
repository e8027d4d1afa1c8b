// Merging the reports of a sharded batch (`shadelab batch --shard i/N` on a cluster) into the report one
// unsharded run would have written: the same jobs, in the same order, with the same fields.
#pragma once
#include <string>
#include <vector>

#include "scene/batch.hpp"

namespace shadelab {

// Reads a JSON report that write_report_json wrote. Throws shadelab::Error naming the file and the field.
BatchSummary read_report_json(const std::string& path);

// The shards' jobs by index, their counts summed, shard "1/1". Refuses (one line) reports of different batches
// (another planned_total or shard count), a job index twice, or a missing shard unless allow_missing.
// wall_ms is the longest shard's (the shards ran side by side).
BatchSummary merge_reports(const std::vector<BatchSummary>& shards, const std::vector<std::string>& paths,
                           bool allow_missing = false);

}  // namespace shadelab
