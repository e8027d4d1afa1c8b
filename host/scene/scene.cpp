// Scene-file parsing and validation (schema: docs/batch.md).
#include "scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "core/format.hpp"
#include "core/text.hpp"
#include "image/image.hpp"
#include "models/catalogue.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace shadelab {

namespace {

constexpr int kMaxSide = 16384;
constexpr std::size_t kMaxLights = 64;   // each light count is its own program (the loop is unrolled)
constexpr int kMaxMaterialDepth = 4;     // named materials referring to names: stops a cycle
constexpr std::uintmax_t kMaxSceneBytes = 16u << 20;   // the bundled scenes are under 4 kB
constexpr int kMaxJsonDepth = 32;        // the deepest scene key is 6 levels down

const std::map<std::string, std::vector<std::string>>& schema_keys() {
    static const std::map<std::string, std::vector<std::string>> k{
        {"scene", {"name", "camera", "resolution", "meshes", "materials", "lights", "ambient", "background",
                   "outputs", "precision", "per_vertex"}},
        {"camera", {"fit", "view_from", "position", "target", "up", "fov"}},
        {"mesh", {"path", "transform", "material", "cull_backfaces"}},
        {"transform", {"matrix", "translate", "rotate", "scale"}},
        {"material", {"model", "params", "albedo", "specular", "children"}},
        {"light", {"type", "direction", "position", "colour", "color", "intensity", "range"}},
        {"outputs", {"png", "exr", "depth", "normal"}},
    };
    return k;
}

std::string type_of(const json& v) {
    std::string s = v.dump();
    if (s.size() > 40) s = s.substr(0, 37) + "...";
    return std::string(v.type_name()) + " " + s;
}

// Parsing context: the file for messages and the folder mesh paths are relative to.
class Parser {
public:
    Parser(std::string file, const SceneLoadOptions& opt) : file_(std::move(file)), opt_(opt) {}

    [[noreturn]] void fail(const std::string& field, const std::string& what) const {
        throw Error("scene '" + file_ + "': " + (field.empty() ? "" : field + ": ") + what);
    }
    std::string where(const std::string& field) const { return "scene '" + file_ + "': " + field; }

    // Unknown keys are errors (a misspelt key would otherwise be ignored silently and the image would be
    // wrong without a word); keys starting with '_' are comments and skipped.
    void check_keys(const json& obj, const std::string& kind, const std::string& field) const {
        if (!obj.is_object()) fail(field, "expected an object, got " + type_of(obj));
        const auto& known = schema_keys().at(kind);
        for (auto it = obj.begin(); it != obj.end(); ++it) {
            const std::string& key = it.key();
            if (!key.empty() && key[0] == '_') continue;
            if (std::find(known.begin(), known.end(), key) != known.end()) continue;
            std::string best;
            std::size_t best_d = 3;
            for (const auto& k : known) {
                const std::size_t d = edit_distance(key, k);
                if (d < best_d) { best_d = d; best = k; }
            }
            std::string list;
            for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
            fail(join(field, key), "unknown key" + (best.empty() ? "" : " (did you mean '" + best + "'?)") +
                                       "; known keys here: " + list + " (keys starting with '_' are comments)");
        }
    }

    static std::string join(const std::string& field, const std::string& key) {
        return field.empty() ? key : field + "." + key;
    }
    static std::string index(const std::string& field, std::size_t i) {
        return field + "[" + std::to_string(i) + "]";
    }

