#include "scene/report_merge.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace shadelab {

namespace {

using nlohmann::json;

template <class T>
T field(const json& j, const char* key, const std::string& where) {
    if (!j.contains(key)) throw Error(where + ": no '" + key + "' field: not a shadelab batch report");
    try {
        return j.at(key).get<T>();
    } catch (const json::exception&) {
        throw Error(where + ": field '" + key + "' has the wrong type (" + j.at(key).type_name() + ")");
    }
}

JobResult::Status parse_status(const std::string& s, const std::string& where) {
    if (s == "ok") return JobResult::Status::Ok;
    if (s == "up_to_date") return JobResult::Status::Skipped;
    if (s == "failed") return JobResult::Status::Failed;
    throw Error(where + ": status '" + s + "' is not ok, up_to_date or failed");
}

}  // namespace

BatchSummary read_report_json(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Error("report '" + path + "': cannot open it: check the path");
    json doc;
    try {
        doc = json::parse(in);
    } catch (const json::exception& e) {
        throw Error("report '" + path + "': not valid JSON (" + std::string(e.what()) + ")");
    }
    const std::string where = "report '" + path + "'";
    if (!doc.is_object() || field<std::string>(doc, "tool", where) != "shadelab batch")
        throw Error(where + ": not a shadelab batch report (no \"tool\": \"shadelab batch\")");
    BatchSummary s;
    s.device = field<std::string>(doc, "device", where);
    const std::string shard = field<std::string>(doc, "shard", where);
    const auto sh = parse_shard(shard);
    s.shard_index = sh.first;
    s.shard_count = sh.second;
    s.planned_total = field<std::size_t>(doc, "planned_total", where);
    s.ok = field<std::size_t>(doc, "ok", where);
    s.skipped = field<std::size_t>(doc, "up_to_date", where);
    s.failed = field<std::size_t>(doc, "failed", where);
    s.wall_ms = field<double>(doc, "wall_ms", where);
    s.overlap = field<bool>(doc, "overlap", where);
    s.wait_ms = field<double>(doc, "wait_for_raster_ms", where);
    s.write_wait_ms = field<double>(doc, "wait_for_write_ms", where);
    s.programs_built = field<std::size_t>(doc, "programs_built", where);
    const json jobs = field<json>(doc, "jobs", where);
    if (!jobs.is_array()) throw Error(where + ": 'jobs' is not an array");
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        const json& j = jobs[i];
        const std::string w = where + ", job " + std::to_string(i + 1);
        JobResult r;
        r.job.index = field<std::size_t>(j, "index", w);
        r.job.scene = field<std::string>(j, "scene", w);
        r.job.mesh = field<std::string>(j, "mesh", w);
        r.name = field<std::string>(j, "name", w);
        r.status = parse_status(field<std::string>(j, "status", w), w);
        r.outputs = field<std::vector<std::string>>(j, "outputs", w);
        r.models = field<std::vector<std::string>>(j, "models", w);
        r.width = field<int>(j, "width", w);
        r.height = field<int>(j, "height", w);
        r.triangles = field<std::size_t>(j, "triangles", w);
        r.fragments = field<std::size_t>(j, "fragments", w);
        r.times.load_ms = field<double>(j, "load_ms", w);
        r.times.raster_ms = field<double>(j, "raster_ms", w);
        r.times.build_ms = field<double>(j, "build_ms", w);
        r.times.kernel_ms = field<double>(j, "kernel_ms", w);
        r.times.shade_ms = field<double>(j, "shade_ms", w);
        r.times.resolve_ms = j.contains("resolve_ms") ? field<double>(j, "resolve_ms", w) : 0.0;   // absent before the stage breakdown
        r.times.write_ms = field<double>(j, "write_ms", w);
        r.error = field<std::string>(j, "error", w);
        r.warnings = field<std::vector<std::string>>(j, "warnings", w);
        s.jobs.push_back(std::move(r));
    }
    if (s.jobs.size() != field<std::size_t>(doc, "jobs_in_shard", where))
        throw Error(where + ": 'jobs_in_shard' does not match the number of jobs listed: the file is damaged");
    return s;
}

BatchSummary merge_reports(const std::vector<BatchSummary>& shards, const std::vector<std::string>& paths,
                           bool allow_missing) {
    if (shards.empty()) throw Error("report merge: give the shards' reports");
    BatchSummary out;
    out.planned_total = shards[0].planned_total;
    out.device = shards[0].device;
    out.overlap = shards[0].overlap;
    std::set<int> seen_shards;
    std::map<std::size_t, std::string> owner;   // job index -> report it came from
    for (std::size_t i = 0; i < shards.size(); ++i) {
        const BatchSummary& s = shards[i];
        if (s.planned_total != out.planned_total || s.shard_count != shards[0].shard_count)
            throw Error("report merge: '" + paths[i] + "' is of another batch (" + std::to_string(s.planned_total) +
                        " jobs in " + std::to_string(s.shard_count) + " shards; '" + paths[0] + "' has " +
                        std::to_string(out.planned_total) + " in " + std::to_string(shards[0].shard_count) + ")");
        if (!seen_shards.insert(s.shard_index).second)
            throw Error("report merge: shard " + std::to_string(s.shard_index) + "/" + std::to_string(s.shard_count) +
                        " is given twice ('" + paths[i] + "')");
        for (const auto& j : s.jobs) {
            const auto [it, fresh] = owner.emplace(j.job.index, paths[i]);
            if (!fresh)
                throw Error("report merge: job " + std::to_string(j.job.index) + " is in both '" + it->second +
                            "' and '" + paths[i] + "'");
            out.jobs.push_back(j);
        }
        out.ok += s.ok;
        out.skipped += s.skipped;
        out.failed += s.failed;
        out.wall_ms = std::max(out.wall_ms, s.wall_ms);
        out.wait_ms += s.wait_ms;
        out.write_wait_ms += s.write_wait_ms;
        out.programs_built += s.programs_built;
        if (s.device != out.device) out.device += " | " + s.device;
    }
    const int n = shards[0].shard_count;
    if (!allow_missing && int(seen_shards.size()) != n) {
        std::string missing;
        for (int k = 1; k <= n; ++k)
            if (!seen_shards.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(n);
        throw Error("report merge: shard(s) " + missing + " missing: give every shard's report (or --allow-missing)");
    }
    std::sort(out.jobs.begin(), out.jobs.end(),
              [](const JobResult& a, const JobResult& b) { return a.job.index < b.job.index; });
    return out;
}

}  // namespace shadelab
