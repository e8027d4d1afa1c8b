// Host rasteriser: mesh + camera -> fragment buffer. See raster.hpp for the rules.
//
// Stages, each a small function below:
//   to_clip             world -> clip space (double), once per vertex;
//   outcode             per vertex, which frustum planes it is beyond (and near plane, guard band): trivial
//                       rejection is all three vertices beyond one plane;
//   clip_polygon        Sutherland-Hodgman against the near plane (and, rarely, a far-off guard band);
//   viewport_transform  clip -> NDC -> screen pixels (y flipped: row 0 is the top of the image);
//   setup_triangle      snap to 1/256 pixel, orient, cull, top-left flags, depth plane, bounding box; a box of
//                       at most 2 x 2 pixels has its centres tested (centres_covered): none, and the triangle is
//                       dropped; setup_lanes does the same for eight triangles at a time on AVX-512 hosts and
//                       four on AVX2 hosts (tests/raster_isa checks each build against this CPU's);
//   bin_chunk           each triangle listed in the 128 x 64 pixel tiles its bounding box touches;
//   raster_tile         per tile: edge functions at pixel centres + depth test (depth_span, a loop without
//                       branches that vectorises) into the visibility buffer (triangle id per pixel), with
//                       the tile's depth and owner buffers in cache; draw_small takes a 2 x 2 box's centres
//                       from set-up instead of edge functions;
//   emit_rows/emit_run  perspective-correct interpolation once per covered pixel, for the triangle that won
//                       it (deferred resolve: resolve_into sets a triangle's sums up in lanes, once per band
//                       of rows, in a small cache), in pixel order, one run of a triangle's pixels at a time in
//                       blocks of kLanes pixels, each block one AVX computation stored straight into the
//                       fragment arrays (emit_block_avx; without AVX a vectorised loop, emit_lanes); emit_pixel,
//                       the one-pixel path, takes the rare fallbacks.
// Threads: vertices and triangles are cut into blocks and chunks of a fixed size for set-up and binning,
// tiles and bands of rows for rasterisation and emission, and threads take the next one from a shared counter.
// Every per-pixel result is computed the same way whatever the split and whichever thread takes which piece,
// so the output is bit-identical for any thread count.
#include "raster/raster.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstddef>
#include <cstring>
#include <iterator>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#ifdef __AVX__
#include <immintrin.h>
#endif

#include <glm/gtc/type_ptr.hpp>

#include "core/error.hpp"
#include "raster/big_buffer.hpp"
#include "raster/parallel.hpp"

namespace shadelab {

namespace {

constexpr int kMaxImageSide = 16384;
constexpr int kSubBits = 8;                                   // sub-pixel precision, as GPUs snap
constexpr std::int64_t kSub = std::int64_t(1) << kSubBits;    // sub-pixel steps per pixel
using clock_type = std::chrono::steady_clock;
double ms_between(clock_type::time_point a, clock_type::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}
constexpr int kMaxPolygon = 9;                                // triangle clipped by 5 planes: <= 8 vertices

// ------------------------------------------------------------------------------------------------------
// Input validation

std::string str(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string str(const glm::dvec3& v) { return "(" + str(v.x) + ", " + str(v.y) + ", " + str(v.z) + ")"; }

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Not NaN or inf, as a comparison (|v| <= max) that vectorises.
inline bool finite_d(double v) { return std::fabs(v) <= std::numeric_limits<double>::max(); }

[[noreturn]] void fail(const std::string& what) { throw Error("rasteriser: " + what); }

// The options and the camera (validate_mesh checks the mesh).
void validate(const Camera& cam, const RasterOptions& o) {
    if (o.width < 1 || o.width > kMaxImageSide || o.height < 1 || o.height > kMaxImageSide)
        fail("image size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
             " is out of range: width and height must each be in [1, 16384]");
    if (o.threads < 0)
        fail("threads " + std::to_string(o.threads) + " is out of range: must be >= 0 (0 = all hardware threads)");
    if (!finite(cam.eye)) fail("camera eye " + str(cam.eye) + " must be finite");
    if (!finite(cam.target)) fail("camera target " + str(cam.target) + " must be finite");
    if (!finite(cam.up)) fail("camera up " + str(cam.up) + " must be finite");
    if (!(cam.fov_y_deg > 0.0 && cam.fov_y_deg < 180.0))
        fail("camera field of view " + str(cam.fov_y_deg) + " deg is out of range: must be in (0, 180)");
    if (!(cam.z_near > 0.0) || !std::isfinite(cam.z_near))
        fail("camera z_near " + str(cam.z_near) + " is out of range: must be finite and > 0");
    if (!(cam.z_far > cam.z_near) || !std::isfinite(cam.z_far))
        fail("camera z_far " + str(cam.z_far) + " is out of range: must be finite and > z_near (" + str(cam.z_near) + ")");
    if (cam.eye == cam.target) fail("camera eye and target are the same point " + str(cam.eye) + ": move one of them");
    if (glm::length(glm::cross(cam.target - cam.eye, cam.up)) == 0.0)
        fail("camera up " + str(cam.up) + " is zero or parallel to the view direction: choose another up vector");
}

// The mesh checks run every frame, over every vertex and triangle: blocks of kCheckBlock elements, each tested as
// one reduction without branches (it vectorises; a loop that stopped at the first bad element did not, and took
// ~1 ms of the dragon's frame on one thread), shared among the frame's threads. Only a block that fails is
// scanned again for its first bad element, and the lowest one over all blocks is reported, as one scan from the
// start would report it.
constexpr std::size_t kCheckBlock = 4096;

// The lowest i in [0, n) with bad(i), or n; block_bad(lo, hi) is true when some i in [lo, hi) is bad.
template <class BlockBad, class Bad>
std::size_t first_bad(std::size_t n, int threads, const BlockBad& block_bad, const Bad& bad) {
    std::atomic<std::size_t> first{n};
    run_pieces(threads, (n + kCheckBlock - 1) / kCheckBlock, [&](std::size_t b) {
        const std::size_t lo = b * kCheckBlock, hi = std::min(n, lo + kCheckBlock);
        if (!block_bad(lo, hi)) return;
        std::size_t i = lo;
        while (!bad(i)) ++i;
        for (std::size_t seen = first.load(); i < seen && !first.compare_exchange_weak(seen, i);) {
        }
    });
    return first.load();
}

void validate_mesh(const Mesh& mesh, int threads) {
    const std::string name = mesh.source.empty() ? std::string("mesh") : "mesh '" + mesh.source + "'";
    if (mesh.normals.size() != mesh.positions.size())
        fail(name + " has " + std::to_string(mesh.normals.size()) + " normals for " +
             std::to_string(mesh.positions.size()) + " vertices: need one normal per vertex");
    const glm::dvec3 *const P = mesh.positions.data(), *const N = mesh.normals.data();
    const std::size_t nv = mesh.positions.size();
    const std::size_t v = first_bad(
        nv, threads,
        [&](std::size_t lo, std::size_t hi) {
            // as flat arrays of doubles (glm::value_ptr's view): GCC 12 finds no vector type for a glm vector's
            // members, which are in an anonymous union
            static_assert(sizeof(glm::dvec3) == 3 * sizeof(double), "a dvec3 is three doubles");
            const double *const p = glm::value_ptr(P[0]), *const q = glm::value_ptr(N[0]);
            int bad = 0;   // (an int: GCC 12 does not vectorise a reduction into a bool)
            for (std::size_t j = 3 * lo; j < 3 * hi; ++j) bad |= int(!finite_d(p[j])) | int(!finite_d(q[j]));
            return bad != 0;
        },
        [&](std::size_t i) { return !finite(P[i]) || !finite(N[i]); });
    if (v < nv) fail(name + ": vertex " + std::to_string(v) + " has a non-finite position or normal");
    const glm::u32vec3* const T = mesh.triangles.data();
    const std::size_t nt = mesh.triangles.size();
    const std::size_t t = first_bad(
        nt, threads,
        [&](std::size_t lo, std::size_t hi) {
            std::uint32_t top = 0;
            for (std::size_t i = lo; i < hi; ++i) top = std::max(top, std::max(T[i][0], std::max(T[i][1], T[i][2])));
            return std::size_t(top) >= nv;
        },
        [&](std::size_t i) { return T[i][0] >= nv || T[i][1] >= nv || T[i][2] >= nv; });
    if (t < nt)
        for (int k = 0; k < 3; ++k)
            if (T[t][k] >= nv)
                fail(name + ": triangle " + std::to_string(t) + " refers to vertex " + std::to_string(T[t][k]) +
                     ", but there are only " + std::to_string(nv) + " vertices");
}

// ------------------------------------------------------------------------------------------------------
// Geometry stages

// A vertex in clip space carrying the attributes to interpolate. Clip coordinates are an affine function
// of the world position, so a point a fraction t along an edge in world space is the same fraction t along
// it in clip space: the clipper may interpolate every attribute linearly in t.
struct ClipVertex {
    glm::dvec4 clip;
    glm::dvec3 world;
    glm::dvec3 normal;
    glm::dvec3 bary;   // barycentric position in the original mesh triangle (survives clipping)
};

glm::dvec4 to_clip(const glm::dmat4& view_projection, const glm::dvec3& world) {
    return view_projection * glm::dvec4(world, 1.0);
}

// Clip-space half-spaces written as planes p with inside <=> dot(p, clip) >= 0.
// Near (OpenGL): z_ndc >= -1 <=> z_clip >= -w_clip <=> z + w >= 0; with w = -z_view this is
// z_view <= -z_near exactly, so clipped vertices have w >= z_near > 0 and the divide is safe.
const glm::dvec4 kNearPlane{0.0, 0.0, 1.0, 1.0};

bool near_inside(const glm::dvec4& c) { return glm::dot(kNearPlane, c) >= 0.0; }

bool in_guard_band(const glm::dvec4& c, double guard) {
    return std::abs(c.x) <= guard * c.w && std::abs(c.y) <= guard * c.w;
}

// A vertex's clip tests, one bit each, computed once per vertex (its SetupVertex's `code`): a triangle's tests
// are then bit operations on the three records it reads anyway, where loading its three clip-space vertices
// (scattered over memory when the mesh's order is not spatial: the bunny's, the dragon's) made set-up wait on
// memory. The low six bits are the frustum planes, so that the triangle is trivially outside when one bit is
// set in all three (all three vertices beyond the same plane); kBehindNear and kOffGuard ask for clipping.
enum Outcode : std::uint8_t {
    kBeyondRight = 1, kBeyondLeft = 2, kBeyondTop = 4, kBeyondBottom = 8, kBeyondFar = 16, kBeyondNearZ = 32,
    kFrustumBits = 63, kBehindNear = 64, kOffGuard = 128
};
// What set-up reads of a mesh vertex, computed once per vertex in one 32-byte record (one cache line's half:
// the triangles' vertex loads were set-up's cost): screen position, NDC depth z / w and the outcode.
struct SetupVertex {
    glm::dvec2 screen;
    double ndc_z;
    std::uint32_t code;   // an Outcode's bits (32 bits wide, so that setup_lanes can gather it)
};

std::uint8_t outcode(const glm::dvec4& c, double guard) {
    return std::uint8_t((c.x > c.w ? kBeyondRight : 0) | (c.x < -c.w ? kBeyondLeft : 0) | (c.y > c.w ? kBeyondTop : 0) |
                        (c.y < -c.w ? kBeyondBottom : 0) | (c.z > c.w ? kBeyondFar : 0) |
                        (c.z < -c.w ? kBeyondNearZ : 0) | (near_inside(c) ? 0 : kBehindNear) |
                        (in_guard_band(c, guard) ? 0 : kOffGuard));
}

// Where edge p-q crosses the plane. The endpoints are put in a canonical order first, so the two triangles
// sharing an edge compute a bit-identical crossing point (no crack where the plane cuts the shared edge).
ClipVertex intersect(const ClipVertex& p, const ClipVertex& q, const glm::dvec4& plane) {
    const bool swap = std::tie(p.clip.x, p.clip.y, p.clip.z, p.clip.w) > std::tie(q.clip.x, q.clip.y, q.clip.z, q.clip.w);
    const ClipVertex& a = swap ? q : p;
    const ClipVertex& b = swap ? p : q;
    const double da = glm::dot(plane, a.clip), db = glm::dot(plane, b.clip);
    const double t = da / (da - db);   // da and db have opposite signs, so |t| <= 1 and no division by 0
    ClipVertex r;
    r.clip = a.clip + t * (b.clip - a.clip);
    r.world = a.world + t * (b.world - a.world);
    r.normal = a.normal + t * (b.normal - a.normal);
    r.bary = a.bary + t * (b.bary - a.bary);
    return r;
}

// Sutherland-Hodgman: one pass of the convex polygon in[0..n) against one plane. A convex polygon stays
// convex and gains at most one vertex per plane. Returns the new vertex count.
int clip_polygon(const ClipVertex* in, int n, const glm::dvec4& plane, ClipVertex* out) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const ClipVertex& cur = in[i];
        const ClipVertex& nxt = in[(i + 1) % n];
        const bool cur_in = glm::dot(plane, cur.clip) >= 0.0, nxt_in = glm::dot(plane, nxt.clip) >= 0.0;
        if (cur_in) out[m++] = cur;
        if (cur_in != nxt_in) out[m++] = intersect(cur, nxt, plane);
    }
    return m;
}

// NDC depth of a clip-space point (z / w: the depth buffer's value).
double ndc_depth(const glm::dvec4& c) { return c.z / c.w; }

// Screen position of a clip-space point: perspective divide to NDC ([-1, 1], y up), then to pixels with
// x in [0, W) to the right and y in [0, H) downwards (row 0 is the top row, so NDC y is flipped).
glm::dvec2 viewport_transform(const glm::dvec4& c, int width, int height) {
    const double inv_w = 1.0 / c.w;
    const double x_ndc = c.x * inv_w, y_ndc = c.y * inv_w;
    return {(x_ndc * 0.5 + 0.5) * width, (0.5 - y_ndc * 0.5) * height};
}

// Twice the signed area of (a, b, p), y down: > 0 when p lies to the right of a->b as seen on screen,
// i.e. when a, b, p run clockwise on the screen. Exact in 64-bit integers for snapped coordinates.
std::int64_t edge_function(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by, std::int64_t px,
                           std::int64_t py) {
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

// Top-left fill rule (Direct3D / OpenGL): a pixel centre exactly on an edge belongs to the triangle only if
// the edge is a top edge (horizontal, triangle below it) or a left edge. With the triangle oriented
// clockwise on screen (edge_function > 0 inside, interior on the right of each directed edge), a top edge
// runs in +x (dy == 0, dx > 0) and a left edge runs upwards (dy < 0). The neighbour sharing the edge
// traverses it in the opposite direction (it lies on the other side), so exactly one of the two takes a
// pixel on it: the rule is a strict choice between (dx, dy) and (-dx, -dy).
bool is_top_left(std::int64_t dx, std::int64_t dy) { return dy < 0 || (dy == 0 && dx > 0); }

// floor(a / kSub): kSub is 2^kSubBits, and an arithmetic right shift of a two's-complement integer rounds
// towards minus infinity (guaranteed from C++20, and what GCC and Clang do for every earlier standard).
static_assert((std::int64_t(-1) >> 1) == -1, "floor_sub needs an arithmetic right shift");
std::int64_t floor_sub(std::int64_t a) { return a >> kSubBits; }

// Round to the nearest sub-pixel (halves up). Inline floor: the result is the same on every thread.
std::int32_t snap(double pixels) {
    const double v = pixels * double(kSub) + 0.5;
    std::int64_t i = std::int64_t(v);
    if (double(i) > v) --i;
    return std::int32_t(i);
}

// The per-pixel loop's view of a triangle (kept small: every band thread walks all of them).
struct RasterTri {
    std::int32_t x[3], y[3];     // snapped screen positions in 1/256 pixel, clockwise on screen
    double z0, dzdx, dzdy;       // NDC depth plane: z = z0 + dzdx (px - x0) + dzdy (py - y0), in pixels
    std::int16_t min_x, max_x, min_y, max_y;   // pixels whose centre may be covered, clamped to the image
    std::uint8_t top_left;       // bit i set: the edge opposite vertex i takes pixel centres lying on it
    std::uint8_t small_cover;    // 0, or for a box of at most 2 x 2 pixels kSmall | the centres it covers (centres_covered)
};

// What emission needs to find a winning triangle's corners again.
struct ShadeTri {
    std::int32_t mesh_triangle;
    std::int32_t clip_vertices;  // -1: the corners are the mesh triangle's vertices `vertex` (in screen order:
                                 // the mesh order 0, 1, 2, or 0, 2, 1 if `swapped`); else index of the three
                                 // corners, already in screen order, in the chunk's `clipped` array
    std::uint32_t vertex[3];
    bool swapped;
};

// A mesh vertex as emission reads it, in one place: screen position, 1 / w, world position and normal.
struct ScreenVertex {
    glm::dvec2 screen;   // viewport_transform of its clip position
    double inv_w;
    glm::dvec3 world, normal;
};

// Set-up output of one contiguous range of mesh triangles (one per thread), in mesh order.
struct Chunk {
    std::vector<RasterTri> raster;
    std::vector<ShadeTri> shade;
    std::vector<ClipVertex> clipped;
    RasterStats stats;
};

struct Frame {
    glm::dmat4 view_projection;
    int width = 0, height = 0;
    double guard = 0.0;          // guard band half-width in NDC
    bool cull = false;
};

enum class Setup { Kept, Culled, Empty };

// A triangle whose box is at most 2 x 2 pixels has its pixel centres tested in set-up: it is dropped there if it
// covers none (at 512 x 512 most of the dragon's triangles are smaller than a pixel, and 38% of those set up, 13%
// of the bunny's, covered no centre, yet each was stored, binned and drawn), and otherwise keeps the centres it
// covers (RasterTri::small_cover), which draw_small draws without edge functions.
constexpr std::uint8_t kSmall = 16;   // RasterTri::small_cover: the box is at most 2 x 2 pixels

// The centres of the set-up triangle `t` (clockwise, its box and top_left flags set; a box of at most 2 x 2
// pixels) that it covers: bit i + 2 j for pixel (min_x + i, min_y + j). draw_triangle's test of each pixel,
// E_i >= bias_i for the three edges (the same exact integers), so a triangle dropped for covering none would have
// drawn nothing, and draw_small covers what draw_triangle would. The four centres of the 2 x 2 block at the box's
// corner are tested without a branch, and those outside the box masked off.
unsigned centres_covered(const RasterTri& t) {
    const std::int64_t cx = std::int64_t(t.min_x) * kSub + kSub / 2, cy = std::int64_t(t.min_y) * kSub + kSub / 2;
    const bool wide = t.max_x > t.min_x, tall = t.max_y > t.min_y;
    bool c00 = true, c10 = wide, c01 = tall, c11 = wide & tall;   // pixel (min_x + i, min_y + j) is cij
    for (int i = 0; i < 3; ++i) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        const std::int64_t dx = std::int64_t(t.x[b]) - t.x[a], dy = std::int64_t(t.y[b]) - t.y[a];
        const std::int64_t e = dx * (cy - t.y[a]) - dy * (cx - t.x[a]) - ((t.top_left >> i) & 1u ? 0 : 1);
        const std::int64_t right = -dy * kSub, down = dx * kSub;   // the steps of one pixel in x and in y
        c00 = c00 & (e >= 0);
        c10 = c10 & (e + right >= 0);
        c01 = c01 & (e + down >= 0);
        c11 = c11 & (e + right + down >= 0);
    }
    return unsigned(c00) | unsigned(c10) << 1 | unsigned(c01) << 2 | unsigned(c11) << 3;
}

// One screen triangle from three corners (all with w > 0, inside the guard band): their screen positions and
// NDC depths z / w (read only for the depth plane of a triangle that covers a pixel centre).
// `corners`, when the triangle came out of the clipper, are kept for emission; otherwise the corners are
// the mesh triangle's own vertices.
// `mesh_vertices` are the mesh triangle's vertex indices when the corners are its own vertices (else null).
Setup setup_triangle(const double ndc_z[3], const glm::dvec2 screen[3], const ClipVertex* corners,
                     const std::uint32_t* mesh_vertices, const Frame& f, std::int32_t mesh_triangle, Chunk& out) {
    RasterTri r;
    for (int k = 0; k < 3; ++k) {
        const glm::dvec2& p = screen[k];   // viewport_transform(c[k])
        // The guard band keeps |p| below ~2^19.1 pixels, so snapped values fit 28 bits and every edge
        // function product fits comfortably in 64 bits.
        r.x[k] = snap(p.x);
        r.y[k] = snap(p.y);
    }
    std::int64_t area = edge_function(r.x[0], r.y[0], r.x[1], r.y[1], r.x[2], r.y[2]);
    if (area == 0) return Setup::Empty;   // edge-on after snapping: covers no pixel centre
    // Front faces run counter-clockwise on the displayed image (OpenGL); in these y-down coordinates that
    // is edge_function < 0.
    const bool front = area < 0;
    if (f.cull && !front) return Setup::Culled;
    if (front) {   // make every triangle clockwise on screen, so "inside" is edge_function >= 0
        std::swap(r.x[1], r.x[2]);
        std::swap(r.y[1], r.y[2]);
        area = -area;
    }

    // Bounding box: pixel x's centre is x * kSub + kSub / 2 in sub-pixels; keep the x with a centre in
    // [min, max] of the snapped vertices, clamped to the image.
    const std::int64_t lo_x = std::min({r.x[0], r.x[1], r.x[2]}), hi_x = std::max({r.x[0], r.x[1], r.x[2]});
    const std::int64_t lo_y = std::min({r.y[0], r.y[1], r.y[2]}), hi_y = std::max({r.y[0], r.y[1], r.y[2]});
    const std::int64_t first_x = -floor_sub(-(lo_x - kSub / 2)), last_x = floor_sub(hi_x - kSub / 2);
    const std::int64_t first_y = -floor_sub(-(lo_y - kSub / 2)), last_y = floor_sub(hi_y - kSub / 2);
    const std::int64_t min_x = std::max<std::int64_t>(first_x, 0), max_x = std::min<std::int64_t>(last_x, f.width - 1);
    const std::int64_t min_y = std::max<std::int64_t>(first_y, 0), max_y = std::min<std::int64_t>(last_y, f.height - 1);
    if (min_x > max_x || min_y > max_y) return Setup::Empty;
    // NDC depth of the corners, in screen order.
    const int i1 = front ? 2 : 1, i2 = front ? 1 : 2;
    const double z[3] = {ndc_z[0], ndc_z[i1], ndc_z[i2]};
    r.min_x = std::int16_t(min_x);   // image sides are <= 16384
    r.max_x = std::int16_t(max_x);
    r.min_y = std::int16_t(min_y);
    r.max_y = std::int16_t(max_y);

    r.top_left = 0;
    for (int i = 0; i < 3; ++i) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        if (is_top_left(std::int64_t(r.x[b]) - r.x[a], std::int64_t(r.y[b]) - r.y[a]))
            r.top_left = std::uint8_t(r.top_left | (1u << i));
    }
    r.small_cover = 0;
    if (max_x - min_x <= 1 && max_y - min_y <= 1) {
        const unsigned covered = centres_covered(r);
        if (covered == 0) return Setup::Empty;
        r.small_cover = std::uint8_t(kSmall | covered);
    }