    double number(const json& v, const std::string& field, double lo, double hi) const {
        if (!v.is_number()) fail(field, "expected a number, got " + type_of(v));
        const double x = v.get<double>();
        if (!std::isfinite(x) || x < lo || x > hi)
            fail(field, num(x) + " is out of range: allowed [" + num(lo) + ", " + num(hi) + "]");
        return x;
    }
    int integer(const json& v, const std::string& field, int lo, int hi) const {
        const double x = number(v, field, lo, hi);
        if (x != std::floor(x)) fail(field, num(x) + " must be a whole number");
        return int(x);
    }
    bool boolean(const json& v, const std::string& field) const {
        if (!v.is_boolean()) fail(field, "expected true or false, got " + type_of(v));
        return v.get<bool>();
    }
    std::string string(const json& v, const std::string& field) const {
        if (!v.is_string()) fail(field, "expected a string, got " + type_of(v));
        return v.get<std::string>();
    }
    std::vector<double> numbers(const json& v, const std::string& field, std::size_t n_min, std::size_t n_max,
                                double lo, double hi) const {
        const std::string count = n_min == n_max ? std::to_string(n_min)
                                                 : std::to_string(n_min) + " or " + std::to_string(n_max);
        if (!v.is_array() || v.size() < n_min || v.size() > n_max)
            fail(field, "expected an array of " + count + " numbers, got " + type_of(v));
        std::vector<double> out;
        for (std::size_t i = 0; i < v.size(); ++i) out.push_back(number(v[i], index(field, i), lo, hi));
        return out;
    }
    glm::dvec3 vec3(const json& v, const std::string& field, double lo = -1e30, double hi = 1e30) const {
        const auto a = numbers(v, field, 3, 3, lo, hi);
        return {a[0], a[1], a[2]};
    }
    glm::dvec3 direction(const json& v, const std::string& field) const {
        const glm::dvec3 d = vec3(v, field);
        if (!(glm::length(d) > 0.0)) fail(field, "a direction must not be the zero vector");
        return d;
    }

    const std::string& file() const { return file_; }
    const SceneLoadOptions& options() const { return opt_; }

private:
    std::string file_;
    const SceneLoadOptions& opt_;
};

glm::dmat4 parse_transform(const Parser& p, const json& t, const std::string& field) {
    p.check_keys(t, "transform", field);
    if (t.contains("matrix")) {
        for (const char* k : {"translate", "rotate", "scale"})
            if (t.contains(k)) p.fail(Parser::join(field, k), "cannot be combined with 'matrix' (give one or the other)");
        const std::string f = Parser::join(field, "matrix");
        json flat = t["matrix"];
        if (flat.is_array() && flat.size() == 4 && flat[0].is_array()) {
            json rows = json::array();
            for (std::size_t r = 0; r < 4; ++r) {
                if (!flat[r].is_array() || flat[r].size() != 4) p.fail(Parser::index(f, r), "expected a row of 4 numbers");
                for (const auto& x : flat[r]) rows.push_back(x);
            }
            flat = rows;
        }
        const auto a = p.numbers(flat, f, 16, 16, -1e30, 1e30);
        glm::dmat4 m(1.0);
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) m[c][r] = a[std::size_t(r * 4 + c)];   // written row-major, glm is column-major
        if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
            p.fail(f, "the last row must be 0 0 0 1 (an affine transform)");
        if (!(std::abs(glm::determinant(glm::dmat3(m))) > 1e-300)) p.fail(f, "the matrix is singular (it flattens the mesh)");
        return m;
    }
    glm::dmat4 m(1.0);
    if (t.contains("translate")) m = glm::translate(m, p.vec3(t["translate"], Parser::join(field, "translate")));
    if (t.contains("rotate")) {
        // Degrees about x, then y, then z (extrinsic): R = Rz Ry Rx.
        const glm::dvec3 r = p.vec3(t["rotate"], Parser::join(field, "rotate"), -36000.0, 36000.0);
        m = glm::rotate(m, glm::radians(r.z), glm::dvec3(0, 0, 1));
        m = glm::rotate(m, glm::radians(r.y), glm::dvec3(0, 1, 0));
        m = glm::rotate(m, glm::radians(r.x), glm::dvec3(1, 0, 0));
    }
    if (t.contains("scale")) {
        const std::string f = Parser::join(field, "scale");
        glm::dvec3 s;
        if (t["scale"].is_number()) s = glm::dvec3(p.number(t["scale"], f, -1e30, 1e30));
        else s = p.vec3(t["scale"], f);
        if (s.x == 0.0 || s.y == 0.0 || s.z == 0.0) p.fail(f, "a zero scale flattens the mesh: every factor must be non-zero");
        m = glm::scale(m, s);
    }
    return m;
}

class MaterialParser {
public:
    MaterialParser(const Parser& p, const json& library) : p_(p), lib_(library) {}

