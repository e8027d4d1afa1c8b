// A cache of loaded meshes: the Mesh and MeshLoadReport of a full, validated load_mesh, on disk, so that the next
// load of the same bytes skips OpenMesh's readers, the grammar checks and the repairs and returns the same result.
//
// Key: SHA-256 (FIPS 180-4) of the entry format, the loader version (kLoaderVersion below, and a digest of the
// loader's sources that the build computes), OpenMesh's version, the byte order, the file's lower-case extension
// and the SHA-256 of the file's bytes. Never the modification time: an edited file is another key, whatever its
// time stamp; a file whose stamp changes while it is loaded is not stored.
// One file per key, '<hex key>.slmesh', holding: magic "SLMC", format version, the key, the payload's size and its
// SHA-256, then the payload (the report's counts and notes, the vertex and triangle counts, positions, normals,
// triangles as they are in memory). An entry is used only when all of these check out and the payload is a
// well-formed mesh (every index in range, every number finite, at least one triangle); anything else (stale,
// truncated, corrupt, another key under the file's name, too large for the memory limit) is rejected: the mesh is
// loaded from the file and the entry is written again. Only successful loads are stored: a file load_mesh refuses
// is refused again, by the full loader, every time.
//
// Where: SHADELAB_MESH_CACHE (a folder; "off" or "0" disables the cache), else $XDG_CACHE_HOME/shadelab/meshes,
// else $HOME/.cache/shadelab/meshes; MeshCacheUse::setting overrides the variable. Writes are atomic
// (core/atomic_file.hpp); a cache that cannot be written is skipped, never an error of the load.
#pragma once
#include <string>

#include "mesh/mesh.hpp"

namespace shadelab {

// Bump whenever what load_mesh returns for some file could change in a way the loader's source digest does not
// see (a library's behaviour, a helper outside host/mesh/): every older entry then stops matching.
constexpr int kMeshLoaderVersion = 1;

// The folder `setting` names ("" = the environment, then the XDG default; "off"/"0" = none: returns "").
std::string mesh_cache_dir(const std::string& setting);

// The key of the file at `path` (lower-case extension `ext`), as 64 hex digits; reads the whole file.
// Throws shadelab::Error when the file cannot be read.
std::string mesh_cache_key(const std::string& path, const std::string& ext);

// Entry file of `key` in `dir`.
std::string mesh_cache_entry(const std::string& dir, const std::string& key);

// Reads the entry for `key`: true with the mesh (its `source` left empty) and report when it exists and checks
// out; false when missing (`why` empty) or unusable (the reason in `why`). Never throws for a bad entry.
bool read_mesh_cache_entry(const std::string& dir, const std::string& key, Mesh& mesh, MeshLoadReport& report,
                           std::string& why);

// Writes the entry for `key` atomically; false (and no file left) when it cannot.
bool write_mesh_cache_entry(const std::string& dir, const std::string& key, const Mesh& mesh,
                            const MeshLoadReport& report);

}  // namespace shadelab
