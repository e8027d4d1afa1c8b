// Contact sheet: one tile per model (sphere | mesh, label underneath), shaded with one Runtime and one
// Shader; the two fragment buffers are rasterised once and shaded once per model.
#include "scene/contact.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <glm/gtc/matrix_transform.hpp>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "image/image.hpp"
#include "image/image_io.hpp"
#include "core/assets.hpp"
#include "mesh/mesh.hpp"
#include "pipeline/pipeline.hpp"
#include "models/catalogue.hpp"
#include "raster/raster.hpp"
#include "shade/shade_program.hpp"
#include "shade/shader.hpp"

namespace fs = std::filesystem;

namespace shadelab {

namespace {

// The sheet's look: a dark grey ground (so white highlights and dark limbs both read), one key light
// up and to the right of the camera, a faint ambient so unlit sides are not pure black.
const glm::dvec4 kGround{0.045, 0.045, 0.05, 1.0};
const glm::dvec3 kViewFrom{0.0, 0.25, 1.0};
const glm::dvec3 kKeyLight{1.0, 1.0, 1.0};
const glm::dvec3 kAmbient{0.03, 0.03, 0.03};

// One of the two views of a tile (the sphere or the mesh): a one-mesh job of the render path, rasterised once
// and shaded once per model.
struct View {
    pipeline::Job job;
    pipeline::Frame frame;
};

View frame(Mesh mesh, const ContactOptions& o) {
    View v;
    v.job.camera = Camera::fit(mesh.bounds(), kViewFrom, 30.0, 1.0);
    v.job.meshes.push_back(pipeline::JobMesh{std::move(mesh), Material{}, false});
    v.job.width = v.job.height = o.cell;
    v.job.lights = {Light{Light::Type::Directional, kKeyLight, {1.0, 1.0, 1.0}, 1.0, 0.0}};
    v.job.ambient = kAmbient;
    v.job.background = kGround;
    v.job.precision = o.precision;
    v.job.per_vertex = o.per_vertex;
    pipeline::StageTimes times;
    v.frame = pipeline::raster(v.job, times);
    return v;
}

Image shade_view(Shader& shader, View& v, const Material& mat) {
    v.job.meshes.front().material = mat;
    pipeline::StageTimes times;
    return pipeline::compose(v.job, v.frame, pipeline::shade(shader, v.job, v.frame, times), times);
}

// A material at the model's defaults; models that blend others get two Lambert children of
// contrasting colour, so the blend shows.
Material default_material(const ModelInfo& info) {
    Material m;
    m.model = info.name;
    add_demo_children(m, info);
    return resolve_material(m, "contact sheet, model '" + info.name + "'");
}

// Builds one program for the tiles' models that can share one (Shader::prepare_many), with the sheet's lights
// and precision, holding one dispatching kernel for them all: PoCL then compiles one work-group function at the
// first tile instead of one per model (docs/speed.md, the cold contact sheet); its tiles are small, so that the
// kernel is not vectorised costs little. A model whose default material cannot be made is left out (its tile
// reports why); a failed build is logged and each model then builds its own program (a broken model fails its
// own tile only).
void share_programs(Shader& shader, const std::vector<const ModelInfo*>& models, const pipeline::Job& job,
                    std::ostream& log) {
    std::vector<Material> mats;
    for (const ModelInfo* info : models) {
        try {
            mats.push_back(default_material(*info));
        } catch (const Error&) {   // its tile makes it again and reports why
        }
    }
    try {
        shader.prepare_many(mats, job.lights, job.precision, true, is_perspective(pipeline::shade_view(job)));
    } catch (const Error& e) {
        log << "contact sheet: the models' shared program did not build, building one program per model: " << e.what()
            << "\n";
    }
}

void blit(Image& sheet, const Image& cell, int x0, int y0) {
    for (int y = 0; y < cell.height; ++y)
        for (int x = 0; x < cell.width; ++x)
            for (int c = 0; c < 4; ++c) sheet.at(x0 + x, y0 + y, c) = cell.at(x, y, c);
}

}  // namespace

std::string find_label_font() {
    if (const char* env = std::getenv("SHADELAB_FONT"); env && *env) return fs::exists(env) ? env : "";
    const fs::path dejavu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";   // Debian: fonts-dejavu-core
    std::error_code ec;
    if (fs::exists(dejavu, ec)) return dejavu.string();
    std::vector<std::string> found;
    for (auto it = fs::recursive_directory_iterator("/usr/share/fonts", ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec))
        if (it->is_regular_file(ec) && it->path().extension() == ".ttf") found.push_back(it->path().string());
    std::sort(found.begin(), found.end());
    return found.empty() ? "" : found.front();
}

namespace {

// Labels: OpenImageIO's render_text (FreeType, in the image plug-in: image/image_io.hpp) with a system
// TrueType font, centred under each tile.
void draw_labels(Image& sheet, const std::vector<std::string>& labels, int cols, int tile_w, int tile_h, int cell,
                 int label_h, ContactResult& res, std::ostream& log) {
    res.font = find_label_font();
    if (res.font.empty()) return;
    const image_io::Plugin& io = image_io::plugin();
    const float white[4] = {0.9f, 0.9f, 0.9f, 1.0f};
    bool ok = true;
    std::string why;
    for (std::size_t i = 0; i < labels.size() && ok; ++i) {
        const int cx = (int(i) % cols) * tile_w + tile_w / 2;
        const int cy = (int(i) / cols) * tile_h + cell + label_h / 2;
        // The largest size up to the strip's height at which the name fits the tile's width.
        int size = std::max(8, label_h - 8);
        while (size > 8) {
            int width = 0;
            if (!io.text_width(labels[i], size, res.font, width) || width <= tile_w - 8) break;
            --size;
        }
        ok = io.render_text(sheet.pixels.data(), res.width, res.height, cx, cy, labels[i], size, res.font, white, why);
    }
    res.labelled = ok;
    if (!ok) log << "contact sheet: could not render labels with '" << res.font << "': " << why << "\n";
}

// No usable font: the names go to a legend file beside the image, tile by tile.
void write_legend(const ContactOptions& o, const std::string& mesh_file, const std::vector<std::string>& labels,
                  int cols, ContactResult& res, std::ostream& log) {
    res.legend = fs::path(o.output).replace_extension(".txt").string();
    std::ostringstream legend;
    legend << "contact sheet " << o.output << ": " << cols << " tiles per row, each sphere | "
           << fs::path(mesh_file).filename().string() << "; no TrueType font was found for labels\n";
    for (std::size_t i = 0; i < labels.size(); ++i)
        legend << "row " << int(i) / cols + 1 << ", column " << int(i) % cols + 1 << ": " << labels[i] << "\n";
    write_text_atomically(res.legend, "legend", legend.str());
    log << "contact sheet: no TrueType font found (install fonts-dejavu-core or set SHADELAB_FONT): names in "
        << res.legend << "\n";
}

}  // namespace

ContactResult make_contact_sheet(const ContactOptions& o, Runtime& rt) {
    std::ostream& log = o.log ? *o.log : shadelab::log_out();
    const auto t0 = std::chrono::steady_clock::now();
    if (o.cell < 16 || o.cell > 2048) throw Error("contact sheet: --cell " + std::to_string(o.cell) + " must be in [16, 2048]");
    encoding_for(o.output);   // a bad extension fails before any work

    std::vector<const ModelInfo*> models;
    if (o.models.empty()) {
        for (const auto& m : model_catalogue()) models.push_back(&m);
    } else {
        for (const auto& name : o.models) models.push_back(&find_model(name));
    }
    if (models.empty()) throw Error("contact sheet: the catalogue is empty");

    View sphere = frame(make_icosphere(4), o);
    // Real meshes mostly face +z or -z (spot faces -z): turned 215 degrees about y, a three-quarter view of
    // spot's face from the sheet's camera, lit by the same key light as the sphere.
    const std::string mesh_file = o.mesh.empty() ? bundled_mesh("spot.obj") : o.mesh;
    Mesh real = load_mesh(mesh_file);
    real.transform(glm::rotate(glm::dmat4(1.0), glm::radians(o.mesh_turn_deg), glm::dvec3(0.0, 1.0, 0.0)));
    View mesh = frame(std::move(real), o);

    const int n = int(models.size());
    const int label_h = std::max(14, o.cell / 7 + 8);
    const int tile_w = 2 * o.cell, tile_h = o.cell + label_h;
    int cols = o.columns;
    if (cols <= 0) cols = std::max(1, int(std::lround(std::sqrt(n * (4.0 / 3.0) * tile_h / tile_w))));
    cols = std::min(cols, n);
    const int rows = (n + cols - 1) / cols;

    ContactResult res;
    res.output = o.output;
    res.models = models.size();
    res.width = cols * tile_w;
    res.height = rows * tile_h;
    Image sheet(res.width, res.height, 4);
    for (std::size_t p = 0; p < std::size_t(res.width) * std::size_t(res.height); ++p)
        for (int c = 0; c < 4; ++c) sheet.pixels[p * 4 + std::size_t(c)] = float(kGround[c]);

    Shader shader(rt);
    if (o.shared_programs) share_programs(shader, models, sphere.job, log);
    std::vector<std::string> labels;
    for (int i = 0; i < n; ++i) {
        const ModelInfo& info = *models[std::size_t(i)];
        const int x0 = (i % cols) * tile_w, y0 = (i / cols) * tile_h;
        std::string label = info.name;
        try {
            const Material mat = default_material(info);
            for (int k = 0; k < 2; ++k) blit(sheet, shade_view(shader, k == 0 ? sphere : mesh, mat), x0 + k * o.cell, y0);
        } catch (const Error& e) {
            res.failed.push_back(info.name + ": " + e.what());
            log << "contact sheet: model '" << info.name << "' failed: " << e.what() << "\n";
            label += " (failed)";
        }
        labels.push_back(label);
    }

    draw_labels(sheet, labels, cols, tile_w, tile_h, o.cell, label_h, res, log);
    if (!res.labelled) write_legend(o, mesh_file, labels, cols, res, log);
    write_image(o.output, sheet);
    res.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return res;
}

}  // namespace shadelab