    // A material is an object, or a string naming an entry of the top-level "materials".
    Material parse(const json& v, const std::string& field, int depth = 0) {
        if (depth > kMaxMaterialDepth) p_.fail(field, "materials refer to each other too deeply (a cycle?)");
        if (v.is_string()) {
            const std::string name = v.get<std::string>();
            if (!lib_.is_object() || !lib_.contains(name)) {
                std::string names;
                if (lib_.is_object())
                    for (auto it = lib_.begin(); it != lib_.end(); ++it) names += (names.empty() ? "" : ", ") + it.key();
                p_.fail(field, "no material named '" + name + "' in \"materials\"" +
                                   (names.empty() ? std::string(" (there are none)") : " (there are: " + names + ")"));
            }
            used_.push_back(name);
            return parse(lib_[name], "materials." + name, depth + 1);
        }
        p_.check_keys(v, "material", field);
        Material m;
        if (v.contains("model")) m.model = p_.string(v["model"], Parser::join(field, "model"));
        if (v.contains("params")) {
            const std::string f = Parser::join(field, "params");
            const json& ps = v["params"];
            if (!ps.is_object()) p_.fail(f, "expected an object of name: number (or name: [numbers]), got " + type_of(ps));
            for (auto it = ps.begin(); it != ps.end(); ++it) {
                const std::string fk = Parser::join(f, it.key());
                if (!it.value().is_array()) {
                    m.params[it.key()] = p_.number(it.value(), fk, -1e30, 1e30);
                    continue;
                }
                // a table-valued parameter (the empirical family's phase_list, k_list, ...)
                std::vector<double>& t = m.tables[it.key()];
                for (std::size_t j = 0; j < it.value().size(); ++j)
                    t.push_back(p_.number(it.value()[j], Parser::index(fk, j), -1e30, 1e30));
            }
        }
        if (v.contains("albedo")) m.albedo = p_.vec3(v["albedo"], Parser::join(field, "albedo"), 0.0, 1e6);
        if (v.contains("specular")) m.specular = p_.vec3(v["specular"], Parser::join(field, "specular"), 0.0, 1e6);
        if (v.contains("children")) {
            const std::string f = Parser::join(field, "children");
            const json& cs = v["children"];
            if (!cs.is_array()) p_.fail(f, "expected an array of materials, got " + type_of(cs));
            for (std::size_t i = 0; i < cs.size(); ++i) m.children.push_back(parse(cs[i], Parser::index(f, i), depth + 1));
        }
        // Model name, parameter names, ranges and child count: the catalogue's own checks and messages.
        return resolve_material(m, p_.where(field));
    }

    const std::vector<std::string>& used() const { return used_; }

private:
    const Parser& p_;
    const json& lib_;
    std::vector<std::string> used_;
};

Light parse_light(const Parser& p, const json& v, const std::string& field) {
    p.check_keys(v, "light", field);
    if (!v.contains("type")) p.fail(field, "missing \"type\": \"directional\" or \"point\"");
    const std::string type = p.string(v["type"], Parser::join(field, "type"));
    Light l;
    if (type == "directional") {
        l.type = Light::Type::Directional;
        if (!v.contains("direction")) p.fail(field, "a directional light needs \"direction\" (the direction TO the light)");
        if (v.contains("position")) p.fail(Parser::join(field, "position"), "a directional light has a direction, not a position");
        if (v.contains("range")) p.fail(Parser::join(field, "range"), "only point lights have a range");
        l.vec = p.direction(v["direction"], Parser::join(field, "direction"));
    } else if (type == "point") {
        l.type = Light::Type::Point;
        if (!v.contains("position")) p.fail(field, "a point light needs \"position\"");
        if (v.contains("direction")) p.fail(Parser::join(field, "direction"), "a point light has a position, not a direction");
        l.vec = p.vec3(v["position"], Parser::join(field, "position"));
        if (v.contains("range")) l.range = p.number(v["range"], Parser::join(field, "range"), 0.0, 1e30);
    } else {
        p.fail(Parser::join(field, "type"), "'" + type + "' is not a light type: use \"directional\" or \"point\"");
    }
    if (v.contains("colour") && v.contains("color")) p.fail(field, "give \"colour\" or \"color\", not both");
    for (const char* k : {"colour", "color"})
        if (v.contains(k)) l.colour = p.vec3(v[k], Parser::join(field, k), 0.0, 1e6);
    if (v.contains("intensity")) l.intensity = p.number(v["intensity"], Parser::join(field, "intensity"), 0.0, 1e12);
    return l;
}

