#include "plan/substitute.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>

#include "color/image_compare.hpp"
#include "core/error.hpp"
#include "fit/all.hpp"
#include "fit/fit.hpp"
#include "image/image.hpp"
#include "models/catalogue.hpp"
#include "raster/raster.hpp"
#include "reference/reference.hpp"

namespace shadelab {

namespace {

using clock_type = std::chrono::steady_clock;

// The scene rasterised at w x h: every item's fragments, and which item wins each pixel (nearest; ties: the
// earlier item, as the batch renderer composes them).
struct Frame {
    int width = 0, height = 0;
    std::vector<FragmentBuffer> fragments;
    std::vector<std::vector<bool>> visible;   // per item, per fragment: wins its pixel
};

Frame rasterise(const PlanInput& in, int w, int h) {
    Frame f;
    f.width = w;
    f.height = h;
    for (const PlanItem& it : in.items) {
        RasterOptions ro;
        ro.width = w;
        ro.height = h;
        ro.cull_backfaces = it.cull_backfaces;
        f.fragments.push_back(rasterize(it.mesh, in.camera, ro));
    }
    std::vector<float> z(std::size_t(w) * h, std::numeric_limits<float>::infinity());
    std::vector<std::pair<std::size_t, std::size_t>> who(z.size(), {SIZE_MAX, 0});
    for (std::size_t k = 0; k < f.fragments.size(); ++k)
        for (std::size_t i = 0; i < f.fragments[k].size(); ++i) {
            const std::size_t p = std::size_t(f.fragments[k].pixel[i]);
            if (f.fragments[k].depth[i] < z[p]) z[p] = f.fragments[k].depth[i], who[p] = {k, i};
        }
    for (const auto& fb : f.fragments) f.visible.emplace_back(fb.size(), false);
    for (const auto& w2 : who)
        if (w2.first != SIZE_MAX) f.visible[w2.first][w2.second] = true;
    return f;
}

Image compose(const Frame& f, const std::vector<std::vector<float>>& planes) {
    Image img(f.width, f.height, 4);
    for (std::size_t k = 0; k < f.fragments.size(); ++k) {
        const FragmentBuffer& fb = f.fragments[k];
        const std::size_t n = fb.size();
        for (std::size_t i = 0; i < n; ++i) {
            if (!f.visible[k][i]) continue;
            const std::size_t p = std::size_t(fb.pixel[i]);
            for (std::size_t c = 0; c < 3; ++c) img.pixels[p * 4 + c] = planes[k][c * n + i];
            img.pixels[p * 4 + 3] = 1.0f;
        }
    }
    return img;
}

std::vector<float> shade_item(Shader& sh, const FragmentBuffer& fb, const Material& m, const PlanInput& in,
                              double* kernel_ms = nullptr) {
    ShadeSetup s;
    s.material = m;
    s.lights = in.lights;
    s.ambient = in.ambient;
    s.view = glm::dvec4(in.camera.eye, 1.0);
    ShadeTiming t;
    auto out = sh.shade(fb, s, &t);
    if (kernel_ms) *kernel_ms = t.kernel_ms;
    return out;
}

double metric_of(const ImageDiff& d, const PlanOptions& o) {
    double e = o.metric == PlanMetric::DeltaE2000 ? d.de_max : d.rel_max;
    if (d.coverage_mismatch) e = std::max(e, o.metric == PlanMetric::DeltaE2000 ? 100.0 : 1.0);
    return e;
}

// The fit domain of item k: its visible fragments (at most `limit`, evenly spread), one sample per light.
fit::Domain item_domain(const Frame& f, std::size_t k, const PlanInput& in, std::size_t limit) {
    const FragmentBuffer& fb = f.fragments[k];
    std::vector<std::size_t> vis;
    for (std::size_t i = 0; i < fb.size(); ++i)
        if (f.visible[k][i]) vis.push_back(i);
    const std::size_t step = std::max<std::size_t>(1, (vis.size() + limit - 1) / limit);
    fit::Domain d;
    d.per_group = in.lights.size();
    d.ambient = in.ambient;
    for (std::size_t q = 0; q < vis.size(); q += step) {
        const std::size_t i = vis[q];
        const glm::dvec3 P(fb.px[i], fb.py[i], fb.pz[i]);
        glm::dvec3 N(fb.nx[i], fb.ny[i], fb.nz[i]);
        N = glm::length(N) > 0 ? glm::normalize(N) : glm::dvec3(0, 0, 1);
        fit::add_fragment(d, P, N, in.camera.eye, in.lights);
    }
    d.name = "item " + std::to_string(k);
    d.description = std::to_string(d.size() / std::max<std::size_t>(1, d.per_group)) + " visible fragments of mesh " +
                    std::to_string(k + 1);
    return d;
}

double mean3(const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; }

double ms_since(clock_type::time_point t) {
    return std::chrono::duration<double, std::milli>(clock_type::now() - t).count();
}

// A model's shading-kernel speed at its catalogue defaults on this device (Mfrag/s, a 32768-fragment buffer,
// best of 3): it only ranks the candidates (the plan's own timings are at full resolution), so it is measured
// once per process and device and kept (a batch plans every job with the same ranking).
double ranking_speed(Runtime& rt, const std::string& model) {
    static std::mutex mutex;
    static std::map<std::string, double> kept;
    const std::string key = rt.device_description() + "|" + model;
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (auto it = kept.find(key); it != kept.end()) return it->second;
    }
    Material m;
    m.model = model;
    add_demo_children(m, find_model(model));
    const double v = fit::measure_mfrag_per_s(rt, resolve_material(m), std::size_t(1) << 15, 3);
    std::lock_guard<std::mutex> lock(mutex);
    return kept[key] = v;
}

}  // namespace

