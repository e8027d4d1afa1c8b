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
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "image/image.hpp"
#include "core/assets.hpp"
#include "mesh/mesh.hpp"
#include "models/catalogue.hpp"
#include "raster/raster.hpp"
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

struct View {
    FragmentBuffer fb;
    Camera cam;
};

View frame(const Mesh& mesh, int cell) {
    View v;
    v.cam = Camera::fit(mesh.bounds(), kViewFrom, 30.0, 1.0);
    RasterOptions ro;
    ro.width = cell;
    ro.height = cell;
    v.fb = rasterize(mesh, v.cam, ro);
    return v;
}

// A material at the model's defaults; models that blend others get two Lambert children of
// contrasting colour, so the blend shows.
Material default_material(const ModelInfo& info) {
    Material m;
    m.model = info.name;
    add_demo_children(m, info);
    return resolve_material(m, "contact sheet, model '" + info.name + "'");
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

    const View sphere = frame(make_icosphere(4), o.cell);
    // Real meshes mostly face +z or -z (spot faces -z): turned 215 degrees about y, a three-quarter view of
    // spot's face from the sheet's camera, lit by the same key light as the sphere.
    const std::string mesh_file = o.mesh.empty() ? bundled_mesh("spot.obj") : o.mesh;
    Mesh real = load_mesh(mesh_file);
    real.transform(glm::rotate(glm::dmat4(1.0), glm::radians(o.mesh_turn_deg), glm::dvec3(0.0, 1.0, 0.0)));
    const View mesh = frame(real, o.cell);

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
    std::vector<std::string> labels;
    for (int i = 0; i < n; ++i) {
        const ModelInfo& info = *models[std::size_t(i)];
        const int x0 = (i % cols) * tile_w, y0 = (i / cols) * tile_h;
        std::string label = info.name;
        try {
            const Material mat = default_material(info);
            for (int k = 0; k < 2; ++k) {
                const View& v = k == 0 ? sphere : mesh;
                ShadeSetup setup;
                setup.material = mat;
                setup.lights = {Light{Light::Type::Directional, kKeyLight, {1.0, 1.0, 1.0}, 1.0, 0.0}};
                setup.ambient = kAmbient;
                setup.view = glm::dvec4(v.cam.eye, 1.0);
                blit(sheet, compose_image(v.fb, shader.shade(v.fb, setup), kGround), x0 + k * o.cell, y0);
            }
        } catch (const Error& e) {
            res.failed.push_back(info.name + ": " + e.what());
            log << "contact sheet: model '" << info.name << "' failed: " << e.what() << "\n";
            label += " (failed)";
        }
        labels.push_back(label);
    }

    // Labels: OpenImageIO's render_text (FreeType) with a system TrueType font, centred under each tile.
    res.font = find_label_font();
    if (!res.font.empty()) {
        OIIO::ImageBuf buf(OIIO::ImageSpec(res.width, res.height, 4, OIIO::TypeDesc::FLOAT), sheet.pixels.data());
        const float white[4] = {0.9f, 0.9f, 0.9f, 1.0f};
        bool ok = true;
        for (int i = 0; i < n && ok; ++i) {
            const int cx = (i % cols) * tile_w + tile_w / 2;
            const int cy = (i / cols) * tile_h + o.cell + label_h / 2;
            // The largest size up to the strip's height at which the name fits the tile's width.
            int size = std::max(8, label_h - 8);
            while (size > 8) {
                const OIIO::ROI box = OIIO::ImageBufAlgo::text_size(labels[std::size_t(i)], size, res.font);
                if (!box.defined() || box.width() <= tile_w - 8) break;
                --size;
            }
            ok = OIIO::ImageBufAlgo::render_text(buf, cx, cy, labels[std::size_t(i)], size, res.font,
                                                 OIIO::cspan<float>(white, 4), OIIO::ImageBufAlgo::TextAlignX::Center,
                                                 OIIO::ImageBufAlgo::TextAlignY::Center);
        }
        res.labelled = ok;
        if (!ok) log << "contact sheet: could not render labels with '" << res.font << "': " << buf.geterror() << "\n";
    }
    if (!res.labelled) {
        // No usable font: the names go to a legend file beside the image, tile by tile.
        res.legend = fs::path(o.output).replace_extension(".txt").string();
        std::ostringstream legend;
        legend << "contact sheet " << o.output << ": " << cols << " tiles per row, each sphere | "
               << fs::path(mesh_file).filename().string() << "; no TrueType font was found for labels\n";
        for (int i = 0; i < n; ++i)
            legend << "row " << i / cols + 1 << ", column " << i % cols + 1 << ": " << labels[std::size_t(i)] << "\n";
        write_text_atomically(res.legend, "legend", legend.str());
        log << "contact sheet: no TrueType font found (install fonts-dejavu-core or set SHADELAB_FONT): names in "
            << res.legend << "\n";
    }
    write_image(o.output, sheet);
    res.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return res;
}

}  // namespace shadelab