    // NDC depth is an affine function of screen position (that is what makes a depth buffer work). Its
    // plane through the three snapped vertices, by Cramer's rule on z - z0 = a (x - x0) + b (y - y0):
    const double x0 = double(r.x[0]) / double(kSub), y0 = double(r.y[0]) / double(kSub);
    const double x1 = double(r.x[1]) / double(kSub) - x0, y1 = double(r.y[1]) / double(kSub) - y0;
    const double x2 = double(r.x[2]) / double(kSub) - x0, y2 = double(r.y[2]) / double(kSub) - y0;
    const double det = x1 * y2 - x2 * y1;   // = area / kSub^2 > 0
    r.z0 = z[0];
    r.dzdx = ((z[1] - z[0]) * y2 - (z[2] - z[0]) * y1) / det;
    r.dzdy = ((z[2] - z[0]) * x1 - (z[1] - z[0]) * x2) / det;

    ShadeTri s;
    s.mesh_triangle = mesh_triangle;
    s.clip_vertices = -1;
    s.swapped = front;
    for (int k = 0; k < 3; ++k) s.vertex[k] = mesh_vertices ? mesh_vertices[front && k > 0 ? 3 - k : k] : 0u;
    if (corners) {
        s.clip_vertices = std::int32_t(out.clipped.size());
        s.swapped = false;
        out.clipped.push_back(corners[0]);
        out.clipped.push_back(corners[front ? 2 : 1]);
        out.clipped.push_back(corners[front ? 1 : 2]);
    }
    out.raster.push_back(r);
    out.shade.push_back(s);
    return Setup::Kept;
}

// Clip one mesh triangle and set up the screen triangles it becomes (none, one, or a fan of several).
// `vertices` are the frame's per-vertex set-up records; a triangle that needs clipping forms its three clip
// positions again (the vertex pass keeps none: an array of 32 bytes a vertex written for the few such triangles).
void setup_mesh_triangle(const Mesh& mesh, const SetupVertex* vertices, std::size_t mt,
                         const Frame& f, Chunk& out) {
    const glm::u32vec3& tri = mesh.triangles[mt];
    const SetupVertex &v0 = vertices[tri[0]], &v1 = vertices[tri[1]], &v2 = vertices[tri[2]];
    const std::uint32_t o0 = v0.code, o1 = v1.code, o2 = v2.code;
    if (o0 & o1 & o2 & kFrustumBits) {   // all three beyond one plane
        ++out.stats.triangles_culled;
        return;
    }
    const std::uint32_t any = o0 | o1 | o2;   // bits set in at least one vertex
    const bool crosses_near = (any & kBehindNear) != 0;
    if ((any & (kBehindNear | kOffGuard)) == 0) {
        // The common case: nothing to clip.
        const glm::dvec2 sc[3] = {v0.screen, v1.screen, v2.screen};
        const double z[3] = {v0.ndc_z, v1.ndc_z, v2.ndc_z};
        const std::uint32_t vi[3] = {tri[0], tri[1], tri[2]};
        if (setup_triangle(z, sc, nullptr, vi, f, std::int32_t(mt), out) == Setup::Culled) ++out.stats.triangles_culled;
        return;
    }
    // the clip positions again, by the vertex pass's own function: bit for bit the values its records came from
    const glm::dvec4 c[3] = {to_clip(f.view_projection, mesh.positions[tri[0]]),
                             to_clip(f.view_projection, mesh.positions[tri[1]]),
                             to_clip(f.view_projection, mesh.positions[tri[2]])};

    ClipVertex poly[kMaxPolygon], tmp[kMaxPolygon];
    for (int k = 0; k < 3; ++k) {
        glm::dvec3 unit(0.0);
        unit[k] = 1.0;
        poly[k] = {c[k], mesh.positions[tri[k]], mesh.normals[tri[k]], unit};
    }
    int n = 3;
    if (crosses_near) {
        n = clip_polygon(poly, n, kNearPlane, tmp);
        std::copy(tmp, tmp + n, poly);
        ++out.stats.triangles_clipped;
    }
    // Guard band: vertices very far off screen (e.g. just in front of the near plane, far to the side) are
    // clipped to |x|, |y| <= G w, G >> 1, so snapped coordinates stay in range. The cut lies far outside
    // the image, so it changes no pixel; the triangle's shape on screen is exactly preserved.
    bool far_off = false;
    for (int k = 0; k < n; ++k) far_off = far_off || !in_guard_band(poly[k].clip, f.guard);
    if (far_off) {
        const glm::dvec4 planes[4] = {{-1, 0, 0, f.guard}, {1, 0, 0, f.guard}, {0, -1, 0, f.guard}, {0, 1, 0, f.guard}};
        for (const glm::dvec4& p : planes) {
            n = clip_polygon(poly, n, p, tmp);
            std::copy(tmp, tmp + n, poly);
            if (n < 3) return;
        }
    }
    // Fan-triangulate the convex polygon (its inner edges are shared with bit-identical end points, so the
    // fill rule covers them exactly once, as any other shared edge).
    int culled = 0, kept = 0;
    for (int k = 1; k + 1 < n; ++k) {
        const ClipVertex fan[3] = {poly[0], poly[k], poly[k + 1]};
        const glm::dvec2 sc[3] = {viewport_transform(fan[0].clip, f.width, f.height),
                                  viewport_transform(fan[1].clip, f.width, f.height),
                                  viewport_transform(fan[2].clip, f.width, f.height)};
        const double z[3] = {ndc_depth(fan[0].clip), ndc_depth(fan[1].clip), ndc_depth(fan[2].clip)};
        const Setup r = setup_triangle(z, sc, fan, nullptr, f, std::int32_t(mt), out);
        culled += r == Setup::Culled ? 1 : 0;
        kept += r == Setup::Kept ? 1 : 0;
    }
    if (culled > 0 && kept == 0) ++out.stats.triangles_culled;
}

// Set-up reads each triangle's three vertices, which are scattered over the vertex arrays when the mesh's
// triangle order is not spatial (the bunny's and the dragon's are not): it asks for those of the triangle
// kSetupAhead on, so that their loads overlap the set-up of the ones between. Only a hint.
constexpr std::size_t kSetupAhead = 8;
void prefetch_vertices(const glm::u32vec3& tri, const SetupVertex* vertices) {
    for (int k = 0; k < 3; ++k) __builtin_prefetch(&vertices[tri[k]]);
}

// Set-up of kSetupLanes mesh triangles at once (setup_lanes) on AVX-512 and AVX2 hosts, for those that need no
// clipping (the common case): one vector per value (gathers of the three vertices' records, 64-bit integer edge
// functions, double depth planes). One triangle at a time, set-up took about 200 cycles a triangle on the dragon
// (202k triangles), spent on instructions rather than memory: most of a 512 x 512 frame's set-up. Every value is
// setup_triangle's: the same exact integers, the same double operations in the same order (no fused
// multiply-adds: -ffp-contract=off), the same tests in the same order (a lane's fate). A triangle outside the
// frustum is counted as culled, and one that needs clipping left to setup_mesh_triangle. Written in intrinsics:
// GCC 12 does not vectorise a loop over the lanes ("control flow in loop": int64 -> double conversions count as
// trapping; without that, no vector type for the records' loads), and such a loop measured no faster than
// setup_triangle on `-march=haswell` code. Builds with neither set up one triangle at a time.
#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__AVX512VL__)
#define SHADELAB_SETUP_LANES 512
constexpr int kSetupLanes = 8;
#elif defined(__AVX2__)
#define SHADELAB_SETUP_LANES 256
constexpr int kSetupLanes = 4;
#else
#define SHADELAB_SETUP_LANES 0
#endif

#if SHADELAB_SETUP_LANES
enum Fate : std::int32_t { kKept = 0, kCulledLane = 1, kEmptyLane = 2, kOneByOne = 3 };

// kSetupLanes triangles' set-up, one array per field (lane l is triangle l of the group).
struct SetupLanes {
    std::int32_t x[3][kSetupLanes], y[3][kSetupLanes];   // snapped, clockwise on screen
    double z0[kSetupLanes], dzdx[kSetupLanes], dzdy[kSetupLanes];
    std::int32_t min_x[kSetupLanes], max_x[kSetupLanes], min_y[kSetupLanes], max_y[kSetupLanes];
    std::int32_t top_left[kSetupLanes], small_cover[kSetupLanes], front[kSetupLanes], fate[kSetupLanes];
};

// The gathers' indices: index[k][l] is the first 8-byte word of corner k's record of triangle tris[l].
static_assert(sizeof(SetupVertex) == 32 && offsetof(SetupVertex, ndc_z) == 16 && offsetof(SetupVertex, code) == 24,
              "setup_lanes gathers a SetupVertex as four 8-byte words");
void record_words(const glm::u32vec3* tris, std::int64_t (&index)[3][kSetupLanes]) {
    for (int l = 0; l < kSetupLanes; ++l)
        for (int k = 0; k < 3; ++k) index[k][l] = std::int64_t(tris[l][k]) * 4;
}

// The lanes' snapped corners and boxes (min_x, max_x, min_y, max_y) into `s`, by `store(to, value)` (which writes
// kSetupLanes 32-bit values from a vector of the instruction set's kind).
template <class V, class Store>
void store_corners_and_box(const V (&X)[3], const V (&Y)[3], const V (&box)[4], Store store, SetupLanes& s) {
    for (int k = 0; k < 3; ++k) {
        store(s.x[k], X[k]);
        store(s.y[k], Y[k]);
    }
    std::int32_t* const to[4] = {s.min_x, s.max_x, s.min_y, s.max_y};
    for (int j = 0; j < 4; ++j) store(to[j], box[j]);
}
#endif

#if SHADELAB_SETUP_LANES == 512

// Each operation is the scalar one lane by lane: IEEE multiplications, additions, divisions and conversions are
// exact or correctly rounded in vector and scalar alike; floor(v) (roundscale towards -inf) is what snap's
// truncate-and-correct computes for every v of the guard band (|v| < 2^28); x / 256 is
// x * (1 / 256), exact for both (a power of two, no underflow at these magnitudes).
static_assert(kSetupLanes == 8, "one AVX-512 vector of 64-bit lanes per value");
// GCC 12 warns (-Wuninitialized) on the unmasked forms of these, which pass an undefined vector through: the
// zero-masking forms with every lane set are the same instructions.
inline __m512i slli64(__m512i v, unsigned n) { return _mm512_maskz_slli_epi64(0xFF, v, n); }
inline __m512i srai64(__m512i v, unsigned n) { return _mm512_maskz_srai_epi64(0xFF, v, n); }
inline __m512i min64(__m512i a, __m512i b) { return _mm512_maskz_min_epi64(0xFF, a, b); }
inline __m512i max64(__m512i a, __m512i b) { return _mm512_maskz_max_epi64(0xFF, a, b); }
// Eight triangles' corners as setup_lanes computes with them: snapped positions and NDC depths in screen order
// (clockwise), twice the signed area before the swap, and setup_mesh_triangle's tests.
struct LaneCorners {
    __m512i X[3], Y[3], area;
    __m512d Z[3];
    __mmask8 outside, one_by_one, front;   // all beyond one plane; needs clipping; front-facing (swapped)
};