SubstitutionPlan plan_substitutions(Runtime& rt, const PlanInput& in_raw, const PlanOptions& opt) {
    const auto t0 = clock_type::now();
    auto phase = clock_type::now();
    if (in_raw.items.empty()) throw Error("plan: the scene has no meshes");
    if (in_raw.lights.empty()) throw Error("plan: the catalogue search needs at least one light");
    PlanInput in = in_raw;
    for (auto& it : in.items) it.material = resolve_material(it.material);
    SubstitutionPlan plan;
    const double pixels = double(in.width) * in.height;
    const double scale = pixels > opt.verify_pixels ? std::sqrt(opt.verify_pixels / pixels) : 1.0;
    plan.verify_width = std::max(1, int(std::lround(in.width * scale)));
    plan.verify_height = std::max(1, int(std::lround(in.height * scale)));
    const Frame verify = rasterise(in, plan.verify_width, plan.verify_height);
    const Frame full = rasterise(in, in.width, in.height);
    Shader shader(rt);
    std::vector<std::vector<float>> ref_planes, requested_planes;
    for (std::size_t k = 0; k < in.items.size(); ++k) {
        ref_planes.push_back(ref::shade_fragments(verify.fragments[k], in.items[k].material, in.lights, in.ambient, in.camera.eye));
        requested_planes.push_back(shade_item(shader, verify.fragments[k], in.items[k].material, in));
    }
    const Image reference = compose(verify, ref_planes);
    plan.verify_ms += ms_since(phase);

    auto speed_of = [&](const std::string& model) { return ranking_speed(rt, model); };
    // Full-resolution shading time of one mesh with material m: best of at least 3 runs and 10 ms.
    auto time_item = [&](std::size_t k, const Material& m) {
        double best = std::numeric_limits<double>::infinity(), spent = 0.0;
        for (int r = 0; r < 40 && (r < 3 || spent < 10.0); ++r) {
            double ms = 0.0;
            shade_item(shader, full.fragments[k], m, in, &ms);
            best = std::min(best, ms);
            spent += ms;
        }
        return best;
    };
    std::vector<Material> chosen;
    for (std::size_t k = 0; k < in.items.size(); ++k) {
        const Material& req = in.items[k].material;
        Substitution s;
        s.item = k;
        s.requested = req;
        s.chosen = req;
        chosen.push_back(req);
        if (!req.children.empty()) {
            plan.items.push_back(s);
            continue;
        }
        phase = clock_type::now();
        const double own = speed_of(req.model);
        std::vector<std::pair<double, std::string>> cands;
        // not a table model (the empirical family): a fit varies no table, so its default tables would stand in
        for (const auto& info : model_catalogue())
            if (info.children == 0 && !has_tables(info) && info.name != req.model && speed_of(info.name) >= 1.1 * own)
                cands.push_back({speed_of(info.name), info.name});
        std::sort(cands.rbegin(), cands.rend());   // fastest first
        plan.rank_ms += ms_since(phase);
        fit::Domain d = item_domain(verify, k, in, 4096);
        if (d.size() == 0) {
            plan.items.push_back(s);
            continue;
        }
        Material grey = req;   // the fit is grey: the material's mean colours
        grey.albedo = glm::dvec3(mean3(req.albedo));
        grey.specular = glm::dvec3(mean3(req.specular));
        fit::Problem problem(rt, std::move(d), grey);
        fit::FitOptions fo;
        fo.limb_check = false;
        fo.starts = 1;   // every candidate is verified by rendering: one refined start is enough to rank it
        for (const auto& [sp, model] : cands) {
            phase = clock_type::now();
            const fit::FitResult r = fit::fit_model(problem, fit::shape_for(model, grey, -1.0, nullptr), {}, fo);
            plan.fit_ms += ms_since(phase);
            phase = clock_type::now();
            ++s.tried;
            Material sub;
            sub.model = model;
            for (const auto& p : r.params) sub.params[p.name] = p.value;
            sub.albedo = req.albedo * r.scale;
            sub.specular = req.specular * r.scale;
            sub = resolve_material(sub);
            auto planes = requested_planes;
            planes[k] = shade_item(shader, verify.fragments[k], sub, in);
            const double e = metric_of(compare_images(compose(verify, planes), reference, 1e-3), opt);
            plan.verify_ms += ms_since(phase);
            if (e > opt.tolerance) continue;
            // Within the tolerance: chosen only if this mesh really shades faster at full resolution (5%: the
            // kernels' ranking above is on a small buffer, and timings on a shared machine jitter).
            phase = clock_type::now();
            const double t_req = time_item(k, req), t_sub = time_item(k, sub);
            plan.timing_ms += ms_since(phase);
            if (!(t_sub < 0.95 * t_req)) continue;
            s.chosen = sub;
            s.fit_rel_rms = r.error.at("rel-rms");
            s.error = e;
            s.model_speedup = t_req / t_sub;
            chosen[k] = sub;
            break;
        }
        plan.items.push_back(s);
    }
    // The combination, verified and timed at full resolution.
    phase = clock_type::now();
    {
        std::vector<std::vector<float>> planes;
        for (std::size_t k = 0; k < in.items.size(); ++k) planes.push_back(shade_item(shader, verify.fragments[k], chosen[k], in));
        plan.error = metric_of(compare_images(compose(verify, planes), reference, 1e-3), opt);
        plan.within = plan.error <= opt.tolerance;
    }
    plan.verify_ms += ms_since(phase);
    phase = clock_type::now();
    auto time_all = [&](const std::vector<Material>& ms) {
        double best = std::numeric_limits<double>::infinity(), spent = 0.0;
        for (int r = 0; r < 40 && (r < std::max(1, opt.timing_repeats) || spent < 25.0); ++r) {
            double total = 0.0;
            for (std::size_t k = 0; k < in.items.size(); ++k) {
                double ms_k = 0.0;
                shade_item(shader, full.fragments[k], ms[k], in, &ms_k);
                total += ms_k;
            }
            best = std::min(best, total);
            spent += total;
        }
        return best;
    };
    std::vector<Material> requested;
    for (const auto& it : in.items) requested.push_back(it.material);
    plan.requested_ms = time_all(requested);
    plan.chosen_ms = time_all(chosen);
    plan.timing_ms += ms_since(phase);
    plan.speedup = plan.chosen_ms > 0.0 ? plan.requested_ms / plan.chosen_ms : 1.0;
    plan.planning_ms = std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
    return plan;
}