std::string stem_of(const std::string& path) { return fs::path(path).stem().string(); }

// Expands {name}, {scene} and {mesh}; anything else in braces is an error.
std::string expand(const Parser& p, const std::string& pattern, const std::string& field,
                   const std::map<std::string, std::string>& vars) {
    std::string out;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '{') { out += pattern[i]; continue; }
        const std::size_t close = pattern.find('}', i);
        if (close == std::string::npos) p.fail(field, "unclosed '{' in '" + pattern + "'");
        const std::string var = pattern.substr(i + 1, close - i - 1);
        const auto it = vars.find(var);
        if (it == vars.end()) p.fail(field, "unknown placeholder '{" + var + "}' in '" + pattern + "': use {name}, {scene} or {mesh}");
        out += it->second;
        i = close;
    }
    return out;
}

}  // namespace

std::vector<std::string> SceneOutputs::all() const {
    std::vector<std::string> v;
    for (const auto* s : {&png, &exr, &depth, &normal})
        if (!s->empty()) v.push_back(*s);
    return v;
}

const std::vector<std::string>& scene_keys(const std::string& object) {
    const auto it = schema_keys().find(object);
    if (it == schema_keys().end()) throw Error("internal: no scene object kind '" + object + "'");
    return it->second;
}

namespace {

SceneMesh parse_mesh(const Parser& p, MaterialParser& mp, const json& m, std::size_t i) {
    const SceneLoadOptions& opt = p.options();
    const bool template_mode = !opt.mesh_override.empty();
    const std::string f = Parser::index("meshes", i);
    p.check_keys(m, "mesh", f);
    SceneMesh sm;
    if (template_mode) {
        sm.path = sm.path_written = opt.mesh_override;
    } else {
        if (!m.contains("path")) p.fail(f, "missing \"path\" (the mesh file, relative to the scene file's folder)");
        sm.path_written = p.string(m["path"], Parser::join(f, "path"));
        if (sm.path_written.empty()) p.fail(Parser::join(f, "path"), "is empty");
        const fs::path mp_path(sm.path_written);
        const fs::path folder = fs::path(p.file()).parent_path();
        sm.path = (mp_path.is_absolute() ? mp_path : (folder / mp_path).lexically_normal()).string();
    }
    std::error_code ec;
    if (!fs::is_regular_file(sm.path, ec))
        p.fail(template_mode ? f : Parser::join(f, "path"),
               "mesh '" + sm.path_written + "' not found" +
                   (sm.path == sm.path_written ? std::string() : " (looked for '" + sm.path + "': mesh paths are relative to the scene file's folder)"));
    if (m.contains("transform")) sm.transform = parse_transform(p, m["transform"], Parser::join(f, "transform"));
    sm.material = m.contains("material") ? mp.parse(m["material"], Parser::join(f, "material"))
                                         : resolve_material(Material{}, p.where(f));
    if (m.contains("cull_backfaces")) sm.cull_backfaces = p.boolean(m["cull_backfaces"], Parser::join(f, "cull_backfaces"));
    return sm;
}

// Meshes first: their stems feed the job name and {mesh}.
void parse_meshes(const Parser& p, const json& doc, Scene& s) {
    const bool template_mode = !p.options().mesh_override.empty();
    const json library = doc.contains("materials") ? doc["materials"] : json::object();
    if (!library.is_object()) p.fail("materials", "expected an object of name: material, got " + type_of(library));
    MaterialParser mp(p, library);
    if (!doc.contains("meshes")) p.fail("meshes", "missing: a scene needs at least one mesh");
    const json& meshes = doc["meshes"];
    if (!meshes.is_array() || meshes.empty()) p.fail("meshes", "expected a non-empty array of meshes, got " + type_of(meshes));
    if (template_mode && meshes.size() != 1)
        p.fail("meshes", "a template scene (--scene with --meshes) must have exactly one mesh entry, whose path is "
                         "replaced by each mesh of the folder; this one has " + std::to_string(meshes.size()));
    for (std::size_t i = 0; i < meshes.size(); ++i) s.meshes.push_back(parse_mesh(p, mp, meshes[i], i));
    // Library entries nobody uses are still checked (an error there is an error in the file).
    for (auto it = library.begin(); it != library.end(); ++it) {
        if (std::find(mp.used().begin(), mp.used().end(), it.key()) != mp.used().end()) continue;
        MaterialParser(p, library).parse(it.value(), "materials." + it.key(), 1);
        s.warnings.push_back("materials." + it.key() + " is not used by any mesh");
    }
}

void parse_name(const Parser& p, const json& doc, Scene& s) {
    const SceneLoadOptions& opt = p.options();
    const bool template_mode = !opt.mesh_override.empty();
    if (template_mode) s.name = stem_of(opt.mesh_override);
    else if (doc.contains("name")) s.name = p.string(doc["name"], "name");
    else s.name = stem_of(p.file());
    if (s.name.empty() || s.name.find_first_of("/\\") != std::string::npos)
        p.fail("name", "'" + s.name + "' cannot name output files (empty or contains a path separator)");
    if (template_mode && doc.contains("name")) s.warnings.push_back("name is ignored in template mode: each job is named after its mesh");
}

SceneCamera parse_camera(const Parser& p, const json& c) {
    p.check_keys(c, "camera", "camera");
    SceneCamera cam;
    const bool has_pos = c.contains("position");
    cam.fit = c.contains("fit") ? p.boolean(c["fit"], "camera.fit") : !has_pos;
    if (cam.fit && has_pos) p.fail("camera", "\"fit\": true and \"position\" both given: fit places the camera itself; drop one");
    if (!cam.fit && !has_pos) p.fail("camera", "\"fit\": false needs \"position\"");
    if (!cam.fit && c.contains("view_from")) p.fail("camera.view_from", "only used when the camera is fitted (no \"position\")");
    if (cam.fit && c.contains("target")) p.fail("camera.target", "a fitted camera looks at the centre of the meshes' bounds; give \"position\" to aim it yourself");
    if (c.contains("view_from")) cam.view_from = p.direction(c["view_from"], "camera.view_from");
    if (has_pos) cam.position = p.vec3(c["position"], "camera.position");
    if (c.contains("target")) { cam.target = p.vec3(c["target"], "camera.target"); cam.has_target = true; }
    if (c.contains("up")) cam.up = p.direction(c["up"], "camera.up");
    if (c.contains("fov")) cam.fov_deg = p.number(c["fov"], "camera.fov", 1.0, 170.0);
    if (!cam.fit) {
        if (cam.has_target && glm::length(cam.target - cam.position) == 0.0)
            p.fail("camera.target", "equals the camera position: the view direction is undefined");
        const glm::dvec3 dir = cam.has_target ? cam.target - cam.position : glm::dvec3(0.0);
        if (cam.has_target && glm::length(glm::cross(glm::normalize(dir), glm::normalize(cam.up))) < 1e-9)
            p.fail("camera.up", "is parallel to the view direction: choose another up vector");
    }
    return cam;
}

// resolution, lights, ambient, background, precision, per_vertex.
void parse_look(const Parser& p, const json& doc, Scene& s) {
    if (doc.contains("resolution")) {
        const json& r = doc["resolution"];
        if (!r.is_array() || r.size() != 2) p.fail("resolution", "expected [width, height], got " + type_of(r));
        s.width = p.integer(r[0], "resolution[0]", 1, kMaxSide);
        s.height = p.integer(r[1], "resolution[1]", 1, kMaxSide);
    }
    if (doc.contains("lights")) {
        const json& ls = doc["lights"];
        if (!ls.is_array()) p.fail("lights", "expected an array of lights, got " + type_of(ls));
        if (ls.size() > kMaxLights) p.fail("lights", std::to_string(ls.size()) + " lights: at most " + std::to_string(kMaxLights));
        for (std::size_t i = 0; i < ls.size(); ++i) s.lights.push_back(parse_light(p, ls[i], Parser::index("lights", i)));
    } else {
        s.lights.push_back(Light{Light::Type::Directional, {1.0, 1.0, 1.0}, {1.0, 1.0, 1.0}, 1.0, 0.0});
    }
    if (doc.contains("ambient")) s.ambient = p.vec3(doc["ambient"], "ambient", 0.0, 1e6);
    if (s.lights.empty() && s.ambient == glm::dvec3(0.0))
        s.warnings.push_back("no lights and no ambient: every covered pixel will be black");
    if (doc.contains("background")) {
        const auto b = p.numbers(doc["background"], "background", 3, 4, -1e6, 1e6);
        s.background = glm::dvec4(b[0], b[1], b[2], b.size() == 4 ? b[3] : 1.0);
        if (s.background.a < 0.0 || s.background.a > 1.0) p.fail("background[3]", "alpha must be in [0, 1]");
    }
    if (doc.contains("precision")) {
        const std::string pr = p.string(doc["precision"], "precision");
        if (pr != "precise" && pr != "fast") p.fail("precision", "'" + pr + "': use \"precise\" or \"fast\"");
        s.precision = parse_precision(pr);
    }
    if (doc.contains("per_vertex")) s.per_vertex = p.boolean(doc["per_vertex"], "per_vertex");
}

// Outputs: placeholders expanded, then relative paths resolved against the output folder.
void parse_outputs(const Parser& p, const json& doc, Scene& s) {
    const std::map<std::string, std::string> vars{
        {"name", s.name}, {"scene", stem_of(p.file())}, {"mesh", stem_of(s.meshes.front().path)}};
    std::map<std::string, std::string> outs{{"png", "{name}.png"}};
    if (doc.contains("outputs")) {
        const json& o = doc["outputs"];
        p.check_keys(o, "outputs", "outputs");
        if (o.empty()) p.fail("outputs", "is empty: give at least one of png, exr, depth, normal");
        outs.clear();
        for (auto it = o.begin(); it != o.end(); ++it)
            if (it.key()[0] != '_') outs[it.key()] = p.string(it.value(), "outputs." + it.key());
    }
    std::vector<std::string> seen;
    for (const auto& [key, pattern] : outs) {
        const std::string f = "outputs." + key;
        const std::string rel = expand(p, pattern, f, vars);
        if (rel.empty()) p.fail(f, "is empty");
        Encoding enc;
        try {
            enc = encoding_for(rel);
        } catch (const Error& e) {
            p.fail(f, e.what());
        }
        if (key == "png" && enc != Encoding::Srgb8)
            p.fail(f, "'" + rel + "' is not an 8-bit sRGB format: use .png (or put a linear file under \"exr\")");
        if (key != "png" && enc != Encoding::Linear)
            p.fail(f, "'" + rel + "' is not a linear float format: use .exr");
        const fs::path path(rel);
        const std::string full = path.is_absolute() ? rel : (fs::path(p.options().out_dir) / path).lexically_normal().string();
        if (std::find(seen.begin(), seen.end(), full) != seen.end()) p.fail(f, "'" + full + "' is already written by another output");
        seen.push_back(full);
        if (key == "png") s.outputs.png = full;
        else if (key == "exr") s.outputs.exr = full;
        else if (key == "depth") s.outputs.depth = full;
        else s.outputs.normal = full;
    }
}

}  // namespace