// The corners of triangles tris[0 .. 7]: their vertex records gathered, the positions snapped (zeros in the lanes
// outside or left to the one-at-a-time path), oriented clockwise as setup_triangle orients them.
LaneCorners gather_lanes(const glm::u32vec3* tris, const SetupVertex* vertices) {
    alignas(64) std::int64_t index[3][kSetupLanes];
    record_words(tris, index);
    const double* const words = reinterpret_cast<const double*>(vertices);
    const __m512i zero = _mm512_setzero_si512();
    __m512i I[3];
    __m256i code[3];
    for (int k = 0; k < 3; ++k) {
        I[k] = _mm512_load_si512(index[k]);
        code[k] = _mm512_mask_i64gather_epi32(_mm256_setzero_si256(), 0xFF, slli64(I[k], 1),
                                              reinterpret_cast<const int*>(words + 3), 4);
    }
    const __m256i all3 = _mm256_and_si256(_mm256_and_si256(code[0], code[1]), code[2]);
    const __m256i any3 = _mm256_or_si256(_mm256_or_si256(code[0], code[1]), code[2]);
    // setup_mesh_triangle's tests: all three vertices beyond one plane (culled), else clipping needed (left to it)
    const __mmask8 outside = _mm256_test_epi32_mask(all3, _mm256_set1_epi32(kFrustumBits));
    const __mmask8 one_by_one = __mmask8(_mm256_test_epi32_mask(any3, _mm256_set1_epi32(kBehindNear | kOffGuard)) & ~outside);
    const __mmask8 fast = __mmask8(~(outside | one_by_one));
    // snapped positions (zeros in the one-by-one lanes) and NDC depths
    __m512i X[3], Y[3];
    __m512d Z[3];
    const __m512d sub = _mm512_set1_pd(double(kSub)), half = _mm512_set1_pd(0.5);
    auto snap_v = [&](__m512d p) {
        const __m512d v = _mm512_add_pd(_mm512_mul_pd(p, sub), half);
        return _mm512_cvttpd_epi64(_mm512_maskz_roundscale_pd(0xFF, v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
    };
    for (int k = 0; k < 3; ++k) {
        X[k] = snap_v(_mm512_mask_i64gather_pd(_mm512_setzero_pd(), fast, I[k], words, 8));
        Y[k] = snap_v(_mm512_mask_i64gather_pd(_mm512_setzero_pd(), fast, I[k], words + 1, 8));
        Z[k] = _mm512_mask_i64gather_pd(_mm512_setzero_pd(), 0xFF, I[k], words + 2, 8);
    }
    const __m512i area = _mm512_sub_epi64(_mm512_mullo_epi64(_mm512_sub_epi64(X[1], X[0]), _mm512_sub_epi64(Y[2], Y[0])),
                                          _mm512_mullo_epi64(_mm512_sub_epi64(Y[1], Y[0]), _mm512_sub_epi64(X[2], X[0])));
    const __mmask8 front = _mm512_cmplt_epi64_mask(area, zero);
    LaneCorners c;
    c.X[0] = X[0];
    c.Y[0] = Y[0];
    c.Z[0] = Z[0];
    c.X[1] = _mm512_mask_blend_epi64(front, X[1], X[2]);
    c.X[2] = _mm512_mask_blend_epi64(front, X[2], X[1]);
    c.Y[1] = _mm512_mask_blend_epi64(front, Y[1], Y[2]);
    c.Y[2] = _mm512_mask_blend_epi64(front, Y[2], Y[1]);
    c.Z[1] = _mm512_mask_blend_pd(front, Z[1], Z[2]);
    c.Z[2] = _mm512_mask_blend_pd(front, Z[2], Z[1]);
    c.area = area;
    c.outside = outside;
    c.one_by_one = one_by_one;
    c.front = front;
    return c;
}

// Box, top-left flags, covered centres and fate of each lane (setup_triangle's and setup_mesh_triangle's tests in
// their order), and the corners, stored into `s`. Returns the kept lanes.
__mmask8 lane_fates(const LaneCorners& c, const Frame& f, SetupLanes& s) {
    const __m512i zero = _mm512_setzero_si512(), one = _mm512_set1_epi64(1);
    const __m512i X0 = c.X[0], X1 = c.X[1], X2 = c.X[2], Y0 = c.Y[0], Y1 = c.Y[1], Y2 = c.Y[2], area = c.area;
    const __mmask8 outside = c.outside, one_by_one = c.one_by_one, front = c.front;
    // bounding box
    const __m512i centre = _mm512_set1_epi64(kSub / 2);
    auto first_pixel = [&](__m512i lo) {   // -floor_sub(-(lo - kSub / 2)), at least 0
        return max64(_mm512_sub_epi64(zero, srai64(_mm512_sub_epi64(centre, lo), kSubBits)), zero);
    };
    auto last_pixel = [&](__m512i hi, std::int64_t last) {   // floor_sub(hi - kSub / 2), at most last
        return min64(srai64(_mm512_sub_epi64(hi, centre), kSubBits), _mm512_set1_epi64(last));
    };
    const __m512i min_x = first_pixel(min64(X0, min64(X1, X2)));
    const __m512i max_x = last_pixel(max64(X0, max64(X1, X2)), f.width - 1);
    const __m512i min_y = first_pixel(min64(Y0, min64(Y1, Y2)));
    const __m512i max_y = last_pixel(max64(Y0, max64(Y1, Y2)), f.height - 1);
    const __mmask8 box_empty = _mm512_cmpgt_epi64_mask(min_x, max_x) | _mm512_cmpgt_epi64_mask(min_y, max_y);
    // edges opposite vertices 0, 1, 2 (1 -> 2, 2 -> 0, 0 -> 1): top-left flags and centres_covered's test
    const __m512i ax[3] = {X1, X2, X0}, ay[3] = {Y1, Y2, Y0};
    const __m512i dx[3] = {_mm512_sub_epi64(X2, X1), _mm512_sub_epi64(X0, X2), _mm512_sub_epi64(X1, X0)};
    const __m512i dy[3] = {_mm512_sub_epi64(Y2, Y1), _mm512_sub_epi64(Y0, Y2), _mm512_sub_epi64(Y1, Y0)};
    const __mmask8 small = _mm512_cmple_epi64_mask(_mm512_sub_epi64(max_x, min_x), one) &
                           _mm512_cmple_epi64_mask(_mm512_sub_epi64(max_y, min_y), one);
    const __mmask8 wide = _mm512_cmpgt_epi64_mask(max_x, min_x), tall = _mm512_cmpgt_epi64_mask(max_y, min_y);
    const __m512i cx = _mm512_add_epi64(slli64(min_x, kSubBits), centre);
    const __m512i cy = _mm512_add_epi64(slli64(min_y, kSubBits), centre);
    __mmask8 tl[3], c00 = 0xFF, c10 = wide, c01 = tall, c11 = wide & tall;
    for (int i = 0; i < 3; ++i) {
        tl[i] = _mm512_cmplt_epi64_mask(dy[i], zero) |
                (_mm512_cmpeq_epi64_mask(dy[i], zero) & _mm512_cmpgt_epi64_mask(dx[i], zero));
        __m512i e = _mm512_sub_epi64(_mm512_mullo_epi64(dx[i], _mm512_sub_epi64(cy, ay[i])),
                                     _mm512_mullo_epi64(dy[i], _mm512_sub_epi64(cx, ax[i])));
        e = _mm512_mask_sub_epi64(e, __mmask8(~tl[i]), e, one);
        const __m512i right = slli64(_mm512_sub_epi64(zero, dy[i]), kSubBits);   // -dy kSub
        const __m512i down = slli64(dx[i], kSubBits);                             // dx kSub
        c00 &= _mm512_cmpge_epi64_mask(e, zero);
        c10 &= _mm512_cmpge_epi64_mask(_mm512_add_epi64(e, right), zero);
        c01 &= _mm512_cmpge_epi64_mask(_mm512_add_epi64(e, down), zero);
        c11 &= _mm512_cmpge_epi64_mask(_mm512_add_epi64(_mm512_add_epi64(e, right), down), zero);
    }
    const __mmask8 uncovered = small & __mmask8(~(c00 | c10 | c01 | c11));
    // the lane's fate, in setup_mesh_triangle's and setup_triangle's order of tests (a later line takes precedence)
    __m256i fate = _mm256_maskz_mov_epi32(box_empty | uncovered, _mm256_set1_epi32(kEmptyLane));
    if (f.cull) fate = _mm256_mask_mov_epi32(fate, __mmask8(~front), _mm256_set1_epi32(kCulledLane));
    fate = _mm256_mask_mov_epi32(fate, _mm512_cmpeq_epi64_mask(area, zero), _mm256_set1_epi32(kEmptyLane));
    fate = _mm256_mask_mov_epi32(fate, one_by_one, _mm256_set1_epi32(kOneByOne));
    fate = _mm256_mask_mov_epi32(fate, outside, _mm256_set1_epi32(kCulledLane));
    auto store32 = [](std::int32_t* to, __m512i v) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(to), _mm512_maskz_cvtepi64_epi32(0xFF, v));
    };
    store_corners_and_box(c.X, c.Y, {min_x, max_x, min_y, max_y}, store32, s);
    const __m256i top_left = _mm256_or_si256(_mm256_or_si256(_mm256_maskz_mov_epi32(tl[0], _mm256_set1_epi32(1)),
                                                              _mm256_maskz_mov_epi32(tl[1], _mm256_set1_epi32(2))),
                                             _mm256_maskz_mov_epi32(tl[2], _mm256_set1_epi32(4)));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(s.top_left), top_left);
    const __m256i cover = _mm256_or_si256(
        _mm256_or_si256(_mm256_maskz_mov_epi32(c00, _mm256_set1_epi32(1)), _mm256_maskz_mov_epi32(c10, _mm256_set1_epi32(2))),
        _mm256_or_si256(_mm256_maskz_mov_epi32(c01, _mm256_set1_epi32(4)), _mm256_maskz_mov_epi32(c11, _mm256_set1_epi32(8))));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(s.small_cover),
                        _mm256_maskz_mov_epi32(small, _mm256_or_si256(cover, _mm256_set1_epi32(kSmall))));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(s.front), _mm256_maskz_mov_epi32(front, _mm256_set1_epi32(1)));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(s.fate), fate);
    return _mm256_cmpeq_epi32_mask(fate, _mm256_set1_epi32(kKept));
}

// The depth plane of each lane, as setup_triangle computes it, into `s` (a lane that is not kept divides by 1).
void lane_depth_planes(const LaneCorners& c, __mmask8 kept, SetupLanes& s) {
    const __m512i X0 = c.X[0], X1 = c.X[1], X2 = c.X[2], Y0 = c.Y[0], Y1 = c.Y[1], Y2 = c.Y[2];
    const __m512d z0 = c.Z[0], z1 = c.Z[1], z2 = c.Z[2];
    // depth plane, as setup_triangle (a lane that is not kept divides by 1: its values are unused)
    const __m512d inv_sub = _mm512_set1_pd(1.0 / double(kSub));
    const __m512d x0 = _mm512_mul_pd(_mm512_cvtepi64_pd(X0), inv_sub), y0 = _mm512_mul_pd(_mm512_cvtepi64_pd(Y0), inv_sub);
    const __m512d x1 = _mm512_sub_pd(_mm512_mul_pd(_mm512_cvtepi64_pd(X1), inv_sub), x0);
    const __m512d y1 = _mm512_sub_pd(_mm512_mul_pd(_mm512_cvtepi64_pd(Y1), inv_sub), y0);
    const __m512d x2 = _mm512_sub_pd(_mm512_mul_pd(_mm512_cvtepi64_pd(X2), inv_sub), x0);
    const __m512d y2 = _mm512_sub_pd(_mm512_mul_pd(_mm512_cvtepi64_pd(Y2), inv_sub), y0);
    const __m512d det = _mm512_mask_blend_pd(kept, _mm512_set1_pd(1.0),
                                             _mm512_sub_pd(_mm512_mul_pd(x1, y2), _mm512_mul_pd(x2, y1)));
    const __m512d dz1 = _mm512_sub_pd(z1, z0), dz2 = _mm512_sub_pd(z2, z0);
    _mm512_storeu_pd(s.dzdx, _mm512_div_pd(_mm512_sub_pd(_mm512_mul_pd(dz1, y2), _mm512_mul_pd(dz2, y1)), det));
    _mm512_storeu_pd(s.dzdy, _mm512_div_pd(_mm512_sub_pd(_mm512_mul_pd(dz2, x1), _mm512_mul_pd(dz1, x2)), det));
    _mm512_storeu_pd(s.z0, z0);
}

void setup_lanes(const glm::u32vec3* tris, const SetupVertex* vertices, const Frame& f, SetupLanes& s) {
    const LaneCorners c = gather_lanes(tris, vertices);
    lane_depth_planes(c, lane_fates(c, f, s), s);
}
#elif SHADELAB_SETUP_LANES == 256
// The same steps in AVX2, four triangles a vector. AVX2 has no 64-bit multiply, minimum, maximum, arithmetic shift,
// or conversion between 64-bit integers and doubles, and needs none of them here: the snapped positions, their
// differences, the boxes and the pixel centres fit 32 bits (inside the guard band a snapped coordinate is below
// 2^28 in magnitude), so they are 32-bit lanes, and only the edge functions and the area, products of two such
// values, are 64-bit lanes, from _mm256_mul_epi32 (32 x 32 -> 64 bits, signed, exact). Masks are vectors of
// all-ones lanes, of 32 bits where they select 32-bit values and of 64 bits where they select 64-bit ones.
static_assert(kSetupLanes == 4, "one AVX2 vector of 64-bit lanes per value");
inline __m256i wide64(__m128i v) { return _mm256_cvtepi32_epi64(v); }   // 32-bit lanes sign-extended to 64 bits
inline __m128i narrow_mask(__m256i m) {                                  // a 64-bit lane mask as a 32-bit one
    return _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(m, _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6)));
}
inline __m256i product64(__m128i a, __m128i b) { return _mm256_mul_epi32(wide64(a), wide64(b)); }
inline __m128i not32(__m128i m) { return _mm_xor_si128(m, _mm_set1_epi32(-1)); }
inline __m256i non_negative64(__m256i v) {   // all ones where v >= 0
    return _mm256_xor_si256(_mm256_cmpgt_epi64(_mm256_setzero_si256(), v), _mm256_set1_epi64x(-1));
}

// Four triangles' corners as setup_lanes computes with them: snapped positions and NDC depths in screen order
// (clockwise), twice the signed area before the swap, and setup_mesh_triangle's tests.
struct LaneCorners {
    __m128i X[3], Y[3];
    __m256i area;
    __m256d Z[3];
    __m128i outside, one_by_one, front;   // all beyond one plane; needs clipping; front-facing (swapped)
};

// The corners of triangles tris[0 .. 3], as the AVX-512 gather_lanes.
LaneCorners gather_lanes(const glm::u32vec3* tris, const SetupVertex* vertices) {
    alignas(32) std::int64_t index[3][kSetupLanes];
    record_words(tris, index);
    const double* const words = reinterpret_cast<const double*>(vertices);
    const __m128i zero = _mm_setzero_si128(), all = _mm_set1_epi32(-1);
    const __m256d all_pd = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    __m256i I[3];
    __m128i code[3];
    for (int k = 0; k < 3; ++k) {
        I[k] = _mm256_load_si256(reinterpret_cast<const __m256i*>(index[k]));
        code[k] = _mm256_mask_i64gather_epi32(zero, reinterpret_cast<const int*>(words + 3),
                                              _mm256_slli_epi64(I[k], 1), all, 4);
    }
    const __m128i all3 = _mm_and_si128(_mm_and_si128(code[0], code[1]), code[2]);
    const __m128i any3 = _mm_or_si128(_mm_or_si128(code[0], code[1]), code[2]);
    const __m128i outside = not32(_mm_cmpeq_epi32(_mm_and_si128(all3, _mm_set1_epi32(kFrustumBits)), zero));
    const __m128i one_by_one = _mm_andnot_si128(
        outside, not32(_mm_cmpeq_epi32(_mm_and_si128(any3, _mm_set1_epi32(kBehindNear | kOffGuard)), zero)));
    const __m256d fast = _mm256_castsi256_pd(wide64(not32(_mm_or_si128(outside, one_by_one))));
    const __m256d sub = _mm256_set1_pd(double(kSub)), half = _mm256_set1_pd(0.5), none = _mm256_setzero_pd();
    auto snap_v = [&](__m256d p) {
        return _mm256_cvttpd_epi32(_mm256_floor_pd(_mm256_add_pd(_mm256_mul_pd(p, sub), half)));
    };
    __m128i X[3], Y[3];
    __m256d Z[3];
    for (int k = 0; k < 3; ++k) {
        X[k] = snap_v(_mm256_mask_i64gather_pd(none, words, I[k], fast, 8));
        Y[k] = snap_v(_mm256_mask_i64gather_pd(none, words + 1, I[k], fast, 8));
        Z[k] = _mm256_mask_i64gather_pd(none, words + 2, I[k], all_pd, 8);
    }
    const __m256i area = _mm256_sub_epi64(product64(_mm_sub_epi32(X[1], X[0]), _mm_sub_epi32(Y[2], Y[0])),
                                          product64(_mm_sub_epi32(Y[1], Y[0]), _mm_sub_epi32(X[2], X[0])));
    const __m256i front = _mm256_cmpgt_epi64(_mm256_setzero_si256(), area);
    const __m128i front32 = narrow_mask(front);
    LaneCorners c;
    c.X[0] = X[0];
    c.Y[0] = Y[0];
    c.Z[0] = Z[0];
    c.X[1] = _mm_blendv_epi8(X[1], X[2], front32);
    c.X[2] = _mm_blendv_epi8(X[2], X[1], front32);
    c.Y[1] = _mm_blendv_epi8(Y[1], Y[2], front32);
    c.Y[2] = _mm_blendv_epi8(Y[2], Y[1], front32);
    c.Z[1] = _mm256_blendv_pd(Z[1], Z[2], _mm256_castsi256_pd(front));
    c.Z[2] = _mm256_blendv_pd(Z[2], Z[1], _mm256_castsi256_pd(front));
    c.area = area;
    c.outside = outside;
    c.one_by_one = one_by_one;
    c.front = front32;
    return c;
}

