// Structural checks of mesh files, run before OpenMesh reads them.
//
// OpenMesh's readers trust their input: an OBJ face corner without a vertex index ("f /1") fails an
// assertion (abort), a PLY header cut inside a keyword makes its reader loop for ever, a misspelt PLY header
// keyword crashes it, and a truncated body is read in part without a word. These checks walk the file's
// grammar themselves (header, element counts, list lengths, index ranges, the end of the data) with every
// loop bounded by the file's size, so OpenMesh only ever sees files that are complete and well formed.
#pragma once
#include <string>

namespace shadelab {

// The checks before any byte is read: `path` exists, is a file of a supported format (by its extension), is not
// empty and can be opened. Returns the lower-case extension; throws shadelab::Error with one line otherwise.
std::string check_mesh_opens(const std::string& path);

// Throws shadelab::Error with one line (the file, the line or byte where it goes wrong, what to do) when
// `path` is not a complete, well-formed file of its format. `ext` is the lower-case extension with its
// dot: ".obj", ".ply", ".off" or ".stl". Does not judge geometry (NaN, degenerate faces): load_mesh does.
void check_mesh_file(const std::string& path, const std::string& ext);

// The same on bytes already in memory (the fuzz targets use it); `name` is used in messages.
void check_mesh_bytes(const std::string& bytes, const std::string& ext, const std::string& name);

}  // namespace shadelab