Scene parse_scene(const json& doc, const std::string& file, const SceneLoadOptions& opt) {
    const Parser p(file, opt);
    p.check_keys(doc, "scene", "");
    Scene s;
    s.file = file;
    parse_meshes(p, doc, s);
    parse_name(p, doc, s);
    if (doc.contains("camera")) s.camera = parse_camera(p, doc["camera"]);
    parse_look(p, doc, s);
    parse_outputs(p, doc, s);
    return s;
}

Scene load_scene(const std::string& file, const SceneLoadOptions& opt) {
    const std::string at = "scene '" + file + "': ";
    std::error_code ec;
    if (!fs::exists(file, ec)) throw Error(at + "file not found");
    if (fs::is_directory(file, ec)) throw Error(at + "is a folder, not a scene file");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw Error(at + "cannot be opened for reading");
    // A scene is a few kilobytes; a huge file is a mistake (or an attack), refused before it is parsed.
    const auto size = fs::file_size(file, ec);
    if (!ec && size > kMaxSceneBytes)
        throw Error(at + "is " + std::to_string(size) + " bytes, more than the " + std::to_string(kMaxSceneBytes) +
                    " a scene file may have: is it really a scene?");
    json doc;
    try {
        // Nesting deeper than any scene needs is refused while parsing (the parse itself is not recursive,
        // but walking and printing such a document would be).
        const json::parser_callback_t depth_guard = [&at](int depth, json::parse_event_t, json&) {
            if (depth > kMaxJsonDepth)
                throw Error(at + "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels: no scene needs that");
            return true;
        };
        doc = json::parse(in, depth_guard, /*allow_exceptions=*/true, /*ignore_comments=*/true);
    } catch (const json::exception& e) {   // syntax, invalid UTF-8, a number beyond double (1e999)
        std::string what = e.what();
        const auto close = what.find("] ");
        if (what.rfind("[json.exception", 0) == 0 && close != std::string::npos) what = what.substr(close + 2);
        throw Error(at + "not valid JSON: " + what);
    }
    try {
        return parse_scene(doc, file, opt);
    } catch (const json::exception& e) {   // a value of a type the checks did not expect: still one line
        throw Error(at + "unexpected content: " + e.what());
    }
}