// The pixel centres each lane covers of its box's first 2 x 2 (centres_covered's test; `wide` and `tall` as there),
// as four 64-bit lane masks c00, c10, c01, c11, and the top-left flags of the three edges (32-bit lane masks).
struct LaneCover {
    __m256i c[4];
    __m128i tl[3];
};
LaneCover lane_cover(const LaneCorners& c, __m128i min_x, __m128i min_y, __m128i wide, __m128i tall) {
    const __m128i zero = _mm_setzero_si128(), centre = _mm_set1_epi32(kSub / 2);
    const __m128i X0 = c.X[0], X1 = c.X[1], X2 = c.X[2], Y0 = c.Y[0], Y1 = c.Y[1], Y2 = c.Y[2];
    const __m128i ax[3] = {X1, X2, X0}, ay[3] = {Y1, Y2, Y0};   // edges opposite vertices 0, 1, 2
    const __m128i dx[3] = {_mm_sub_epi32(X2, X1), _mm_sub_epi32(X0, X2), _mm_sub_epi32(X1, X0)};
    const __m128i dy[3] = {_mm_sub_epi32(Y2, Y1), _mm_sub_epi32(Y0, Y2), _mm_sub_epi32(Y1, Y0)};
    const __m128i cx = _mm_add_epi32(_mm_slli_epi32(min_x, kSubBits), centre);
    const __m128i cy = _mm_add_epi32(_mm_slli_epi32(min_y, kSubBits), centre);
    const __m256i zero64 = _mm256_setzero_si256(), one64 = _mm256_set1_epi64x(1);
    LaneCover v{{_mm256_set1_epi64x(-1), wide64(wide), wide64(tall), wide64(_mm_and_si128(wide, tall))}, {}};
    for (int i = 0; i < 3; ++i) {
        v.tl[i] = _mm_or_si128(_mm_cmpgt_epi32(zero, dy[i]),
                               _mm_and_si128(_mm_cmpeq_epi32(dy[i], zero), _mm_cmpgt_epi32(dx[i], zero)));
        __m256i e = _mm256_sub_epi64(product64(dx[i], _mm_sub_epi32(cy, ay[i])),
                                     product64(dy[i], _mm_sub_epi32(cx, ax[i])));
        e = _mm256_sub_epi64(e, _mm256_andnot_si256(wide64(v.tl[i]), one64));
        const __m256i right = _mm256_slli_epi64(_mm256_sub_epi64(zero64, wide64(dy[i])), kSubBits);   // -dy kSub
        const __m256i down = _mm256_slli_epi64(wide64(dx[i]), kSubBits);                             // dx kSub
        v.c[0] = _mm256_and_si256(v.c[0], non_negative64(e));
        v.c[1] = _mm256_and_si256(v.c[1], non_negative64(_mm256_add_epi64(e, right)));
        v.c[2] = _mm256_and_si256(v.c[2], non_negative64(_mm256_add_epi64(e, down)));
        v.c[3] = _mm256_and_si256(v.c[3], non_negative64(_mm256_add_epi64(_mm256_add_epi64(e, right), down)));
    }
    return v;
}

// Box, top-left flags, covered centres and fate of each lane, as the AVX-512 lane_fates, stored into `s`. Returns
// the kept lanes (a 32-bit lane mask).
__m128i lane_fates(const LaneCorners& c, const Frame& f, SetupLanes& s) {
    const __m128i zero = _mm_setzero_si128(), one = _mm_set1_epi32(1), centre = _mm_set1_epi32(kSub / 2);
    const __m128i X0 = c.X[0], X1 = c.X[1], X2 = c.X[2], Y0 = c.Y[0], Y1 = c.Y[1], Y2 = c.Y[2];
    auto first_pixel = [&](__m128i lo) {   // -floor_sub(-(lo - kSub / 2)), at least 0
        return _mm_max_epi32(_mm_sub_epi32(zero, _mm_srai_epi32(_mm_sub_epi32(centre, lo), kSubBits)), zero);
    };
    auto last_pixel = [&](__m128i hi, int last) {   // floor_sub(hi - kSub / 2), at most last
        return _mm_min_epi32(_mm_srai_epi32(_mm_sub_epi32(hi, centre), kSubBits), _mm_set1_epi32(last));
    };
    const __m128i min_x = first_pixel(_mm_min_epi32(X0, _mm_min_epi32(X1, X2)));
    const __m128i max_x = last_pixel(_mm_max_epi32(X0, _mm_max_epi32(X1, X2)), f.width - 1);
    const __m128i min_y = first_pixel(_mm_min_epi32(Y0, _mm_min_epi32(Y1, Y2)));
    const __m128i max_y = last_pixel(_mm_max_epi32(Y0, _mm_max_epi32(Y1, Y2)), f.height - 1);
    const __m128i box_empty = _mm_or_si128(_mm_cmpgt_epi32(min_x, max_x), _mm_cmpgt_epi32(min_y, max_y));
    const __m128i small = _mm_and_si128(not32(_mm_cmpgt_epi32(_mm_sub_epi32(max_x, min_x), one)),
                                        not32(_mm_cmpgt_epi32(_mm_sub_epi32(max_y, min_y), one)));
    const LaneCover v = lane_cover(c, min_x, min_y, _mm_cmpgt_epi32(max_x, min_x), _mm_cmpgt_epi32(max_y, min_y));
    __m128i cover32[4];
    for (int j = 0; j < 4; ++j) cover32[j] = narrow_mask(v.c[j]);
    const __m128i covered = _mm_or_si128(_mm_or_si128(cover32[0], cover32[1]), _mm_or_si128(cover32[2], cover32[3]));
    const __m128i uncovered = _mm_andnot_si128(covered, small);
    // the lane's fate, in setup_mesh_triangle's and setup_triangle's order of tests (a later line takes precedence)
    __m128i fate = _mm_and_si128(_mm_or_si128(box_empty, uncovered), _mm_set1_epi32(kEmptyLane));
    if (f.cull) fate = _mm_blendv_epi8(fate, _mm_set1_epi32(kCulledLane), not32(c.front));
    fate = _mm_blendv_epi8(fate, _mm_set1_epi32(kEmptyLane),
                           narrow_mask(_mm256_cmpeq_epi64(c.area, _mm256_setzero_si256())));
    fate = _mm_blendv_epi8(fate, _mm_set1_epi32(kOneByOne), c.one_by_one);
    fate = _mm_blendv_epi8(fate, _mm_set1_epi32(kCulledLane), c.outside);
    auto store = [](std::int32_t* to, __m128i value) { _mm_storeu_si128(reinterpret_cast<__m128i*>(to), value); };
    auto bit = [](__m128i mask, int b) { return _mm_and_si128(mask, _mm_set1_epi32(b)); };
    store_corners_and_box(c.X, c.Y, {min_x, max_x, min_y, max_y}, store, s);
    store(s.top_left, _mm_or_si128(_mm_or_si128(bit(v.tl[0], 1), bit(v.tl[1], 2)), bit(v.tl[2], 4)));
    const __m128i cover = _mm_or_si128(_mm_or_si128(bit(cover32[0], 1), bit(cover32[1], 2)),
                                       _mm_or_si128(bit(cover32[2], 4), bit(cover32[3], 8)));
    store(s.small_cover, _mm_and_si128(small, _mm_or_si128(cover, _mm_set1_epi32(kSmall))));
    store(s.front, bit(c.front, 1));
    store(s.fate, fate);
    return _mm_cmpeq_epi32(fate, _mm_set1_epi32(kKept));
}

// The depth plane of each lane, as the AVX-512 lane_depth_planes (a lane that is not kept divides by 1).
void lane_depth_planes(const LaneCorners& c, __m128i kept, SetupLanes& s) {
    const __m256d inv_sub = _mm256_set1_pd(1.0 / double(kSub));
    auto pixels = [&](__m128i v) { return _mm256_mul_pd(_mm256_cvtepi32_pd(v), inv_sub); };   // exact
    const __m256d x0 = pixels(c.X[0]), y0 = pixels(c.Y[0]);
    const __m256d x1 = _mm256_sub_pd(pixels(c.X[1]), x0), y1 = _mm256_sub_pd(pixels(c.Y[1]), y0);
    const __m256d x2 = _mm256_sub_pd(pixels(c.X[2]), x0), y2 = _mm256_sub_pd(pixels(c.Y[2]), y0);
    const __m256d det = _mm256_blendv_pd(_mm256_set1_pd(1.0), _mm256_sub_pd(_mm256_mul_pd(x1, y2), _mm256_mul_pd(x2, y1)),
                                         _mm256_castsi256_pd(wide64(kept)));
    const __m256d dz1 = _mm256_sub_pd(c.Z[1], c.Z[0]), dz2 = _mm256_sub_pd(c.Z[2], c.Z[0]);
    _mm256_storeu_pd(s.dzdx, _mm256_div_pd(_mm256_sub_pd(_mm256_mul_pd(dz1, y2), _mm256_mul_pd(dz2, y1)), det));
    _mm256_storeu_pd(s.dzdy, _mm256_div_pd(_mm256_sub_pd(_mm256_mul_pd(dz2, x1), _mm256_mul_pd(dz1, x2)), det));
    _mm256_storeu_pd(s.z0, c.Z[0]);
}

void setup_lanes(const glm::u32vec3* tris, const SetupVertex* vertices, const Frame& f, SetupLanes& s) {
    const LaneCorners c = gather_lanes(tris, vertices);
    lane_depth_planes(c, lane_fates(c, f, s), s);
}
#endif

#if SHADELAB_SETUP_LANES

// Mesh triangles [t, t + kSetupLanes) into `out`, in order: setup_lanes' kept triangles as setup_triangle stores
// them, its culled ones counted, and the ones it leaves to setup_mesh_triangle set up there.
void setup_group(const Mesh& mesh, const SetupVertex* vertices, std::size_t t, const Frame& f,
                 Chunk& out) {
    SetupLanes s;
    setup_lanes(&mesh.triangles[t], vertices, f, s);
    for (int l = 0; l < kSetupLanes; ++l) {
        if (s.fate[l] == kOneByOne) {
            setup_mesh_triangle(mesh, vertices, t + std::size_t(l), f, out);
            continue;
        }
        if (s.fate[l] != kKept) {
            out.stats.triangles_culled += s.fate[l] == kCulledLane ? 1 : 0;
            continue;
        }
        RasterTri r;
        for (int k = 0; k < 3; ++k) {
            r.x[k] = s.x[k][l];
            r.y[k] = s.y[k][l];
        }
        r.z0 = s.z0[l];
        r.dzdx = s.dzdx[l];
        r.dzdy = s.dzdy[l];
        r.min_x = std::int16_t(s.min_x[l]);
        r.max_x = std::int16_t(s.max_x[l]);
        r.min_y = std::int16_t(s.min_y[l]);
        r.max_y = std::int16_t(s.max_y[l]);
        r.top_left = std::uint8_t(s.top_left[l]);
        r.small_cover = std::uint8_t(s.small_cover[l]);
        const glm::u32vec3& tri = mesh.triangles[t + std::size_t(l)];
        const bool front = s.front[l] != 0;
        ShadeTri sh;
        sh.mesh_triangle = std::int32_t(t + std::size_t(l));
        sh.clip_vertices = -1;
        sh.swapped = front;
        for (int k = 0; k < 3; ++k) sh.vertex[k] = tri[front && k > 0 ? 3 - k : k];
        out.raster.push_back(r);
        out.shade.push_back(sh);
    }
}

// Mesh triangles [b, e) of a chunk, kSetupLanes at a time, into `out`; returns the first triangle left (fewer than
// kSetupLanes).
std::size_t setup_groups(const Mesh& mesh, const SetupVertex* vertices, std::size_t b,
                         std::size_t e, const Frame& f, Chunk& out) {
    std::size_t t = b;
    for (; t + kSetupLanes <= e; t += kSetupLanes) {
        for (std::size_t p = t + kSetupAhead; p < std::min(e, t + kSetupAhead + kSetupLanes); ++p)
            prefetch_vertices(mesh.triangles[p], vertices);
        setup_group(mesh, vertices, t, f, out);
    }
    return t;
}
#else
// Without AVX-512 or AVX2 no group: every triangle is set up one at a time.
std::size_t setup_groups(const Mesh&, const SetupVertex*, std::size_t b, std::size_t, const Frame&,
                         Chunk&) {
    return b;
}
#endif

// ------------------------------------------------------------------------------------------------------
// Rasterisation into the visibility buffer (depth + winning triangle), tile by tile.
//
// Binning: the image is cut into tiles of kTileW x kTileH pixels; set-up lists each triangle in every tile its
// bounding box touches (per chunk, in id order). A thread takes the next tile, clears its depth and owners
// and draws the tile's triangles chunk by chunk - ascending ids, as one walk of the whole mesh would - with
// the tile's depth and owner buffers (kTileW x kTileH x 12 bytes) in cache. Every pixel sees the same
// triangles in the same order with the same exact integer edge functions and the same depth, whatever the
// tile order or thread count, so coverage and ids are bit-identical to drawing the whole mesh in one pass.

constexpr int kTileW = 128, kTileH = 64;
constexpr int kSpanMinWidth = 12;   // rows at least this wide get their covered span solved per row

struct Tiling {
    int width = 0, height = 0, tiles_x = 0, tiles_y = 0;
    Tiling(int w, int h) : width(w), height(h), tiles_x((w + kTileW - 1) / kTileW), tiles_y((h + kTileH - 1) / kTileH) {}
    int count() const { return tiles_x * tiles_y; }
};

// One chunk's triangles per tile, as compressed rows: the triangles of tile k are ids[start[k] .. start[k+1]),
// as indices into the chunk (ascending).
struct Bins {
    std::vector<std::uint32_t> start;
    std::vector<std::int32_t> ids;
};

// Fills `b` (whose memory is reused from frame to frame) with the chunk's bins.
void bin_chunk(const Chunk& chunk, const Tiling& g, Bins& b) {
    b.start.assign(std::size_t(g.count()) + 1, 0);
    auto each_tile = [&](const RasterTri& t, auto&& fn) {
        for (int ty = t.min_y / kTileH; ty <= t.max_y / kTileH; ++ty)
            for (int tx = t.min_x / kTileW; tx <= t.max_x / kTileW; ++tx) fn(std::size_t(ty * g.tiles_x + tx));
    };
    for (const RasterTri& t : chunk.raster) each_tile(t, [&](std::size_t k) { ++b.start[k + 1]; });
    for (std::size_t k = 0; k < std::size_t(g.count()); ++k) b.start[k + 1] += b.start[k];
    b.ids.resize(b.start.back());
    std::vector<std::uint32_t> next(b.start.begin(), b.start.end() - 1);
    for (std::size_t i = 0; i < chunk.raster.size(); ++i)
        each_tile(chunk.raster[i], [&](std::size_t k) { b.ids[next[k]++] = std::int32_t(i); });
}

// The k in [0, n) with e + step * k >= 0 (one edge function along a row), as [first, last]; empty if first > last.
void edge_span(std::int64_t e, std::int64_t step, std::int64_t n, std::int64_t& first, std::int64_t& last) {
    if (step == 0) {
        if (e < 0) last = -1;
    } else if (step > 0) {
        if (e < 0) first = std::max(first, (-e + step - 1) / step);   // ceil(-e / step), both > 0
    } else {
        if (e < 0) last = -1;
        else last = std::min(last, e / -step);                          // floor(e / -step), both >= 0
    }
    last = std::min(last, n - 1);
}

