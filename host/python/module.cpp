// The Python module `shadelab` (pybind11, numpy): the public C++ API (include/shadelab/) on numpy arrays.
// Errors arrive as shadelab.Error (a RuntimeError) with the same one-line messages as the command line.
#include <cstring>
#include <memory>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "shadelab/shadelab.hpp"

namespace py = pybind11;
namespace sl = shadelab::api;

namespace {

// float32, C order: numpy arrays that already are pass through without a copy.
using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

sl::Engine& engine() {
    static std::unique_ptr<sl::Engine> e;   // one PoCL context per process, made on first use
    if (!e) e = std::make_unique<sl::Engine>();
    return *e;
}

sl::Vec3 vec3(const py::handle& h, const char* what) {
    const auto v = h.cast<std::vector<double>>();
    if (v.size() != 3) throw sl::Error(std::string(what) + " must have three components (r, g, b)");
    return {v[0], v[1], v[2]};
}

// model + keyword arguments -> Material. albedo / specular are colours; every other keyword is a model parameter.
sl::Material material(const std::string& model, const py::kwargs& kw, bool* fast = nullptr) {
    sl::Material m;
    m.model = model;
    m.albedo = {1.0, 1.0, 1.0};   // the Python contract: shaded values for albedo 1
    for (const auto& item : kw) {
        const std::string key = item.first.cast<std::string>();
        if (key == "albedo") m.albedo = vec3(item.second, "albedo");
        else if (key == "specular") m.specular = vec3(item.second, "specular");
        else if (key == "fast" && fast) *fast = item.second.cast<bool>();
        else m.params[key] = item.second.cast<double>();
    }
    return m;
}

std::size_t rows_of(const FloatArray& a, const char* name) {
    if (a.ndim() != 2 || a.shape(1) != 3)
        throw sl::Error(std::string(name) + " must be an array of shape (n, 3), got " + std::to_string(a.ndim()) +
                        " dimensions");
    return std::size_t(a.shape(0));
}

std::size_t same_rows(const FloatArray& N, const FloatArray& L, const FloatArray& V) {
    const std::size_t n = rows_of(N, "N");
    if (rows_of(L, "L") != n || rows_of(V, "V") != n)
        throw sl::Error("N, L and V must have the same number of rows (" + std::to_string(n) + ", " +
                        std::to_string(L.shape(0)) + ", " + std::to_string(V.shape(0)) + ")");
    return n;
}

FloatArray shade(const std::string& model, const FloatArray& N, const FloatArray& L, const FloatArray& V,
                 const py::kwargs& kw) {
    bool fast = false;
    const sl::Material m = material(model, kw, &fast);
    const std::size_t n = same_rows(N, L, V);
    FloatArray out({py::ssize_t(n), py::ssize_t(3)});
    {
        py::gil_scoped_release release;
        engine().shade(m, N.data(), L.data(), V.data(), n, out.mutable_data(), fast);
    }
    return out;
}

py::array_t<double> reference(const std::string& model, const FloatArray& N, const FloatArray& L,
                              const FloatArray& V, const py::kwargs& kw) {
    const sl::Material m = material(model, kw);
    const std::size_t n = same_rows(N, L, V);
    py::array_t<double> out({py::ssize_t(n), py::ssize_t(3)});
    double* o = out.mutable_data();
    const float *pn = N.data(), *pl = L.data(), *pv = V.data();
    for (std::size_t i = 0; i < n; ++i) {
        const auto r = sl::reference(m, {pn[3 * i], pn[3 * i + 1], pn[3 * i + 2]},
                                     {pl[3 * i], pl[3 * i + 1], pl[3 * i + 2]}, {pv[3 * i], pv[3 * i + 1], pv[3 * i + 2]});
        std::memcpy(o + 3 * i, r.data(), 3 * sizeof(double));
    }
    return out;
}

sl::Image to_image(const FloatArray& a, const char* name) {
    if (a.ndim() != 2 && a.ndim() != 3) throw sl::Error(std::string(name) + " must be (height, width) or (height, width, channels)");
    sl::Image img;
    img.height = int(a.shape(0));
    img.width = int(a.shape(1));
    img.channels = a.ndim() == 3 ? int(a.shape(2)) : 1;
    img.pixels.assign(a.data(), a.data() + a.size());
    return img;
}

FloatArray from_image(sl::Image&& img) {
    FloatArray out({py::ssize_t(img.height), py::ssize_t(img.width), py::ssize_t(img.channels)});
    std::memcpy(out.mutable_data(), img.pixels.data(), img.pixels.size() * sizeof(float));
    return out;
}

FloatArray render(const std::string& mesh, int width, int height, const std::string& model, py::object lights,
                  py::object view_from, const py::kwargs& kw) {
    sl::RenderOptions o;
    o.width = width;
    o.height = height;
    o.material = material(model, kw, &o.fast);
    if (!view_from.is_none()) o.view_from = vec3(view_from, "view_from");
    if (!lights.is_none())
        for (const auto& l : lights.cast<std::vector<std::vector<double>>>()) {
            if (l.size() != 3) throw sl::Error("each light is a direction (x, y, z) to the light");
            sl::Light light;
            light.vec = {l[0], l[1], l[2]};
            o.lights.push_back(light);
        }
    sl::Image img;
    {
        py::gil_scoped_release release;
        img = engine().render(mesh, o);
    }
    return from_image(std::move(img));
}

py::dict compare(const FloatArray& a, const FloatArray& b) {
    const sl::Comparison c = sl::compare(to_image(a, "a"), to_image(b, "b"));
    py::dict d;
    d["pixels"] = c.pixels;
    d["coverage_mismatch"] = c.coverage_mismatch;
    d["de2000_mean"] = c.de_mean;
    d["de2000_p99"] = c.de_p99;
    d["de2000_max"] = c.de_max;
    d["rel_max"] = c.rel_max;
    d["rel_p99"] = c.rel_p99;
    return d;
}

py::dict moon_fit(const FloatArray& image, double cx, double cy, double radius, double phase, double pa,
                  const std::string& method) {
    const sl::MinnaertResult r = sl::fit_minnaert(to_image(image, "image"), {cx, cy, radius, phase, pa}, method);
    py::dict d;
    d["k"] = r.k;
    d["se_k"] = r.se_k;
    d["B0"] = r.B0;
    d["se_B0"] = r.se_B0;
    d["rms_rel"] = r.rms_rel;
    d["pixels"] = r.used;
    d["warnings"] = r.warnings;
    return d;
}

py::dict model_info(const std::string& name) {
    const sl::ModelInfo m = sl::model_info(name);
    py::list params;
    for (const auto& p : m.params) {
        py::dict d;
        d["name"] = p.name;
        d["default"] = p.def;
        d["min"] = p.min;
        d["max"] = p.max;
        d["integer"] = p.integer;
        d["doc"] = p.doc;
        params.append(d);
    }
    py::dict d;
    d["name"] = m.name;
    d["family"] = m.family;
    d["summary"] = m.summary;
    d["source"] = m.source;
    d["params"] = params;
    return d;
}

}  // namespace