Camera scene_camera(const Scene& s, const Bounds& b) {
    const double aspect = double(s.width) / double(s.height);
    const SceneCamera& sc = s.camera;
    Camera cam;
    if (sc.fit) {
        cam = Camera::fit(b, sc.view_from, sc.fov_deg, aspect);
        // Keep the requested up vector unless it is parallel to the view direction (fit's own choice then).
        if (glm::length(glm::cross(glm::normalize(cam.eye - cam.target), glm::normalize(sc.up))) > 1e-6) cam.up = sc.up;
        return cam;
    }
    cam.eye = sc.position;
    cam.target = sc.has_target ? sc.target : b.centre();
    if (!(glm::length(cam.target - cam.eye) > 0.0))
        throw Error("scene '" + s.file + "': camera.position is at the centre of the meshes' bounds: give camera.target");
    if (glm::length(glm::cross(glm::normalize(cam.target - cam.eye), glm::normalize(sc.up))) < 1e-9)
        throw Error("scene '" + s.file + "': camera.up is parallel to the view direction: choose another up vector");
    cam.up = sc.up;
    cam.fov_y_deg = sc.fov_deg;
    // Clip planes from the distance to the far side of the bounds; the near plane at 1e-4 of it keeps
    // 24-bit-class depth precision where the meshes are (the rasteriser interpolates depth in double).
    const double reach = glm::length(cam.eye - b.centre()) + 2.0 * b.radius();
    cam.z_near = std::max(reach * 1e-4, 1e-6);
    cam.z_far = reach * 2.0;
    return cam;
}

SceneGeometry load_scene_geometry(const Scene& s, const std::function<Mesh(const std::string&)>& loader) {
    SceneGeometry g;
    for (std::size_t i = 0; i < s.meshes.size(); ++i) {
        const SceneMesh& sm = s.meshes[i];
        Mesh m;
        try {
            m = loader(sm.path);
        } catch (const Error& e) {
            throw Error("scene '" + s.file + "': meshes[" + std::to_string(i) + "] '" + sm.path_written + "': " + e.what());
        }
        if (sm.transform != glm::dmat4(1.0)) m.transform(sm.transform);
        const Bounds b = m.bounds();
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(b.lo[c]) || !std::isfinite(b.hi[c]))
                throw Error("scene '" + s.file + "': meshes[" + std::to_string(i) + "]: the transform overflows (non-finite coordinates)");
        if (i == 0) g.bounds = b;
        g.bounds.lo = glm::min(g.bounds.lo, b.lo);
        g.bounds.hi = glm::max(g.bounds.hi, b.hi);
        g.triangles += m.triangles.size();
        g.meshes.push_back(std::move(m));
    }
    g.camera = scene_camera(s, g.bounds);
    return g;
}

}  // namespace shadelab