// Per row of one tile: the span [lo, hi) holding every pixel a triangle covered (a superset of the owned
// ones: emission skips owner -1) and the number of owned pixels.
struct RowSpan {
    std::int32_t lo, hi, covered;
};

// The visibility buffer as draw_triangle updates it, restricted to one tile. Depth is +inf where no
// triangle has been drawn yet (cleared when the tile starts; the owners are not). Depth and owners are the
// drawing thread's own kTileW x kTileH arrays, contiguous, which stay in cache; only the owners outlive the tile
// (emission reads them): publish_owners copies each row's span of them into the frame's owners when the tile
// is done. Depth is never written back over the whole frame (at 4096 x 4096 that saves 134 MB of writes), and
// drawing never touches the frame's owner rows, whose stride is the image width: at 4096 (16 KB, a power of
// two) a tile's 64 rows fell into the same few cache sets and evicted each other.
struct TileBuffer {
    int width;
    int x0, x1, y0, y1;       // the tile: [x0, x1) x [y0, y1)
    double* depth;            // NDC z of the nearest surface so far: pixel (x, y) at [(y - y0) kTileW + x - x0]
    std::int32_t* tile_owner; // its set-up triangle id while the tile is drawn, at the same index as depth
                              // (meaningful only where depth < +inf)
    std::int32_t* owner;      // the whole frame's owners (row stride `width`), written by publish_owners
    RowSpan* rows;            // rows[y - y0]
};

// Depth test of the covered pixel centres x in [xs, xe] of one row at NDC depth z = zy + dzdx (x + 0.5 - x0):
// far plane (the near plane was clipped), then nearest wins; on an exact tie the earlier, lower-index
// triangle keeps the pixel (strict <, ids ascending). Written without branches so that it vectorises;
// depth starts at +inf, so an unowned pixel takes any z <= 1, and a pixel is unowned exactly while its depth
// is +inf (a taken z is <= 1). Returns the pixels newly owned.
// `d` is the tile row's depth, indexed x - tile_x0; `o` the tile row's owners, indexed x - tile_x0 by the
// caller's offset (not cleared: an unowned pixel's owner is whatever the last tile left, and never read).
inline std::int32_t depth_span(double* __restrict d, std::int32_t* __restrict o, int tile_x0, int xs, int xe,
                               double zy, double dzdx, double x0, std::int32_t tid) {
    std::int32_t newly = 0;
    for (int x = xs; x <= xe; ++x) {
        const double z = zy + dzdx * (double(x) + 0.5 - x0);
        const std::int32_t prev = o[x];
        double& dx = d[x - tile_x0];
        const bool take = (z <= 1.0) & (z < dx);
        newly += std::int32_t(take & (dx == std::numeric_limits<double>::infinity()));
        dx = take ? z : dx;
        o[x] = take ? tid : prev;
    }
    return newly;
}

// The edge test of the n < kSpanMinWidth pixels k = 0 .. n-1 of a narrow row, bit k set when pixel k is inside
// (all three edge functions e_i + step_i k >= 0). Each e_i is affine in k, so each test holds on one interval of
// k and their intersection is one interval: the set bits are contiguous, and the row's covered pixels are
// exactly [lowest set bit, highest set bit]. The same exact integer tests as one pixel at a time, in a
// loop of a fixed count without branches (it vectorises), so a row of a small triangle costs one depth span
// instead of a mispredicted branch and a span update per pixel.
static_assert(kSpanMinWidth <= 16, "narrow_row_mask tests 16 pixels");
inline std::uint32_t narrow_row_mask(std::int64_t e0, std::int64_t e1, std::int64_t e2, std::int64_t step0,
                                     std::int64_t step1, std::int64_t step2, int n) {
    std::uint32_t bits = 0;
    for (int k = 0; k < n; ++k, e0 += step0, e1 += step1, e2 += step2)
        bits |= std::uint32_t((e0 | e1 | e2) >= 0) << k;
    return bits;
}

// The narrow row's two steps in AVX-512 or AVX2, each a fixed count of vector instructions instead of a loop of
// n iterations (the loops' exits, at a different n for every triangle, were mispredicted: on spot.obj at 512 x
// 512 the two loops took about a third of rasterisation), and every row's depth test in such spans of 16 pixels.
// The same exact integer edge tests and the same double depth, operation for operation (no fused multiply-adds:
// -ffp-contract=off), so the same pixels and depths.
#if defined(__AVX512F__) || defined(__AVX2__)
#define SHADELAB_RASTER_SPANS 1
#else
#define SHADELAB_RASTER_SPANS 0
#endif
#ifdef __AVX512F__

// Lanes k = 0 .. 7 of the edge function e + k step along a row: e plus the steps of k's bits (exact integers,
// as the scalar loop's repeated additions).
inline __m512i edge_lanes(std::int64_t e, std::int64_t step) {
    const __m512i s = _mm512_set1_epi64(step);
    __m512i v = _mm512_set1_epi64(e);
    v = _mm512_mask_add_epi64(v, 0xAA, v, s);
    const __m512i s2 = _mm512_add_epi64(s, s);
    v = _mm512_mask_add_epi64(v, 0xCC, v, s2);
    return _mm512_mask_add_epi64(v, 0xF0, v, _mm512_add_epi64(s2, s2));
}

// narrow_row_mask for 16 pixels at once, the bits past n cleared.
inline std::uint32_t narrow_row_bits(std::int64_t e0, std::int64_t e1, std::int64_t e2, std::int64_t step0,
                                     std::int64_t step1, std::int64_t step2, int n) {
    const __m512i a0 = edge_lanes(e0, step0), a1 = edge_lanes(e1, step1), a2 = edge_lanes(e2, step2);
    const __m512i b0 = _mm512_add_epi64(a0, _mm512_set1_epi64(8 * step0)),
                  b1 = _mm512_add_epi64(a1, _mm512_set1_epi64(8 * step1)),
                  b2 = _mm512_add_epi64(a2, _mm512_set1_epi64(8 * step2));
    const __m512i zero = _mm512_setzero_si512();
    const std::uint32_t lo = _mm512_cmpge_epi64_mask(_mm512_or_si512(_mm512_or_si512(a0, a1), a2), zero);
    const std::uint32_t hi = _mm512_cmpge_epi64_mask(_mm512_or_si512(_mm512_or_si512(b0, b1), b2), zero);
    return (lo | hi << 8) & ((1u << n) - 1u);
}

// depth_span for a span of at most 16 pixels [xs, xe] in masked vectors (lanes past xe neither read nor
// written: a masked load does not touch them, so the span may end at the tile buffer's last element).
inline std::int32_t depth_span_narrow(double* d, std::int32_t* o, int tile_x0, int xs, int xe, double zy,
                                      double dzdx, double x0, std::int32_t tid) {
    const __mmask16 lanes = __mmask16((1u << (xe - xs + 1)) - 1u);
    const __mmask8 lanes_lo = __mmask8(lanes), lanes_hi = __mmask8(lanes >> 8);
    double* const dp = d + (xs - tile_x0);
    // double(x) for the 16 pixels x = xs + k: the sum of two small integers, exact
    const __m512d x_lo = _mm512_add_pd(_mm512_set1_pd(double(xs)), _mm512_setr_pd(0, 1, 2, 3, 4, 5, 6, 7));
    const __m512d x_hi = _mm512_add_pd(x_lo, _mm512_set1_pd(8.0));
    const __m512d half = _mm512_set1_pd(0.5), vx0 = _mm512_set1_pd(x0), vdzdx = _mm512_set1_pd(dzdx),
                  vzy = _mm512_set1_pd(zy), one = _mm512_set1_pd(1.0),
                  inf = _mm512_set1_pd(std::numeric_limits<double>::infinity());
    const __m512d z_lo = _mm512_add_pd(
        vzy, _mm512_mul_pd(vdzdx, _mm512_sub_pd(_mm512_add_pd(x_lo, half), vx0)));
    const __m512d z_hi = _mm512_add_pd(
        vzy, _mm512_mul_pd(vdzdx, _mm512_sub_pd(_mm512_add_pd(x_hi, half), vx0)));
    const __m512d d_lo = _mm512_maskz_loadu_pd(lanes_lo, dp), d_hi = _mm512_maskz_loadu_pd(lanes_hi, dp + 8);
    const __mmask8 take_lo = _mm512_mask_cmp_pd_mask(_mm512_mask_cmp_pd_mask(lanes_lo, z_lo, one, _CMP_LE_OQ), z_lo,
                                                     d_lo, _CMP_LT_OQ);
    const __mmask8 take_hi = _mm512_mask_cmp_pd_mask(_mm512_mask_cmp_pd_mask(lanes_hi, z_hi, one, _CMP_LE_OQ), z_hi,
                                                     d_hi, _CMP_LT_OQ);
    const std::uint32_t fresh = _mm512_mask_cmp_pd_mask(take_lo, d_lo, inf, _CMP_EQ_OQ) |
                                std::uint32_t(_mm512_mask_cmp_pd_mask(take_hi, d_hi, inf, _CMP_EQ_OQ)) << 8;
    _mm512_mask_storeu_pd(dp, take_lo, z_lo);
    _mm512_mask_storeu_pd(dp + 8, take_hi, z_hi);
    _mm512_mask_storeu_epi32(o + xs, __mmask16(take_lo | take_hi << 8), _mm512_set1_epi32(tid));
    return std::int32_t(__builtin_popcount(fresh));
}
#elif defined(__AVX2__)
// The same in AVX2: four 64-bit lanes a vector, masks as vectors (a masked load or store leaves its other lanes
// alone, and does not fault on them).
static_assert(kSpanMinWidth <= 12, "the AVX2 narrow_row_bits tests 12 pixels");

// Bit k set where lane k of v is >= 0 (its sign bit clear), for the four 64-bit lanes of v.
inline std::uint32_t non_negative_bits(__m256i v) {
    return ~std::uint32_t(_mm256_movemask_pd(_mm256_castsi256_pd(v))) & 0xFu;
}

// narrow_row_mask for 12 pixels at once, the bits past n cleared.
inline std::uint32_t narrow_row_bits(std::int64_t e0, std::int64_t e1, std::int64_t e2, std::int64_t step0,
                                     std::int64_t step1, std::int64_t step2, int n) {
    // lanes k = 0 .. 3 of e + k step (exact integers, as the scalar loop's repeated additions), then + 4 step
    auto lanes = [](std::int64_t e, std::int64_t step) {
        return _mm256_add_epi64(_mm256_set1_epi64x(e), _mm256_setr_epi64x(0, step, 2 * step, 3 * step));
    };
    const __m256i f0 = _mm256_set1_epi64x(4 * step0), f1 = _mm256_set1_epi64x(4 * step1),
                  f2 = _mm256_set1_epi64x(4 * step2);
    __m256i a0 = lanes(e0, step0), a1 = lanes(e1, step1), a2 = lanes(e2, step2);
    std::uint32_t bits = 0;
    for (int part = 0; part < 3; ++part) {   // a fixed count: unrolled
        bits |= non_negative_bits(_mm256_or_si256(_mm256_or_si256(a0, a1), a2)) << (4 * part);
        a0 = _mm256_add_epi64(a0, f0);
        a1 = _mm256_add_epi64(a1, f1);
        a2 = _mm256_add_epi64(a2, f2);
    }
    return bits & ((1u << n) - 1u);
}

// depth_span for a span of at most 16 pixels [xs, xe] in masked vectors.
inline std::int32_t depth_span_narrow(double* d, std::int32_t* o, int tile_x0, int xs, int xe, double zy,
                                      double dzdx, double x0, std::int32_t tid) {
    const int count = xe - xs + 1;
    double* const dp = d + (xs - tile_x0);
    const __m256d half = _mm256_set1_pd(0.5), vx0 = _mm256_set1_pd(x0), vdzdx = _mm256_set1_pd(dzdx),
                  vzy = _mm256_set1_pd(zy), one = _mm256_set1_pd(1.0),
                  inf = _mm256_set1_pd(std::numeric_limits<double>::infinity());
    const __m256i lane = _mm256_setr_epi64x(0, 1, 2, 3);
    std::uint32_t take = 0, fresh = 0;
    for (int part = 0; part < 4; ++part) {   // a fixed count: unrolled
        const __m256i in = _mm256_cmpgt_epi64(_mm256_set1_epi64x(count - 4 * part), lane);
        const __m256d x = _mm256_add_pd(_mm256_set1_pd(double(xs + 4 * part)), _mm256_setr_pd(0, 1, 2, 3));
        const __m256d z = _mm256_add_pd(vzy, _mm256_mul_pd(vdzdx, _mm256_sub_pd(_mm256_add_pd(x, half), vx0)));
        const __m256d dd = _mm256_maskload_pd(dp + 4 * part, in);
        const __m256d t = _mm256_and_pd(_mm256_and_pd(_mm256_castsi256_pd(in), _mm256_cmp_pd(z, one, _CMP_LE_OQ)),
                                        _mm256_cmp_pd(z, dd, _CMP_LT_OQ));
        _mm256_maskstore_pd(dp + 4 * part, _mm256_castpd_si256(t), z);
        take |= std::uint32_t(_mm256_movemask_pd(t)) << (4 * part);
        fresh |= std::uint32_t(_mm256_movemask_pd(_mm256_and_pd(t, _mm256_cmp_pd(dd, inf, _CMP_EQ_OQ)))) << (4 * part);
    }
    // the owners: lane k's sign bit is bit k of `take`
    const __m256i shifts = _mm256_setr_epi32(31, 30, 29, 28, 27, 26, 25, 24);
    const __m256i id = _mm256_set1_epi32(tid);
    _mm256_maskstore_epi32(o + xs, _mm256_sllv_epi32(_mm256_set1_epi32(int(take)), shifts), id);
    _mm256_maskstore_epi32(o + xs + 8, _mm256_sllv_epi32(_mm256_set1_epi32(int(take >> 8)), shifts), id);
    return std::int32_t(__builtin_popcount(fresh));
}
#endif

// What draw_triangle calls, in the form this build has: a narrow row's edge bits, the depth test of a narrow
// row's covered span [xs, xe] (at most 16 pixels) and that of any row's (blocks of 16 pixels, or the loop).
#if SHADELAB_RASTER_SPANS
inline std::int32_t depth_span_row(double* d, std::int32_t* o, int tile_x0, int xs, int xe, double zy, double dzdx,
                                   double x0, std::int32_t tid) {
    std::int32_t newly = 0;
    for (int x = xs; x <= xe; x += 16)
        newly += depth_span_narrow(d, o, tile_x0, x, std::min(x + 15, xe), zy, dzdx, x0, tid);
    return newly;
}
#else
inline std::uint32_t narrow_row_bits(std::int64_t e0, std::int64_t e1, std::int64_t e2, std::int64_t step0,
                                     std::int64_t step1, std::int64_t step2, int n) {
    return narrow_row_mask(e0, e1, e2, step0, step1, step2, n);
}
inline std::int32_t depth_span_narrow(double* d, std::int32_t* o, int tile_x0, int xs, int xe, double zy,
                                      double dzdx, double x0, std::int32_t tid) {
    // One pixel (most rows of a triangle smaller than a few pixels) takes the loop's one-pass form.
    return xs == xe ? depth_span(d, o, tile_x0, xs, xs, zy, dzdx, x0, tid)
                    : depth_span(d, o, tile_x0, xs, xe, zy, dzdx, x0, tid);
}
inline std::int32_t depth_span_row(double* d, std::int32_t* o, int tile_x0, int xs, int xe, double zy, double dzdx,
                                   double x0, std::int32_t tid) {
    return depth_span(d, o, tile_x0, xs, xe, zy, dzdx, x0, tid);
}
#endif

// Row y's covered pixels [xs, xe] of triangle `t` (set-up id `tid`; (x0, y0) its first corner in pixels), inside
// the tile of `buf`: their depth test, as one narrow span (at most 16 pixels) or in blocks of 16, and the row's span
// widened to them. The depth at a pixel centre comes from (x, y) alone (never accumulated along the row), so it
// does not depend on where a tile starts.
inline void cover_row(const RasterTri& t, double x0, double y0, int y, int xs, int xe, bool narrow, std::int32_t tid,
                      TileBuffer& buf) {
    const double zy = t.z0 + t.dzdy * (double(y) + 0.5 - y0);
    double* const d = buf.depth + std::size_t(y - buf.y0) * std::size_t(kTileW);
    std::int32_t* const o = buf.tile_owner + std::size_t(y - buf.y0) * std::size_t(kTileW) - buf.x0;
    RowSpan& span = buf.rows[y - buf.y0];
    span.covered += narrow ? depth_span_narrow(d, o, buf.x0, xs, xe, zy, t.dzdx, x0, tid)
                           : depth_span_row(d, o, buf.x0, xs, xe, zy, t.dzdx, x0, tid);
    span.lo = std::min(span.lo, xs);
    span.hi = std::max(span.hi, xe + 1);
}