std::string format_substitutions(const SubstitutionPlan& p, const PlanOptions& opt) {
    std::ostringstream s;
    const char* metric = opt.metric == PlanMetric::DeltaE2000 ? "max Delta E 2000" : "max relative error";
    s << "catalogue search per material (verified at " << p.verify_width << "x" << p.verify_height << ", " << metric
      << " <= " << opt.tolerance << "):\n";
    auto params = [](const Material& m) {
        std::ostringstream q;
        q << m.model << "(";
        bool first = true;
        for (const auto& [k, v] : m.params) q << (first ? "" : ", ") << k << "=" << std::setprecision(5) << v, first = false;
        q << ")";
        return q.str();
    };
    for (const auto& it : p.items) {
        s << "  mesh " << (it.item + 1) << ": " << params(it.requested);
        if (it.chosen.model == it.requested.model)
            s << " kept (" << it.tried << " cheaper models fitted: none both within the tolerance and faster here)\n";
        else
            s << " -> " << params(it.chosen) << ", albedo x " << std::setprecision(4)
              << (it.requested.albedo.x > 0 ? it.chosen.albedo.x / it.requested.albedo.x : 0.0) << "; " << metric << " "
              << it.error << ", fit rel-rms " << it.fit_rel_rms << ", this mesh " << it.model_speedup << "x faster\n";
    }
    s << "  all together: " << metric << " " << p.error << (p.within ? " (within)" : " (OVER)") << "; shading "
      << std::setprecision(4) << p.chosen_ms << " ms against " << p.requested_ms << " ms requested: " << p.speedup
      << "x; planning took " << p.planning_ms << " ms (ranking " << p.rank_ms << ", fits " << p.fit_ms
      << ", verification " << p.verify_ms << ", timing " << p.timing_ms << ")\n";
    return s.str();
}

}  // namespace shadelab