PYBIND11_MODULE(shadelab, mod) {
    mod.doc() = "shadelab: classic lighting models as OpenCL kernels on PoCL, checked against double references";
    py::register_exception<sl::Error>(mod, "Error", PyExc_RuntimeError);
    mod.attr("__version__") = sl::version();
    mod.def("models", &sl::models, "Every model name of the catalogue");
    mod.def("model_info", &model_info, py::arg("name"), "A model's family, summary, source and parameters");
    mod.def("device", [] { return engine().device(); }, "The OpenCL device in use");
    mod.def("shade", &shade, py::arg("model"), py::arg("N"), py::arg("L"), py::arg("V"),
            "Shade (n, 3) float32 arrays of unit N, L, V with a catalogue model on PoCL; keyword arguments are the "
            "model's parameters (plus albedo=(r, g, b), default white, and fast=False). Returns (n, 3) float32: "
            "the value for a unit white light.");
    mod.def("reference", &reference, py::arg("model"), py::arg("N"), py::arg("L"), py::arg("V"),
            "The double-precision reference of the same evaluation as shade(): (n, 3) float64");
    mod.def("render", &render, py::arg("mesh"), py::arg("width") = 512, py::arg("height") = 512,
            py::arg("model") = "lambert", py::arg("lights") = py::none(), py::arg("view_from") = py::none(),
            "Render a mesh file (OBJ, OFF, PLY, STL) to a (height, width, 4) float32 RGBA array (linear)");
    mod.def("compare", &compare, py::arg("a"), py::arg("b"),
            "Compare two (h, w, 3|4) linear images in CIEDE2000; b is the reference");
    mod.def("moon_fit", &moon_fit, py::arg("image"), py::arg("cx"), py::arg("cy"), py::arg("radius"),
            py::arg("phase"), py::arg("pa") = 0.0, py::arg("method") = "minnaert-plot",
            "Fit Minnaert's k and B0 to a disc image (centre and radius in pixels, angles in degrees)");
}