// Draws a triangle of at most 2 x 2 pixels (set-up id `tid`) into the tile of `buf` from the centres set-up found
// it covers (RasterTri::small_cover): draw_triangle's narrow rows, each row's covered pixels (inside the tile) as
// one depth_span_narrow with the same depth, without draw_triangle's edge functions.
void draw_small(const RasterTri& t, std::int32_t tid, TileBuffer& buf) {
    const int ya = std::max(int(t.min_y), buf.y0), yb = std::min(int(t.max_y), buf.y1 - 1);
    // the box's two columns that lie in the tile: bit 0 column min_x, bit 1 column min_x + 1
    const unsigned columns = (int(t.min_x) >= buf.x0 ? 1u : 0u) | (int(t.min_x) + 1 < buf.x1 ? 2u : 0u);
    const double x0 = double(t.x[0]) / double(kSub), y0 = double(t.y[0]) / double(kSub);
    for (int y = ya; y <= yb; ++y) {
        const unsigned bits = (unsigned(t.small_cover) >> (2 * (y - int(t.min_y)))) & columns & 3u;
        if (bits == 0) continue;
        const int xs = int(t.min_x) + ((bits & 1u) ? 0 : 1), xe = int(t.min_x) + ((bits & 2u) ? 1 : 0);
        cover_row(t, x0, y0, y, xs, xe, true, tid, buf);
    }
}

// Draws triangle `t` (set-up id `tid`) into the tile of `buf`.
// Edge i runs from vertex i+1 to vertex i+2; its function at pixel centre (cx, cy), in sub-pixels, is
// E_i = dx (cy - ay) - dy (cx - ax): exact integers, stepping by -dy * kSub per pixel in x. A pixel is inside
// when E_i > 0, or E_i == 0 on a top-left edge; subtracting 1 from the other edges turns both into E_i >= 0
// (integers). Narrow rows test each pixel into a bit mask whose set bits are their covered span; wide rows
// solve E_i >= 0 for it (the same exact integer inequalities, so the same pixels). Either way a row's covered
// pixels take one depth_span.
void draw_triangle(const RasterTri& t, std::int32_t tid, TileBuffer& buf) {
    if (t.small_cover != 0) {
        draw_small(t, tid, buf);
        return;
    }
    const int ya = std::max(int(t.min_y), buf.y0), yb = std::min(int(t.max_y), buf.y1 - 1);
    const int min_x = std::max(int(t.min_x), buf.x0), max_x = std::min(int(t.max_x), buf.x1 - 1);
    if (ya > yb || min_x > max_x) return;
    std::int64_t ax[3], ay[3], dx[3], dy[3], bias[3];
    for (int i = 0; i < 3; ++i) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        ax[i] = t.x[a];
        ay[i] = t.y[a];
        dx[i] = std::int64_t(t.x[b]) - t.x[a];
        dy[i] = std::int64_t(t.y[b]) - t.y[a];
        bias[i] = (t.top_left >> i) & 1u ? 0 : 1;
    }
    const std::int64_t step0 = -dy[0] * kSub, step1 = -dy[1] * kSub, step2 = -dy[2] * kSub;
    const double x0 = double(t.x[0]) / double(kSub), y0 = double(t.y[0]) / double(kSub);
    const std::int64_t n = std::int64_t(max_x) - min_x + 1;
    const std::int64_t cx = std::int64_t(min_x) * kSub + kSub / 2;
    // The edge functions at the first pixel of row ya, then exact integer steps of dx * kSub per row.
    const std::int64_t cy = std::int64_t(ya) * kSub + kSub / 2;
    std::int64_t row_e0 = dx[0] * (cy - ay[0]) - dy[0] * (cx - ax[0]) - bias[0];
    std::int64_t row_e1 = dx[1] * (cy - ay[1]) - dy[1] * (cx - ax[1]) - bias[1];
    std::int64_t row_e2 = dx[2] * (cy - ay[2]) - dy[2] * (cx - ax[2]) - bias[2];
    const std::int64_t down0 = dx[0] * kSub, down1 = dx[1] * kSub, down2 = dx[2] * kSub;
    for (int y = ya; y <= yb; ++y, row_e0 += down0, row_e1 += down1, row_e2 += down2) {
        if (n < kSpanMinWidth) {
            // Each pixel's edge test, as one bit; the covered pixels are the bits' one interval (see
            // narrow_row_mask), drawn as one span.
            const std::uint32_t bits = narrow_row_bits(row_e0, row_e1, row_e2, step0, step1, step2, int(n));
            if (bits == 0) continue;
            cover_row(t, x0, y0, y, min_x + __builtin_ctz(bits), min_x + 31 - __builtin_clz(bits), true, tid, buf);
        } else {
            std::int64_t first = 0, last = n - 1;
            edge_span(row_e0, step0, n, first, last);
            edge_span(row_e1, step1, n, first, last);
            edge_span(row_e2, step2, n, first, last);
            if (first > last) continue;
            cover_row(t, x0, y0, y, min_x + int(first), min_x + int(last), false, tid, buf);
        }
    }
}

struct TileContext {
    const Tiling* tiling;
    const std::vector<Chunk>* chunks;
    const std::vector<Bins>* bins;
    const std::vector<std::int32_t>* first_id;
    std::int32_t* owner;
    RowSpan* spans;     // spans[tx * height + y]: row y within tile column tx
};

// Copies the tile's owners inside each row's span to the frame's owners, -1 on the pixels no triangle took
// (depth still +inf). Emission reads the owners only inside the spans, so the rest of the frame's owners are
// never written: clearing the whole frame (67 MB at 4096 x 4096) was a pass over memory that two threads shared
// and that did not scale.
void publish_owners(const TileBuffer& buf) {
    for (int y = buf.y0; y < buf.y1; ++y) {
        const RowSpan& span = buf.rows[y - buf.y0];
        const std::ptrdiff_t row = std::ptrdiff_t(y - buf.y0) * kTileW - buf.x0;
        const double* const d = buf.depth + row;
        const std::int32_t* const t = buf.tile_owner + row;
        std::int32_t* const o = buf.owner + std::size_t(y) * std::size_t(buf.width);
        for (int x = span.lo; x < span.hi; ++x)
            o[x] = d[x] == std::numeric_limits<double>::infinity() ? -1 : t[x];
    }
}

constexpr std::uint32_t kDrawAhead = 4;   // bin entries between a prefetch and the draw that reads it

// Clears tile k's spans, draws its triangles chunk by chunk (ascending ids), publishes the owners of its spans
// and clears the depth it wrote; `depth` and `tile_owner` are the calling thread's kTileW x kTileH tile arrays,
// `depth` +inf everywhere on entry and on return.
void raster_tile(const TileContext& c, int k, double* depth, std::int32_t* tile_owner) {
    const Tiling& g = *c.tiling;
    const int tx = k % g.tiles_x, ty = k / g.tiles_x;
    TileBuffer buf{g.width, tx * kTileW, std::min(g.width, (tx + 1) * kTileW), ty * kTileH,
                   std::min(g.height, (ty + 1) * kTileH), depth, tile_owner, c.owner,
                   c.spans + std::size_t(tx) * std::size_t(g.height) + std::size_t(ty * kTileH)};
    for (int y = buf.y0; y < buf.y1; ++y) buf.rows[y - buf.y0] = RowSpan{buf.x1, buf.x0, 0};
    for (std::size_t ci = 0; ci < c.chunks->size(); ++ci) {
        const Chunk& chunk = (*c.chunks)[ci];
        const Bins& b = (*c.bins)[ci];
        const std::int32_t first = (*c.first_id)[ci];
        const std::uint32_t end = b.start[std::size_t(k) + 1];
        for (std::uint32_t i = b.start[std::size_t(k)]; i < end; ++i) {
            // The tile's triangles are scattered over the chunk when the mesh's order is not spatial: ask for
            // one a few entries ahead so that its load overlaps the drawing of this one.
            if (i + kDrawAhead < end) __builtin_prefetch(&chunk.raster[std::size_t(b.ids[i + kDrawAhead])]);
            const std::int32_t local = b.ids[i];
            draw_triangle(chunk.raster[std::size_t(local)], first + local, buf);
        }
    }
    publish_owners(buf);
    // Every depth the tile wrote lies in its rows' spans: +inf there again leaves the whole buffer cleared for
    // the next tile, without a pass over all of it (at 4096 x 4096, 2048 tiles of 64 KB each).
    for (int y = buf.y0; y < buf.y1; ++y) {
        const RowSpan& span = buf.rows[y - buf.y0];
        double* const d = depth + std::ptrdiff_t(y - buf.y0) * kTileW - buf.x0;
        for (int x = span.lo; x < span.hi; ++x) d[x] = std::numeric_limits<double>::infinity();
    }
}

// ------------------------------------------------------------------------------------------------------
// Emission: attributes are computed once per covered pixel, for the triangle that won it.

// Perspective-correct interpolation (Heckbert & Moreton 1991; Low 2002, "Perspective-Correct Interpolation").
// A world-space attribute a is affine on the triangle, a = sum l_i a_i, but the screen position is its
// projection (x/w, y/w), under which a is not affine; a/w and 1/w are (affine functions of x/w, y/w on the
// triangle's plane). With screen-space barycentrics b_i = e_i / sum_j e_j, where e_i is the edge function
// of the edge opposite vertex i at the pixel centre (from the unsnapped vertex positions: snapping decides
// coverage only), a/w = sum b_i a_i / w_i and 1/w = sum b_i / w_i, so
//   l_i = q_i / sum_j q_j,  q_i = e_i / w_i,  and  a = (sum_i q_i a_i) / (sum_j q_j)
// (the common 1 / sum_j e_j cancels). Each e_i is affine in the pixel position, so each q_i, their sum and
// every numerator sum_i q_i a_i is an affine function c + cx X + cy Y of the offset (X, Y) from the first
// corner: set up when emission meets a triangle (a small cache keeps it for the triangle's next pixels), then
// per pixel two multiply-adds per value and one reciprocal.
// In double, this differs from evaluating l_i first by a few double roundings (~1e-15 of the attribute's
// magnitude), far below the float the fragment buffer stores.

// An affine function of the offset (X, Y) from a triangle's first screen corner.
struct Affine {
    double c = 0, cx = 0, cy = 0;
    double at(double X, double Y) const { return c + cx * X + cy * Y; }
};

// The values interpolated per corner, in this order: world position, normal, and the barycentric coordinates
// 1 and 2 in the mesh triangle (coordinate 0 is never stored).
enum CornerValue { kWorldX, kWorldY, kWorldZ, kNormalX, kNormalY, kNormalZ, kBary1, kBary2, kCornerValues };

// The eight CornerValues of one corner, or one coefficient of their eight sums, as one vector (GCC's vector
// extension: lane-wise IEEE operations, which the compiler maps to the machine's widest vectors, or to pairs).
typedef double CornerLanes __attribute__((vector_size(kCornerValues * sizeof(double))));

// A winning triangle's corners, in screen order, with everything interpolation needs.
struct Corners {
    glm::dvec2 screen[3];
    double inv_w[3];
    CornerLanes value[3];   // corner i's CornerValues
    std::int32_t mesh_triangle;
};

// What emission evaluates per pixel for one visible triangle: the affine numerators and their denominator.
struct Resolve {
    double x0, y0;                  // first screen corner (the origin of X, Y)
    Affine q;                       // sum_j q_j
    CornerLanes c, cx, cy;          // sum_i q_i a_i for each CornerValue a: its affine coefficients, lane by lane
    std::int32_t id;                // set-up triangle id
    std::int32_t mesh_triangle;
    bool degenerate;                // zero screen area (unsnapped): every pixel takes the centroid
    Affine sum(int v) const { return Affine{c[v], cx[v], cy[v]}; }   // sum_i q_i a_i for CornerValue v
};

// Written straight into `r` (a slot of emission's cache): built on the stack and copied, its 64-byte moves read
// back the scalar stores just made, which the core cannot forward (perf put about a tenth of emission's samples
// on them).
void resolve_into(const Corners& k, std::int32_t id, Resolve& r) {
    r.x0 = k.screen[0].x;
    r.y0 = k.screen[0].y;
    r.id = id;
    r.mesh_triangle = k.mesh_triangle;
    Affine qi[3];
    double esum = 0.0;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec2 &a = k.screen[(i + 1) % 3], &b = k.screen[(i + 2) % 3];
        // e_i = (b.x - a.x) (y - a.y) - (b.y - a.y) (x - a.x), with x = x0 + X, y = y0 + Y
        const double ex = b.x - a.x, ey = b.y - a.y;
        const double e0 = ex * (r.y0 - a.y) - ey * (r.x0 - a.x);
        esum += e0;
        qi[i] = Affine{e0 * k.inv_w[i], -ey * k.inv_w[i], ex * k.inv_w[i]};
    }
    r.degenerate = esum == 0.0;
    auto weigh = [&](auto value) {   // sum_i q_i value(i)
        Affine s;
        for (int i = 0; i < 3; ++i) {
            const double v = value(i);
            s.c += qi[i].c * v;
            s.cx += qi[i].cx * v;
            s.cy += qi[i].cy * v;
        }
        return s;
    };
    r.q = weigh([](int) { return 1.0; });
    // The eight values' sums as weigh forms them (each starts at 0 and adds its three products in turn; no fused
    // multiply-adds), in lanes: one at a time they were about two hundred scalar operations for a triangle that, in
    // a dense mesh, most often wins one pixel.
    r.c = ((0.0 + qi[0].c * k.value[0]) + qi[1].c * k.value[1]) + qi[2].c * k.value[2];
    r.cx = ((0.0 + qi[0].cx * k.value[0]) + qi[1].cx * k.value[1]) + qi[2].cx * k.value[2];
    r.cy = ((0.0 + qi[0].cy * k.value[0]) + qi[1].cy * k.value[1]) + qi[2].cy * k.value[2];
}

// The fragment arrays' first elements, taken once per frame; triangle, b1 and b2 are null when the frame leaves
// them empty (RasterOptions::triangle_ids).
struct FragmentArrays {
    float *px, *py, *pz, *nx, *ny, *nz, *depth, *b1, *b2;
    std::int32_t *pixel, *triangle;
};

// `fb`'s arrays as emission writes them (an emptied vector may keep its memory, so `triangle_ids` decides).
FragmentArrays fragment_arrays(FragmentBuffer& fb, bool triangle_ids) {
    FragmentArrays a{fb.px.data(), fb.py.data(), fb.pz.data(), fb.nx.data(), fb.ny.data(), fb.nz.data(),
                     fb.depth.data(), nullptr, nullptr, fb.pixel.data(), nullptr};
    if (triangle_ids) {
        a.b1 = fb.b1.data();
        a.b2 = fb.b2.data();
        a.triangle = fb.triangle.data();
    }
    return a;
}

struct EmitContext {
    const Mesh* mesh;
    const ScreenVertex* vertices;
    const std::vector<Chunk>* chunks;
    const std::vector<std::int32_t>* first_id;   // first set-up triangle id of each chunk (+ total)
    const std::int32_t* owner;
    const RowSpan* spans;       // per tile column and row: the covered span (see raster_tile)
    int tiles_x;
    glm::dvec3 eye, forward;
    bool flip;
    int width, height;
    FragmentArrays out;
};

// The set-up chunk holding triangle `id`.
std::size_t chunk_of(const EmitContext& c, std::int32_t id) {
    const std::vector<std::int32_t>& first_id = *c.first_id;
    return std::size_t(std::upper_bound(first_id.begin(), first_id.end(), id) - first_id.begin()) - 1;
}

const ShadeTri& shade_of(const EmitContext& c, std::size_t chunk, std::int32_t id) {
    return (*c.chunks)[chunk].shade[std::size_t(id - (*c.first_id)[chunk])];
}

// (Stored through a reference: a 64-byte vector returned by value has another calling convention with AVX-512
// than without, which GCC warns of in portable builds.)
void set_corner_values(const glm::dvec3& world, const glm::dvec3& normal, double bary1, double bary2, CornerLanes& out) {
    out = CornerLanes{world.x, world.y, world.z, normal.x, normal.y, normal.z, bary1, bary2};
}

Corners corners_of(const EmitContext& c, std::int32_t id) {
    const std::size_t ci = chunk_of(c, id);
    const Chunk& chunk = (*c.chunks)[ci];
    const ShadeTri& s = shade_of(c, ci, id);
    Corners k;
    for (int i = 0; i < 3; ++i) {
        if (s.clip_vertices >= 0) {
            const ClipVertex& v = chunk.clipped[std::size_t(s.clip_vertices + i)];
            set_corner_values(v.world, v.normal, v.bary.y, v.bary.z, k.value[i]);
            k.screen[i] = viewport_transform(v.clip, c.width, c.height);   // the same function set-up used
            k.inv_w[i] = 1.0 / v.clip.w;
        } else {
            const int slot = s.swapped && i > 0 ? 3 - i : i;
            const ScreenVertex& v = c.vertices[s.vertex[i]];
            set_corner_values(v.world, v.normal, slot == 1 ? 1.0 : 0.0, slot == 2 ? 1.0 : 0.0, k.value[i]);
            k.screen[i] = v.screen;
            k.inv_w[i] = v.inv_w;
        }
    }
    k.mesh_triangle = s.mesh_triangle;
    return k;
}

