#include "fit/evaluate.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <exception>
#include <mutex>
#include <thread>

#include "core/error.hpp"
#include "core/format.hpp"
#include "reference/reference.hpp"

namespace shadelab::fit {

Material material_at(const ModelShape& shape, const std::vector<double>& x) {
    const ModelInfo& info = find_model(shape.model);
    if (x.size() != info.params.size())
        throw Error("internal: " + std::to_string(x.size()) + " values for the " + std::to_string(info.params.size()) +
                    " parameters of model '" + info.name + "'");
    Material m;
    m.model = info.name;
    m.albedo = shape.albedo;
    m.specular = shape.specular;
    m.children = shape.children;
    for (const auto& t : info.tables) m.tables[t.name] = t.def;   // a table model: its default tables, held
    for (std::size_t j = 0; j < x.size(); ++j) {
        const ParamSpec& p = info.params[j];
        if (!std::isfinite(x[j]) || x[j] < p.lo || x[j] > p.hi || (p.integer && x[j] != std::floor(x[j]))) {
            throw Error("internal: the fit asked for " + p.name + " = " + num(x[j], 17) + " of model '" + info.name +
                        "', outside its range [" + num(p.lo, 17) + ", " + num(p.hi, 17) + "]");
        }
        m.params[p.name] = x[j];
    }
    return m;
}

Evaluator::Evaluator(Runtime& rt, Domain domain, Precision precision)
    : shader_(rt), domain_(std::move(domain)), precision_(precision) {
    const std::size_t n = domain_.size();
    std::vector<float> N(3 * n), L(3 * n), V(3 * n), P(3 * n);
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            N[3 * i + c] = float(domain_.N[i][c]);
            L[3 * i + c] = float(domain_.L[i][c]);
            V[3 * i + c] = float(domain_.V[i][c]);
            P[3 * i + c] = float(domain_.P[i][c]);
        }
    device_ = shader_.upload_samples(N, L, V, P);
}

std::vector<float> Evaluator::kernel(const ModelShape& shape, const std::vector<std::vector<double>>& sets, int planes) {
    if (sets.empty()) return {};
    std::vector<ModelConsts> consts;
    Material first;
    std::vector<std::size_t> valid;   // the sets the model accepts, in order
    for (std::size_t s = 0; s < sets.size(); ++s) {
        if (observer) observer(shape.model, sets[s]);
        const Material m = material_at(shape, sets[s]);
        try {
            const auto k = pack_material(m);
            consts.insert(consts.end(), k.begin(), k.end());
            if (valid.empty()) first = m;
            valid.push_back(s);
        } catch (const Error&) {
            // A combination the model refuses (toon's thresholds must ascend): not evaluated; its values are
            // NaN, which the fit reads as "no value here".
        }
    }
    const std::size_t stride = std::size_t(planes) * size();
    double ms = 0.0;
    if (valid.size() == sets.size()) {
        auto got = shader_.eval_batch(first, device_, consts, precision_, &ms, planes);
        kernel_ms_ += ms;
        kernel_evals_ += sets.size() * size();
        return got;
    }
    std::vector<float> out(sets.size() * stride, std::nanf(""));
    if (!valid.empty()) {
        const auto got = shader_.eval_batch(first, device_, consts, precision_, &ms, planes);
        for (std::size_t q = 0; q < valid.size(); ++q)
            std::copy_n(got.begin() + q * stride, stride, out.begin() + valid[q] * stride);
    }
    kernel_ms_ += ms;
    kernel_evals_ += valid.size() * size();
    return out;
}

bool Evaluator::accepts(const Material& m) {
    try {
        pack_material(m);
        return true;
    } catch (const Error&) {
        return false;
    }
}

namespace {

// A material as numbers, children included (their model names go into `names`): equal keys, equal values.
void material_key(const Material& m, std::vector<double>& key, std::string& names) {
    names += m.model + ";";
    for (const auto& [name, v] : m.params) {
        names += name + ",";
        key.push_back(v);
    }
    for (int c = 0; c < 3; ++c) key.push_back(m.albedo[c]), key.push_back(m.specular[c]);
    key.push_back(double(m.children.size()));
    for (const auto& ch : m.children) material_key(ch, key, names);
}

constexpr std::size_t kKeptReferences = 4;

}  // namespace

std::vector<double> Evaluator::reference(const Material& m) {
    std::vector<double> key;
    std::string names;
    material_key(m, key, names);
    for (auto it = kept_.begin(); it != kept_.end(); ++it)
        if (it->model == names && it->key == key) {
            Kept k = std::move(*it);
            kept_.erase(it);
            kept_.push_back(std::move(k));
            return kept_.back().values;
        }
    std::vector<double> out = evaluate_reference(m);
    if (kept_.size() >= kKeptReferences) kept_.erase(kept_.begin());
    kept_.push_back(Kept{std::move(key), std::move(names), out});
    return out;
}

std::vector<double> Evaluator::evaluate_reference(const Material& m) {
    if (observer) {
        const ModelInfo& info = find_model(m.model);
        std::vector<double> x;
        for (const auto& p : info.params) x.push_back(m.params.at(p.name));
        observer(m.model, x);
    }
    const std::size_t n = size();
    std::vector<double> out(3 * n);
    const ref::ModelFn& f = ref::reference_for(m.model);
    // A reference that throws (a combination it refuses) must not end the process from a worker thread: the
    // first exception is kept and rethrown here.
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto run = [&](std::size_t a, std::size_t b) {
        try {
            for (std::size_t i = a; i < b; ++i) {
                const glm::dvec3 v = f(domain_.N[i], domain_.L[i], domain_.V[i], domain_.P[i], m);
                for (int c = 0; c < 3; ++c) out[c * n + i] = std::isfinite(v[c]) ? v[c] : 0.0;
            }
        } catch (...) {
            std::lock_guard<std::mutex> lock(failure_mutex);
            if (!failure) failure = std::current_exception();
        }
    };
    const unsigned threads = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
    if (threads == 1 || n < 2048) {
        run(0, n);
    } else {
        std::vector<std::thread> pool;
        const std::size_t per = (n + threads - 1) / threads;
        for (unsigned t = 0; t < threads; ++t) {
            const std::size_t a = std::min(n, t * per), b = std::min(n, a + per);
            pool.emplace_back(run, a, b);
        }
        for (auto& t : pool) t.join();
    }
    if (failure) std::rethrow_exception(failure);
    reference_evals_ += n;
    return out;
}

}  // namespace shadelab::fit
