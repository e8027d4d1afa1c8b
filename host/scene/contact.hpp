// The contact sheet: every model of the catalogue at its default parameters, on a sphere and on a real
// mesh, side by side, labelled with the model name; one image for the README.
#pragma once
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "shade/shader.hpp"

namespace shadelab {

struct ContactOptions {
    std::string output = "contact_sheet.png";
    std::string mesh;                        // the real mesh shown next to the sphere (empty: bundled spot.obj) ...
    double mesh_turn_deg = 215.0;            // ... turned this much about +y (spot faces -z: a 3/4 front view)
    int cell = 128;                          // side of each rendered square, pixels
    int columns = 0;                         // model tiles per row; 0: chosen for a roughly 4:3 sheet
    std::vector<std::string> models;         // empty: the whole catalogue, in its order
    Precision precision = Precision::Precise;   // of every tile
    bool per_vertex = false;                 // every tile shaded at the vertices and interpolated (Gouraud)
    // One program for every model that can share one (Shader::prepare_many: about 3x less program-build work
    // on a cold first run, docs/speed.md); false: each model its own program, built at its first tile (the
    // way before, kept for bench_e2e_process's comparison). The images are the same either way.
    bool shared_programs = true;
    std::ostream* log = nullptr;             // nullptr: std::cerr
};

struct ContactResult {
    std::string output;
    std::size_t models = 0;
    int width = 0, height = 0;
    bool labelled = false;                   // labels drawn with a TrueType font (else: written beside it)
    std::string font;                        // the font file used
    std::string legend;                      // when unlabelled: the text file naming each tile
    std::vector<std::string> failed;         // "model: why" for models that could not be shaded
    double ms = 0.0;
};

// Renders and writes the sheet (atomically, like every image). Models that fail to shade get an empty
// tile labelled "(failed)" and are listed in `failed`; the sheet is written anyway.
ContactResult make_contact_sheet(const ContactOptions& options, Runtime& runtime);

// A TrueType font OpenImageIO can render labels with: SHADELAB_FONT if set, else DejaVu Sans from
// Debian's fonts-dejavu-core, else the first .ttf under /usr/share/fonts; empty when there is none.
std::string find_label_font();

}  // namespace shadelab