// The interpolated values at one pixel: position, unnormalised normal times the sign of the denominator,
// barycentrics.
struct Interpolated {
    glm::dvec3 P, N, b;
};

// The rare fallback: the centroid weights l_i = (1/3 / w_i) / sum_j (1/3 / w_j), used where the screen
// triangle has no area or the weights' denominator vanishes (a pixel covered after snapping but outside
// the unsnapped triangle), so that no value is ever NaN.
Interpolated centroid_values(const Corners& k) {
    const glm::dvec3 q(k.inv_w[0] / 3.0, k.inv_w[1] / 3.0, k.inv_w[2] / 3.0);
    const glm::dvec3 l = q / (q.x + q.y + q.z);
    auto at = [&](int v) { return l.x * k.value[0][v] + l.y * k.value[1][v] + l.z * k.value[2][v]; };
    return {{at(kWorldX), at(kWorldY), at(kWorldZ)}, {at(kNormalX), at(kNormalY), at(kNormalZ)},
            {0.0, at(kBary1), at(kBary2)}};
}

Interpolated interpolate(const EmitContext& c, const Resolve& r, double X, double Y) {
    const double s = r.q.at(X, Y);
    const double inv = 1.0 / s;
    if (r.degenerate || !std::isfinite(inv)) return centroid_values(corners_of(c, r.id));
    Interpolated v;
    v.P = glm::dvec3(r.sum(kWorldX).at(X, Y), r.sum(kWorldY).at(X, Y), r.sum(kWorldZ).at(X, Y)) * inv;
    v.N = glm::dvec3(r.sum(kNormalX).at(X, Y), r.sum(kNormalY).at(X, Y), r.sum(kNormalZ).at(X, Y));
    if (s < 0.0) v.N = -v.N;   // the normal's direction is that of its numerator over s
    v.b = glm::dvec3(0.0, r.sum(kBary1).at(X, Y) * inv, r.sum(kBary2).at(X, Y) * inv);
    return v;
}

// Writes fragment `at` of `fb` for pixel (x, y), won by the triangle of `r`: the reference path, one pixel
// at a time, with every fallback (degenerate triangle, vanishing denominator, cancelling normals).
void emit_pixel(const EmitContext& c, const Resolve& r, int x, int y, std::size_t at, FragmentBuffer& fb) {
    const Interpolated v = interpolate(c, r, double(x) + 0.5 - r.x0, double(y) + 0.5 - r.y0);
    const glm::dvec3& P = v.P;
    glm::dvec3 N = v.N;
    const double len = glm::length(N);
    if (len > 0.0 && std::isfinite(len)) {
        N *= 1.0 / len;
    } else {   // opposite vertex normals cancel here: fall back to the face normal (mesh winding)
        const Mesh& m = *c.mesh;
        const glm::u32vec3& tri = m.triangles[std::size_t(r.mesh_triangle)];
        N = glm::normalize(glm::cross(m.positions[tri[1]] - m.positions[tri[0]], m.positions[tri[2]] - m.positions[tri[0]]));
        if (!finite(N)) N = -c.forward;
    }
    if (c.flip && glm::dot(N, c.eye - P) < 0.0) N = -N;
    // Depth: view-space distance along the camera axis (-z_view), from the interpolated position.
    const double d = glm::dot(P - c.eye, c.forward);
    fb.px[at] = float(P.x);
    fb.py[at] = float(P.y);
    fb.pz[at] = float(P.z);
    fb.nx[at] = float(N.x);
    fb.ny[at] = float(N.y);
    fb.nz[at] = float(N.z);
    fb.pixel[at] = std::int32_t(std::size_t(y) * std::size_t(c.width) + std::size_t(x));
    fb.depth[at] = float(d);
    if (c.out.triangle) {
        fb.triangle[at] = r.mesh_triangle;
        fb.b1[at] = float(v.b.y);
        fb.b2[at] = float(v.b.z);
    }
}

// Pixels of one emission block: a fixed count, so that a block is whole vectors without a scalar tail.
constexpr int kLanes = 4;

#ifdef __AVX__
// A block of pixels in AVX, one 256-bit vector of 4 doubles per step (GCC 12 compiled the portable lane loop
// below to pairs of 128-bit vectors: two vdivpd and two vsqrtpd per block; preferring 256 bits left it scalar).
// The same operations in the same order as emit_pixel, lane for lane (IEEE division, square root and double ->
// float conversion are correctly rounded in vector and scalar alike; no fused multiply-adds: the host is built
// with -ffp-contract=off), so every value is emit_pixel's own, and the portable build's emit_lanes'.
static_assert(kLanes == 4, "one AVX vector of doubles per block");
inline __m256d affine_at(const Affine& a, __m256d X, __m256d Y) {
    return _mm256_add_pd(_mm256_add_pd(_mm256_set1_pd(a.c), _mm256_mul_pd(_mm256_set1_pd(a.cx), X)),
                         _mm256_mul_pd(_mm256_set1_pd(a.cy), Y));
}
inline __m256d finite_v(__m256d v) {   // finite_d: |v| <= max (false for NaN)
    const __m256d abs = _mm256_andnot_pd(_mm256_set1_pd(-0.0), v);
    return _mm256_cmp_pd(abs, _mm256_set1_pd(std::numeric_limits<double>::max()), _CMP_LE_OQ);
}
inline __m256d sign_of(__m256d negative) {   // -1 where the mask is set, else 1
    return _mm256_blendv_pd(_mm256_set1_pd(1.0), _mm256_set1_pd(-1.0), negative);
}

// Pixels xs .. xs + 3 of row y (Y = y + 0.5 - r.y0), won by the triangle of `r`, stored straight into slots
// `slot` .. of the fragment arrays: all four lanes when `whole` (lanes past the run write slots that later runs
// of the band overwrite), else the first `count` (masked stores). Reads the triangle's numerators from its
// Resolve and the frame's constants from `c` (broadcast loads), so a run costs no copy of either. Returns bit
// i set where lane i needs emit_pixel's fallbacks.
int emit_block_avx(const EmitContext& c, const Resolve& r, double Y_off, std::int32_t row, int xs, std::size_t slot,
                   bool whole, int count) {
    const __m256d one = _mm256_set1_pd(1.0), zero = _mm256_setzero_pd();
    const __m256d X = _mm256_sub_pd(_mm256_add_pd(_mm256_setr_pd(xs, xs + 1, xs + 2, xs + 3), _mm256_set1_pd(0.5)),
                                    _mm256_set1_pd(r.x0));
    const __m256d Y = _mm256_set1_pd(Y_off);
    const __m256d ex = _mm256_set1_pd(c.eye.x), ey = _mm256_set1_pd(c.eye.y), ez = _mm256_set1_pd(c.eye.z);
    const __m256d s = affine_at(r.q, X, Y);
    const __m256d inv = _mm256_div_pd(one, s);
    const __m256d Px = _mm256_mul_pd(affine_at(r.sum(kWorldX), X, Y), inv),
                  Py = _mm256_mul_pd(affine_at(r.sum(kWorldY), X, Y), inv),
                  Pz = _mm256_mul_pd(affine_at(r.sum(kWorldZ), X, Y), inv);
    const __m256d sign = sign_of(_mm256_cmp_pd(s, zero, _CMP_LT_OQ));
    __m256d Nx = _mm256_mul_pd(affine_at(r.sum(kNormalX), X, Y), sign),
            Ny = _mm256_mul_pd(affine_at(r.sum(kNormalY), X, Y), sign),
            Nz = _mm256_mul_pd(affine_at(r.sum(kNormalZ), X, Y), sign);
    const __m256d len = _mm256_sqrt_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(Nx, Nx), _mm256_mul_pd(Ny, Ny)), _mm256_mul_pd(Nz, Nz)));
    const __m256d k = _mm256_div_pd(one, len);
    Nx = _mm256_mul_pd(Nx, k);
    Ny = _mm256_mul_pd(Ny, k);
    Nz = _mm256_mul_pd(Nz, k);
    const __m256d facing = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(Nx, _mm256_sub_pd(ex, Px)),
                                                       _mm256_mul_pd(Ny, _mm256_sub_pd(ey, Py))),
                                         _mm256_mul_pd(Nz, _mm256_sub_pd(ez, Pz)));
    const __m256d back = _mm256_cmp_pd(facing, zero, _CMP_LT_OQ);
    const __m256d turn = sign_of(c.flip ? back : zero);
    Nx = _mm256_mul_pd(Nx, turn);
    Ny = _mm256_mul_pd(Ny, turn);
    Nz = _mm256_mul_pd(Nz, turn);
    const __m256d ok = _mm256_and_pd(_mm256_and_pd(finite_v(inv), _mm256_cmp_pd(len, zero, _CMP_GT_OQ)), finite_v(len));
    const __m256d depth = _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(_mm256_sub_pd(Px, ex), _mm256_set1_pd(c.forward.x)),
                      _mm256_mul_pd(_mm256_sub_pd(Py, ey), _mm256_set1_pd(c.forward.y))),
        _mm256_mul_pd(_mm256_sub_pd(Pz, ez), _mm256_set1_pd(c.forward.z)));
    const FragmentArrays& a = c.out;
    __m128 values[9] = {_mm256_cvtpd_ps(Px), _mm256_cvtpd_ps(Py), _mm256_cvtpd_ps(Pz), _mm256_cvtpd_ps(Nx),
                        _mm256_cvtpd_ps(Ny), _mm256_cvtpd_ps(Nz), _mm256_cvtpd_ps(depth)};
    int arrays = 7;
    if (a.triangle) {   // the barycentrics only where the frame keeps them (RasterOptions::triangle_ids)
        values[7] = _mm256_cvtpd_ps(_mm256_mul_pd(affine_at(r.sum(kBary1), X, Y), inv));
        values[8] = _mm256_cvtpd_ps(_mm256_mul_pd(affine_at(r.sum(kBary2), X, Y), inv));
        arrays = 9;
    }
    float* const to[9] = {a.px, a.py, a.pz, a.nx, a.ny, a.nz, a.depth, a.b1, a.b2};
    const __m128i pixel = _mm_add_epi32(_mm_set1_epi32(row + xs), _mm_setr_epi32(0, 1, 2, 3));
    const __m128i tri = _mm_set1_epi32(r.mesh_triangle);
    if (whole) {
        for (int i = 0; i < arrays; ++i) _mm_storeu_ps(to[i] + slot, values[i]);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(a.pixel + slot), pixel);
        if (a.triangle) _mm_storeu_si128(reinterpret_cast<__m128i*>(a.triangle + slot), tri);
    } else {
        const __m128i mask = _mm_cmpgt_epi32(_mm_set1_epi32(count), _mm_setr_epi32(0, 1, 2, 3));
        for (int i = 0; i < arrays; ++i) _mm_maskstore_ps(to[i] + slot, mask, values[i]);
        _mm_maskstore_ps(reinterpret_cast<float*>(a.pixel + slot), mask, _mm_castsi128_ps(pixel));
        if (a.triangle) _mm_maskstore_ps(reinterpret_cast<float*>(a.triangle + slot), mask, _mm_castsi128_ps(tri));
    }
    return ~_mm256_movemask_pd(ok) & 0xF;
}
#else
// The portable build (no AVX): the block as a loop the compiler vectorises.

// One run's view for emit_lanes: the output arrays from the run's first slot, the triangle's affine numerators
// and the frame constants, copied into locals so that the lane loop keeps them in registers.
struct RunView {
    float *px, *py, *pz, *nx, *ny, *nz, *depth, *b1, *b2;
    std::int32_t *pixel, *triangle;
    Affine q, P0, P1, P2, N0, N1, N2, B1, B2;
    double Y, x0, ex, ey, ez, fx, fy, fz;
    bool flip;
    std::int32_t tri, row;
};

RunView run_view(const EmitContext& c, const Resolve& r, int y, std::size_t at) {
    const FragmentArrays& a = c.out;
    const bool ids = a.triangle != nullptr;   // else b1, b2 and triangle stay null: nothing is stored there
    return RunView{a.px + at, a.py + at, a.pz + at, a.nx + at, a.ny + at, a.nz + at, a.depth + at,
                   ids ? a.b1 + at : nullptr, ids ? a.b2 + at : nullptr, a.pixel + at, ids ? a.triangle + at : nullptr,
                   r.q, r.sum(kWorldX), r.sum(kWorldY), r.sum(kWorldZ), r.sum(kNormalX), r.sum(kNormalY),
                   r.sum(kNormalZ), r.sum(kBary1), r.sum(kBary2), double(y) + 0.5 - r.y0, r.x0,
                   c.eye.x, c.eye.y, c.eye.z, c.forward.x, c.forward.y, c.forward.z, c.flip, r.mesh_triangle,
                   std::int32_t(std::size_t(y) * std::size_t(c.width))};
}

// One block's fragments, computed in the calling thread's own arrays (which alias nothing, so the lane loop
// vectorises without run-time overlap checks) and then copied to the fragment buffer whole.
struct LaneBlock {
    float px[kLanes], py[kLanes], pz[kLanes], nx[kLanes], ny[kLanes], nz[kLanes], depth[kLanes], b1[kLanes], b2[kLanes];
    std::int32_t pixel[kLanes], triangle[kLanes];
    std::int32_t fix[kLanes];   // 1: the pixel needs emit_pixel's fallbacks
};

// Fragments of the Lanes pixels x = xs + i (lanes from Lanes on are left unset): the same operations as
// emit_pixel in the same order (no fused multiply-adds: the host is built with -ffp-contract=off), one loop
// without branches that the compiler vectorises. Lanes is kLanes, or 1 for the one-pixel runs of small
// triangles, which a whole block would only slow down.
template <int Lanes>
LaneBlock emit_lanes(const RunView& v, int xs) {
    const double Y = v.Y, x0 = v.x0, ex = v.ex, ey = v.ey, ez = v.ez, fx = v.fx, fy = v.fy, fz = v.fz;
    const Affine q = v.q, P0 = v.P0, P1 = v.P1, P2 = v.P2, N0 = v.N0, N1 = v.N1, N2 = v.N2, B1 = v.B1, B2 = v.B2;
    const bool flip = v.flip;
    const std::int32_t tri = v.tri, first = v.row + xs;
    LaneBlock b;
    for (int i = 0; i < Lanes; ++i) {
        const double X = double(xs + i) + 0.5 - x0;
        const double s = q.at(X, Y);
        const double inv = 1.0 / s;
        const double Px = P0.at(X, Y) * inv, Py = P1.at(X, Y) * inv, Pz = P2.at(X, Y) * inv;
        const double sign = s < 0.0 ? -1.0 : 1.0;   // -N for s < 0: negation is exact, as in interpolate()
        double Nx = N0.at(X, Y) * sign, Ny = N1.at(X, Y) * sign, Nz = N2.at(X, Y) * sign;
        const double len = std::sqrt(Nx * Nx + Ny * Ny + Nz * Nz);
        const double k = 1.0 / len;
        Nx *= k;
        Ny *= k;
        Nz *= k;
        const double facing = Nx * (ex - Px) + Ny * (ey - Py) + Nz * (ez - Pz);
        const double turn = (flip & (facing < 0.0)) ? -1.0 : 1.0;
        Nx *= turn;
        Ny *= turn;
        Nz *= turn;
        b.fix[i] = std::int32_t(!(finite_d(inv) & (len > 0.0) & finite_d(len)));
        b.px[i] = float(Px);
        b.py[i] = float(Py);
        b.pz[i] = float(Pz);
        b.nx[i] = float(Nx);
        b.ny[i] = float(Ny);
        b.nz[i] = float(Nz);
        b.depth[i] = float((Px - ex) * fx + (Py - ey) * fy + (Pz - ez) * fz);
        b.b1[i] = float(B1.at(X, Y) * inv);
        b.b2[i] = float(B2.at(X, Y) * inv);
        b.pixel[i] = first + i;
        b.triangle[i] = tri;
    }
    return b;
}

// The first m lanes of `b` into slots o .. o + m of the run's arrays: M > 0 stores the constant count M (a copy
// of constant size: one vector or scalar store per array), M == 0 the count n.
template <int M>
void store_lanes(const LaneBlock& b, int n, int o, const RunView& v) {
    const int m = M > 0 ? M : n;
    const std::size_t f = std::size_t(m) * sizeof(float), i = std::size_t(m) * sizeof(std::int32_t);
    std::memcpy(v.px + o, b.px, f);
    std::memcpy(v.py + o, b.py, f);
    std::memcpy(v.pz + o, b.pz, f);
    std::memcpy(v.nx + o, b.nx, f);
    std::memcpy(v.ny + o, b.ny, f);
    std::memcpy(v.nz + o, b.nz, f);
    std::memcpy(v.depth + o, b.depth, f);
    if (v.triangle) {
        std::memcpy(v.b1 + o, b.b1, f);
        std::memcpy(v.b2 + o, b.b2, f);
        std::memcpy(v.triangle + o, b.triangle, i);
    }
    std::memcpy(v.pixel + o, b.pixel, i);
}

#endif

// Writes the fragments of pixels [xa, xb) of row y, all won by the triangle of `r`, from index `at` on, in
// blocks of kLanes pixels. A block may run past xb: its extra lanes write slots [at + xb - xa, ...) that the
// next runs of the same band overwrite, so only slots before `room` (the end of the band's own slice of the
// buffer, which no other thread writes) may be written; a block that would pass it takes the exact count.
// Every pixel's values are those of the one-lane loop; the few that need a fallback are redone by emit_pixel.
void emit_run(const EmitContext& c, const Resolve& r, int y, int xa, int xb, std::size_t at, std::size_t room,
              FragmentBuffer& fb) {
    if (r.degenerate) {
        for (int x = xa; x < xb; ++x) emit_pixel(c, r, x, y, at + std::size_t(x - xa), fb);
        return;
    }
#ifdef __AVX__
    const double Y = double(y) + 0.5 - r.y0;
    const std::int32_t row = std::int32_t(std::size_t(y) * std::size_t(c.width));
    for (int b0 = xa; b0 < xb; b0 += kLanes) {
        const int n = std::min(kLanes, xb - b0);
        const std::size_t slot = at + std::size_t(b0 - xa);
        int fix = emit_block_avx(c, r, Y, row, b0, slot, slot + kLanes <= room, n) & ((1 << n) - 1);
        for (; fix != 0; fix &= fix - 1) {
            const int i = __builtin_ctz(unsigned(fix));
            emit_pixel(c, r, b0 + i, y, slot + std::size_t(i), fb);
        }
    }
#else
    const RunView v = run_view(c, r, y, at);
    for (int b0 = xa; b0 < xb; b0 += kLanes) {
        const int n = std::min(kLanes, xb - b0), o = b0 - xa;
        const LaneBlock lanes = n == 1 ? emit_lanes<1>(v, b0) : emit_lanes<kLanes>(v, b0);
        if (n == 1)
            store_lanes<1>(lanes, n, o, v);
        else if (at + std::size_t(o + kLanes) <= room)
            store_lanes<kLanes>(lanes, n, o, v);
        else
            store_lanes<0>(lanes, n, o, v);
        for (int i = 0; i < n; ++i)
            if (lanes.fix[i]) emit_pixel(c, r, b0 + i, y, at + std::size_t(o + i), fb);
    }
#endif
}

constexpr int kEmitAhead = 16;   // pixels between a prefetch of a triangle's set-up record and its run

// Entries of emission's Resolve cache (a power of two: the slot is the id's low bits).
constexpr std::size_t kResolveCache = 1024;

// Emission meets the triangles of a row in screen order, and their ids (mesh order) are scattered over the
// set-up records when the mesh's order is not spatial, so a Resolve cache miss first waited for the triangle's
// ShadeTri. From run end `e`: a prefetch of the ShadeTri of the triangle kEmitAhead pixels on, if it is not
// cached. Only a hint: nothing is computed from it. (Prefetching its corners too, from the ShadeTri, measured
// no faster.)
void prefetch_ahead(const EmitContext& c, const std::vector<Resolve>& cache, const std::int32_t* owner, int e, int hi) {
    if (e + kEmitAhead >= hi) return;
    const std::int32_t id = owner[e + kEmitAhead];
    if (id >= 0 && cache[std::size_t(id) & (kResolveCache - 1)].id != id)
        __builtin_prefetch(&shade_of(c, chunk_of(c, id), id));
}

// Writes the fragments of rows [y_begin, y_end) in pixel order, from index `at` of `fb` on, run by run
// (consecutive pixels won by the same triangle). A small direct-mapped cache of Resolves (by triangle id)
// sets each triangle up about once per band of rows. `room` is the end of the band's slice of `fb`.
void emit_rows(const EmitContext& c, std::vector<Resolve>& cache, int y_begin, int y_end, std::size_t at,
               std::size_t room, FragmentBuffer& fb) {
    for (int y = y_begin; y < y_end; ++y) {
        const std::int32_t* const owner = c.owner + std::size_t(y) * std::size_t(c.width);
        for (int tx = 0; tx < c.tiles_x; ++tx) {
            const RowSpan& span = c.spans[std::size_t(tx) * std::size_t(c.height) + std::size_t(y)];
            for (int x = span.lo; x < span.hi;) {
                const std::int32_t id = owner[x];
                if (id < 0) {
                    ++x;
                    continue;
                }
                int e = x + 1;
                while (e < span.hi && owner[e] == id) ++e;
                // The triangle a few pixels on, if it is not cached, will need its set-up record: ask for it now
                // (the ids along a row are scattered over the mesh when its order is not spatial).
                prefetch_ahead(c, cache, owner, e, span.hi);
                Resolve& r = cache[std::size_t(id) & (kResolveCache - 1)];
                if (r.id != id) resolve_into(corners_of(c, id), id, r);
                emit_run(c, r, y, x, e, at, room, fb);
                at += std::size_t(e - x);
                x = e;
            }
        }
    }
}

// The visibility buffer's memory (the owners; depth lives in each thread's tile), kept per calling thread
// from one frame to the next: at 4096 x 4096 it is 67 MB, and fresh pages cost a page fault each. Emission
// reads only owners inside the spans, which raster_tile sets in each frame, so reuse changes nothing (the array
// is zeroed when it grows only so that depth_span never reads an indeterminate value).
struct Scratch {
    std::unique_ptr<std::int32_t[]> owner;
    std::unique_ptr<RowSpan[]> spans;
    std::size_t pixels = 0, rows = 0;
};

Scratch& scratch_for(std::size_t pixels, std::size_t rows) {
    thread_local Scratch s;
    if (pixels > s.pixels) {
        s.owner.reset();
        s.owner.reset(new std::int32_t[pixels]);
        advise_huge_pages(s.owner.get(), pixels * sizeof(std::int32_t));
        std::fill(s.owner.get(), s.owner.get() + pixels, 0);
        s.pixels = pixels;
    }
    if (rows > s.rows) {
        s.spans.reset(new RowSpan[rows]);
        s.rows = rows;
    }
    return s;
}

// Set-up's per-vertex and per-triangle arrays, kept per calling thread from one frame to the next (as Scratch
// keeps the owners): allocated fresh every frame, the dragon's (~25 MB at 202k triangles) took a page fault per
// 4 KB, about a tenth of its set-up. Their contents are rewritten by every frame; only the memory is reused.
struct SetupMemory {
    std::vector<SetupVertex> vertices;
    std::vector<ScreenVertex> sv;
    std::vector<Chunk> chunks;
    std::vector<Bins> bins;   // one per chunk (raster_all)
};

SetupMemory& setup_memory() {
    thread_local SetupMemory m;
    return m;
}

// What set-up leaves for the later stages (in the calling thread's SetupMemory).
struct SetupResult {
    const ScreenVertex* sv;
    std::vector<Chunk>& chunks;
    std::vector<std::int32_t> first_id;   // first set-up triangle id of each chunk (+ total)
};


// Set-up's pieces: vertices in blocks of kVertexBlock, triangles in chunks of kSetupChunk (the last ones
// shorter), taken by the threads from a shared counter. With one contiguous range a thread, a thread that the
// machine did not run for a while (a virtual machine's host shares its cores with other guests: see
// docs/speed.md, "core speed probe") kept the other waiting at the end of the stage; set-up on 2 threads was
// then as slow as on one, or slower (the bunny at 512x512: 7.2 ms on one thread, 9.4 ms on two). Chunks of a
// fixed size also make the split the same for every thread count. A chunk's cost in the later stages is one
// bin list a tile (kTileW x kTileH pixels: 2,048 at 4096 x 4096).
// A small mesh is cut finer, into at least kMinPieces pieces (of a multiple of 256): at the fixed sizes spot's
// 5,856 triangles were two chunks, of 4096 and 1760, and its 2,930 vertices one block, which held two threads'
// set-up at 1.4x one thread's (bench_e2e, spot 512x512). The size depends on the count alone, so the split is
// still the same for every thread count.
constexpr std::size_t kVertexBlock = 8192, kSetupChunk = 4096, kMinPieces = 16;
std::size_t piece_size(std::size_t count, std::size_t largest) {
    const std::size_t even = (count + kMinPieces - 1) / kMinPieces;
    return std::clamp<std::size_t>((even + 255) / 256 * 256, 256, largest);
}

// 1. Vertices to clip space, and to the screen (used only by triangles that need no clipping, whose
//    vertices all have w >= z_near > 0); 2. triangle set-up in chunks of up to kSetupChunk mesh triangles; ids
//    follow mesh order (the depth tie-break). The arrays are the calling thread's SetupMemory.
SetupResult setup_all(const Mesh& mesh, const Frame& f, int threads) {
    const std::size_t nv = mesh.positions.size();
    SetupMemory& mem = setup_memory();
    mem.vertices.resize(nv);
    mem.sv.resize(nv);
    SetupVertex* const vertices = mem.vertices.data();
    ScreenVertex* const sv = mem.sv.data();
    const std::size_t block_size = piece_size(nv, kVertexBlock);
    const std::size_t chunk_size = piece_size(mesh.triangles.size(), kSetupChunk);
    run_pieces(threads, (nv + block_size - 1) / block_size, [&](std::size_t block) {
        for (std::size_t v = block * block_size, e = std::min(nv, v + block_size); v < e; ++v) {
            const glm::dvec4 clip = to_clip(f.view_projection, mesh.positions[v]);
            const glm::dvec2 screen = viewport_transform(clip, f.width, f.height);
            vertices[v] = SetupVertex{screen, ndc_depth(clip), outcode(clip, f.guard)};
            sv[v] = ScreenVertex{screen, 1.0 / clip.w, mesh.positions[v], mesh.normals[v]};
        }
    });
    SetupResult s{sv, mem.chunks, {}};
    const std::size_t nt = mesh.triangles.size();
    s.chunks.resize(std::max<std::size_t>(1, (nt + chunk_size - 1) / chunk_size));
    run_pieces(threads, s.chunks.size(), [&](std::size_t i) {
        Chunk& chunk = s.chunks[i];
        chunk.raster.clear();
        chunk.shade.clear();
        chunk.clipped.clear();
        chunk.stats = RasterStats{};
        const std::size_t b = std::min(nt, i * chunk_size), e = std::min(nt, b + chunk_size);
        chunk.raster.reserve(e - b + 8);
        chunk.shade.reserve(e - b + 8);
        for (std::size_t t = setup_groups(mesh, vertices, b, e, f, chunk); t < e; ++t) {
            if (t + kSetupAhead < e) prefetch_vertices(mesh.triangles[t + kSetupAhead], vertices);
            setup_mesh_triangle(mesh, vertices, t, f, chunk);
        }
    });
    s.first_id.assign(s.chunks.size() + 1, 0);
    for (std::size_t i = 0; i < s.chunks.size(); ++i) {
        if (s.chunks[i].raster.size() >= std::size_t(std::numeric_limits<std::int32_t>::max() - s.first_id[i]))
            fail("mesh '" + mesh.source + "' has too many triangles (2^31 or more after clipping)");
        s.first_id[i + 1] = s.first_id[i] + std::int32_t(s.chunks[i].raster.size());
    }
    return s;
}

// 3. Rasterise into the visibility buffer, tile by tile; threads take the next tile (each tile's pixels
//    belong to it alone: no locks, and the order of tiles changes nothing).
Scratch& raster_all(const SetupResult& s, const Tiling& g, int threads) {
    std::vector<Bins>& bins = setup_memory().bins;
    bins.resize(s.chunks.size());
    run_pieces(threads, s.chunks.size(), [&](std::size_t i) { bin_chunk(s.chunks[i], g, bins[i]); });
    Scratch& scratch = scratch_for(std::size_t(g.width) * std::size_t(g.height), std::size_t(g.tiles_x) * std::size_t(g.height));
    const TileContext tc{&g, &s.chunks, &bins, &s.first_id, scratch.owner.get(), scratch.spans.get()};
    std::atomic<int> next_tile{0};
    run_parallel(threads, [&](int) {
        constexpr std::size_t kTilePixels = std::size_t(kTileW) * std::size_t(kTileH);
        std::unique_ptr<double[]> depth(new double[kTilePixels]);   // +inf: cleared (raster_tile keeps it so)
        std::fill(depth.get(), depth.get() + kTilePixels, std::numeric_limits<double>::infinity());
        std::unique_ptr<std::int32_t[]> tile_owner(new std::int32_t[kTilePixels]());   // zeroed: never indeterminate
        for (int k = next_tile++; k < g.count(); k = next_tile++) raster_tile(tc, k, depth.get(), tile_owner.get());
    });
    return scratch;
}

// Emission's bands: rows a thread takes at a time. Small enough that the threads share out the rows a mesh
// covers evenly (with bands of a whole tile row, a 512 x 512 frame had 8 bands in all, and the last band one
// thread took could leave the other idle for an eighth of the frame); large enough that few triangles are cut
// by a band edge, whose Resolve both bands' threads then compute. Between 16 and 64 rows, about 32 bands or more
// per frame: 16 rows at 512, 32 at 1080, 64 at 4096. It depends on the height alone (nothing in the output
// depends on it: each band writes its own slice of the buffer).
int band_rows(const Tiling& g) {
    int rows = 64;
    while (rows > 16 && g.height / rows < 32) rows /= 2;
    return rows;
}
int band_count(const Tiling& g) { return (g.height + band_rows(g) - 1) / band_rows(g); }

// Where each band of band_rows rows starts in the fragment buffer: the covered counts before it (+ total).
std::vector<std::size_t> band_offsets(const RowSpan* spans, const Tiling& g) {
    const int bands = band_count(g), rows = band_rows(g);
    std::vector<std::size_t> at(std::size_t(bands) + 1, 0);
    for (int y = 0; y < g.height; ++y) {
        std::size_t row = 0;
        for (int tx = 0; tx < g.tiles_x; ++tx)
            row += std::size_t(spans[std::size_t(tx) * std::size_t(g.height) + std::size_t(y)].covered);
        at[std::size_t(y / rows) + 1] += row;
    }
    for (int b = 0; b < bands; ++b) at[std::size_t(b) + 1] += at[std::size_t(b)];
    return at;
}

// 4. Emit fragments in pixel order: each band of band_rows rows writes its own slice of the buffer.
void emit_all(const Mesh& mesh, const Camera& camera, const RasterOptions& o, const SetupResult& s, const Tiling& g,
              const Scratch& scratch, int threads, FragmentBuffer& fb) {
    const std::vector<std::size_t> at = band_offsets(scratch.spans.get(), g);
    fb.width = g.width;
    fb.height = g.height;
    size_fragments(fb, at.back(), o.triangle_ids, threads);
    const EmitContext ctx{&mesh, s.sv, &s.chunks, &s.first_id, scratch.owner.get(), scratch.spans.get(), g.tiles_x,
                          camera.eye, glm::normalize(camera.target - camera.eye), o.flip_normals_to_viewer, g.width,
                          g.height, fragment_arrays(fb, o.triangle_ids)};
    const int bands = band_count(g), rows = band_rows(g);
    std::atomic<int> next_band{0};
    run_parallel(threads, [&](int) {
        std::vector<Resolve> cache(kResolveCache);
        for (Resolve& r : cache) r.id = -1;
        for (int b = next_band++; b < bands; b = next_band++)
            emit_rows(ctx, cache, b * rows, std::min(g.height, (b + 1) * rows), at[std::size_t(b)],
                      at[std::size_t(b) + 1], fb);
    });
}

}  // namespace

void rasterize_into(const Mesh& mesh, const Camera& camera, const RasterOptions& options, FragmentBuffer& fb,
                    RasterStats* stats) {
    const auto t0 = clock_type::now();
    validate(camera, options);
    const int W = options.width, H = options.height;
    int threads = options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    threads = std::max(1, std::min(threads, H));
    validate_mesh(mesh, threads);
    Frame f;
    f.view_projection = camera.projection(double(W) / double(H)) * camera.view();
    f.width = W;
    f.height = H;
    f.guard = double(1 << 20) / double(std::max(W, H));   // >= 64; |screen| <= 2^19 + 2^13 pixels
    f.cull = options.cull_backfaces;

    const SetupResult s = setup_all(mesh, f, threads);
    const auto t_setup = clock_type::now();
    const Tiling g(W, H);
    const Scratch& scratch = raster_all(s, g, threads);
    const auto t_raster = clock_type::now();
    emit_all(mesh, camera, options, s, g, scratch, threads, fb);
    const auto t_emit = clock_type::now();

    if (stats) {
        RasterStats st;
        st.triangles_in = mesh.triangles.size();
        for (const Chunk& c : s.chunks) {
            st.triangles_culled += c.stats.triangles_culled;
            st.triangles_clipped += c.stats.triangles_clipped;
        }
        st.fragments = fb.size();
        st.setup_ms = ms_between(t0, t_setup);
        st.raster_ms = ms_between(t_setup, t_raster);
        st.emit_ms = ms_between(t_raster, t_emit);
        *stats = st;
    }
}

FragmentBuffer rasterize(const Mesh& mesh, const Camera& camera, const RasterOptions& options, RasterStats* stats) {
    FragmentBuffer fb;
    rasterize_into(mesh, camera, options, fb, stats);
    return fb;
}

}  // namespace shadelab
