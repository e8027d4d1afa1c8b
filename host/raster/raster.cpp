// Host rasteriser: clip, set up, rasterise into a visibility buffer by horizontal bands (one per
// thread), then emit one fragment per covered pixel in pixel order. See raster.hpp for the rules.
#include "raster/raster.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <thread>
#include <tuple>

#include "core/error.hpp"

namespace shadelab {

namespace {

// A vertex in clip space carrying the attributes to interpolate.
struct ClipVertex {
    glm::dvec4 clip;
    glm::dvec3 world;
    glm::dvec3 normal;
    glm::dvec3 bary;   // barycentric position in the original mesh triangle (survives clipping)
};

// A triangle ready for rasterisation: fixed-point screen positions (1/256 pixel, as GPUs snap), so the
// edge functions are exact integers and a shared edge gives exactly opposite values on both sides.
struct SetupTriangle {
    std::int64_t x[3], y[3];      // 24.8 fixed point, y down
    std::int64_t area;            // twice the signed area, > 0 after orientation fix
    double sx[3], sy[3];          // the unsnapped screen positions: attributes are interpolated from these,
                                  // so snapping decides coverage only and costs no accuracy
    double z_ndc[3];              // depth, affine in screen space
    double inv_w[3];              // 1 / clip w, for perspective correction
    ClipVertex v[3];
    std::int32_t mesh_triangle;       // index of the mesh triangle it came from
    int min_x, max_x, min_y, max_y;   // pixel bounding box, clamped to the image
};

constexpr int kSubBits = 8;
constexpr std::int64_t kSub = 1 << kSubBits;

// Sutherland-Hodgman against the near plane z_clip >= -w_clip (OpenGL). The intersection of an edge
// is computed from its endpoints in a canonical order, so the two triangles sharing a clipped edge get
// bit-identical new vertices (no crack along the near plane).
ClipVertex intersect_near(const ClipVertex& p, const ClipVertex& q) {
    const bool swap = std::tie(p.clip.x, p.clip.y, p.clip.z, p.clip.w) > std::tie(q.clip.x, q.clip.y, q.clip.z, q.clip.w);
    const ClipVertex& a = swap ? q : p;
    const ClipVertex& b = swap ? p : q;
    const double da = a.clip.z + a.clip.w, db = b.clip.z + b.clip.w;
    const double t = da / (da - db);
    ClipVertex r;
    r.clip = a.clip + t * (b.clip - a.clip);
    r.world = a.world + t * (b.world - a.world);
    r.normal = a.normal + t * (b.normal - a.normal);
    r.bary = a.bary + t * (b.bary - a.bary);
    return r;
}

int clip_near(const ClipVertex in[3], ClipVertex out[4]) {
    int n = 0;
    for (int i = 0; i < 3; ++i) {
        const ClipVertex& cur = in[i];
        const ClipVertex& nxt = in[(i + 1) % 3];
        const bool cin = cur.clip.z + cur.clip.w >= 0.0, nin = nxt.clip.z + nxt.clip.w >= 0.0;
        if (cin) out[n++] = cur;
        if (cin != nin) out[n++] = intersect_near(cur, nxt);
    }
    return n;
}

// Trivially outside the frustum: all three vertices beyond the same side plane.
bool outside_frustum(const ClipVertex v[3]) {
    auto all = [&](auto pred) { return pred(v[0].clip) && pred(v[1].clip) && pred(v[2].clip); };
    return all([](const glm::dvec4& c) { return c.x > c.w; }) || all([](const glm::dvec4& c) { return c.x < -c.w; }) ||
           all([](const glm::dvec4& c) { return c.y > c.w; }) || all([](const glm::dvec4& c) { return c.y < -c.w; }) ||
           all([](const glm::dvec4& c) { return c.z > c.w; }) || all([](const glm::dvec4& c) { return c.z < -c.w; });
}

std::int64_t edge_function(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by, std::int64_t px,
                           std::int64_t py) {
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

// Tie rule for a pixel centre exactly on an edge a->b: include it for one direction of the edge only.
// The neighbour sharing the edge traverses it b->a, so exactly one of the two triangles takes the pixel.
// (With this orientation it is the usual top-left rule.)
bool is_top_left(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by) {
    const std::int64_t dx = bx - ax, dy = by - ay;
    return dy > 0 || (dy == 0 && dx < 0);
}

bool setup_triangle(const ClipVertex v[3], int width, int height, bool cull, SetupTriangle& t, bool& culled) {
    culled = false;
    for (int k = 0; k < 3; ++k) {
        const double w = v[k].clip.w;
        if (!(w > 0.0)) return false;
        const double nx = v[k].clip.x / w, ny = v[k].clip.y / w;
        // Viewport transform (y down); snap to the sub-pixel grid. Clamp far-off coordinates so the
        // 64-bit edge products cannot overflow (|coordinate| < 2^22 * 256).
        const double sx = std::clamp((nx * 0.5 + 0.5) * width, -4.0e6, 4.0e6);
        const double sy = std::clamp((0.5 - ny * 0.5) * height, -4.0e6, 4.0e6);
        t.sx[k] = sx;
        t.sy[k] = sy;
        t.x[k] = std::llround(sx * kSub);
        t.y[k] = std::llround(sy * kSub);
        t.z_ndc[k] = v[k].clip.z / w;
        t.inv_w[k] = 1.0 / w;
        t.v[k] = v[k];
    }
    t.area = edge_function(t.x[0], t.y[0], t.x[1], t.y[1], t.x[2], t.y[2]);
    if (t.area == 0) return false;
    // Counter-clockwise in NDC (y up) is clockwise on screen (y down): front faces have area < 0 here.
    const bool front = t.area < 0;
    if (cull && !front) { culled = true; return false; }
    if (t.area < 0) {
        std::swap(t.x[1], t.x[2]); std::swap(t.y[1], t.y[2]);
        std::swap(t.sx[1], t.sx[2]); std::swap(t.sy[1], t.sy[2]);
        std::swap(t.z_ndc[1], t.z_ndc[2]); std::swap(t.inv_w[1], t.inv_w[2]);
        std::swap(t.v[1], t.v[2]);
        t.area = -t.area;
    }
    const std::int64_t minx = std::min({t.x[0], t.x[1], t.x[2]}), maxx = std::max({t.x[0], t.x[1], t.x[2]});
    const std::int64_t miny = std::min({t.y[0], t.y[1], t.y[2]}), maxy = std::max({t.y[0], t.y[1], t.y[2]});
    // Pixels whose centre (x + 0.5) can lie inside [minx, maxx].
    t.min_x = int(std::max<std::int64_t>(0, (minx - kSub / 2 + kSub - 1) / kSub - 1));
    t.max_x = int(std::min<std::int64_t>(width - 1, (maxx - kSub / 2) / kSub + 1));
    t.min_y = int(std::max<std::int64_t>(0, (miny - kSub / 2 + kSub - 1) / kSub - 1));
    t.max_y = int(std::min<std::int64_t>(height - 1, (maxy - kSub / 2) / kSub + 1));
    return t.min_x <= t.max_x && t.min_y <= t.max_y;
}

struct Coverage {
    bool inside;
    std::int64_t w0, w1, w2;   // edge functions opposite vertex 0, 1, 2
};

Coverage cover(const SetupTriangle& t, int px, int py) {
    const std::int64_t cx = std::int64_t(px) * kSub + kSub / 2, cy = std::int64_t(py) * kSub + kSub / 2;
    Coverage c;
    c.w0 = edge_function(t.x[1], t.y[1], t.x[2], t.y[2], cx, cy);
    c.w1 = edge_function(t.x[2], t.y[2], t.x[0], t.y[0], cx, cy);
    c.w2 = edge_function(t.x[0], t.y[0], t.x[1], t.y[1], cx, cy);
    auto ok = [&](std::int64_t w, int a, int b) {
        return w > 0 || (w == 0 && is_top_left(t.x[a], t.y[a], t.x[b], t.y[b]));
    };
    c.inside = ok(c.w0, 1, 2) && ok(c.w1, 2, 0) && ok(c.w2, 0, 1);
    return c;
}

// Screen-space barycentrics of a pixel centre from the unsnapped vertex positions (double precision).
glm::dvec3 exact_barycentrics(const SetupTriangle& t, int px, int py) {
    const double cx = px + 0.5, cy = py + 0.5;
    auto e = [](double ax, double ay, double bx, double by, double x, double y) {
        return (bx - ax) * (y - ay) - (by - ay) * (x - ax);
    };
    const double w0 = e(t.sx[1], t.sy[1], t.sx[2], t.sy[2], cx, cy);
    const double w1 = e(t.sx[2], t.sy[2], t.sx[0], t.sy[0], cx, cy);
    const double w2 = e(t.sx[0], t.sy[0], t.sx[1], t.sy[1], cx, cy);
    const double sum = w0 + w1 + w2;
    return sum != 0.0 ? glm::dvec3(w0, w1, w2) / sum : glm::dvec3(1.0 / 3.0);
}

void validate(const Camera& cam, const RasterOptions& o) {
    auto bad = [](const std::string& what) { throw Error("rasteriser: " + what); };
    if (o.width < 1 || o.width > 16384 || o.height < 1 || o.height > 16384)
        bad("image size " + std::to_string(o.width) + "x" + std::to_string(o.height) + " is out of range: each side must be in [1, 16384]");
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(cam.eye[k]) || !std::isfinite(cam.target[k]) || !std::isfinite(cam.up[k]))
            bad("camera eye/target/up must be finite");
    if (!(cam.fov_y_deg > 0.0 && cam.fov_y_deg < 180.0))
        bad("field of view " + std::to_string(cam.fov_y_deg) + " deg is out of range: use (0, 180)");
    if (!(cam.z_near > 0.0) || !(cam.z_far > cam.z_near)) bad("clip distances need 0 < z_near < z_far");
    if (glm::length(cam.target - cam.eye) == 0.0) bad("camera eye and target are the same point: move one");
    if (glm::length(glm::cross(cam.target - cam.eye, cam.up)) == 0.0) bad("camera up vector is parallel to the view direction");
}

}  // namespace

FragmentBuffer rasterize(const Mesh& mesh, const Camera& camera, const RasterOptions& options, RasterStats* stats) {
    validate(camera, options);
    const int W = options.width, H = options.height;
    const glm::dmat4 view = camera.view();
    const glm::dmat4 vp = camera.projection(double(W) / H) * view;
    RasterStats st;
    st.triangles_in = mesh.triangles.size();

    // Transform every vertex once.
    std::vector<glm::dvec4> clip(mesh.positions.size());
    for (std::size_t i = 0; i < clip.size(); ++i) clip[i] = vp * glm::dvec4(mesh.positions[i], 1.0);

    // Clip and set up, in mesh order (the order is the depth tie-break).
    std::vector<SetupTriangle> tris;
    tris.reserve(mesh.triangles.size());
    for (std::size_t mt = 0; mt < mesh.triangles.size(); ++mt) {
        const auto& tri = mesh.triangles[mt];
        ClipVertex v[3];
        for (int k = 0; k < 3; ++k) {
            glm::dvec3 unit(0.0);
            unit[k] = 1.0;
            v[k] = {clip[tri[k]], mesh.positions[tri[k]], mesh.normals[tri[k]], unit};
        }
        if (outside_frustum(v)) { ++st.triangles_culled; continue; }
        ClipVertex poly[4];
        int n = 3;
        if (v[0].clip.z + v[0].clip.w < 0 || v[1].clip.z + v[1].clip.w < 0 || v[2].clip.z + v[2].clip.w < 0) {
            n = clip_near(v, poly);
            ++st.triangles_clipped;
        } else {
            std::copy(v, v + 3, poly);
        }
        for (int k = 1; k + 1 < n; ++k) {
            const ClipVertex f[3] = {poly[0], poly[k], poly[k + 1]};
            SetupTriangle t;
            bool culled = false;
            t.mesh_triangle = std::int32_t(mt);
            if (setup_triangle(f, W, H, options.cull_backfaces, t, culled)) tris.push_back(t);
            else if (culled && k == 1) ++st.triangles_culled;
        }
    }

    // Rasterise by bands of rows: each thread owns its rows of the visibility buffer.
    const std::size_t npix = std::size_t(W) * H;
    std::vector<double> depth(npix, std::numeric_limits<double>::infinity());
    std::vector<std::int32_t> owner(npix, -1);
    int threads = options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    threads = std::max(1, std::min(threads, H));
    auto raster_band = [&](int y0, int y1) {
        for (std::size_t ti = 0; ti < tris.size(); ++ti) {
            const SetupTriangle& t = tris[ti];
            const int ya = std::max(t.min_y, y0), yb = std::min(t.max_y, y1 - 1);
            for (int y = ya; y <= yb; ++y)
                for (int x = t.min_x; x <= t.max_x; ++x) {
                    const Coverage c = cover(t, x, y);
                    if (!c.inside) continue;
                    // Screen-space barycentrics; NDC depth is affine in screen space.
                    const glm::dvec3 b = exact_barycentrics(t, x, y);
                    const double z = b.x * t.z_ndc[0] + b.y * t.z_ndc[1] + b.z * t.z_ndc[2];
                    if (z < -1.0 - 1e-9 || z > 1.0) continue;   // beyond the far plane (near is clipped)
                    const std::size_t p = std::size_t(y) * W + x;
                    // Nearest wins; exact ties go to the lower triangle index, which was written first.
                    if (z < depth[p]) {
                        depth[p] = z;
                        owner[p] = std::int32_t(ti);
                    }
                }
        }
    };
    auto band = [&](int i) { return int(std::int64_t(H) * i / threads); };
    {
        std::vector<std::thread> pool;
        for (int i = 1; i < threads; ++i) pool.emplace_back(raster_band, band(i), band(i + 1));
        raster_band(band(0), band(1));
        for (auto& th : pool) th.join();
    }

    // Emit fragments in pixel order, each band into its own buffer, then concatenate.
    const glm::dvec3 fwd = glm::normalize(camera.target - camera.eye);
    std::vector<FragmentBuffer> parts(static_cast<std::size_t>(threads));
    auto emit_band = [&](int i) {
        FragmentBuffer& out = parts[std::size_t(i)];
        for (int y = band(i); y < band(i + 1); ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t p = std::size_t(y) * W + x;
                if (owner[p] < 0) continue;
                const SetupTriangle& t = tris[std::size_t(owner[p])];
                const glm::dvec3 b = exact_barycentrics(t, x, y);
                // Perspective-correct weights: screen barycentrics divided by clip w, renormalised
                // (attributes/w are affine in screen space; Low 2002, "Perspective-Correct Interpolation").
                const double q0 = b.x * t.inv_w[0], q1 = b.y * t.inv_w[1], q2 = b.z * t.inv_w[2];
                const double s = q0 + q1 + q2;
                const double l0 = q0 / s, l1 = q1 / s, l2 = q2 / s;
                const glm::dvec3 P = l0 * t.v[0].world + l1 * t.v[1].world + l2 * t.v[2].world;
                glm::dvec3 N = l0 * t.v[0].normal + l1 * t.v[1].normal + l2 * t.v[2].normal;
                const double len = glm::length(N);
                if (len > 0.0) N /= len;
                else N = glm::normalize(glm::cross(t.v[1].world - t.v[0].world, t.v[2].world - t.v[0].world));
                if (options.flip_normals_to_viewer && glm::dot(N, camera.eye - P) < 0.0) N = -N;
                const double d = glm::dot(P - camera.eye, fwd);
                const glm::dvec3 bary = l0 * t.v[0].bary + l1 * t.v[1].bary + l2 * t.v[2].bary;
                out.push_back(float(P.x), float(P.y), float(P.z), float(N.x), float(N.y), float(N.z), std::int32_t(p), float(d));
                out.triangle.push_back(t.mesh_triangle);
                out.b1.push_back(float(bary.y));
                out.b2.push_back(float(bary.z));
            }
    };
    {
        std::vector<std::thread> pool;
        for (int i = 1; i < threads; ++i) pool.emplace_back(emit_band, i);
        emit_band(0);
        for (auto& th : pool) th.join();
    }
    FragmentBuffer fb;
    std::size_t total = 0;
    for (const auto& part : parts) total += part.size();
    fb.reserve(total);
    for (const auto& part : parts) {
        fb.px.insert(fb.px.end(), part.px.begin(), part.px.end());
        fb.py.insert(fb.py.end(), part.py.begin(), part.py.end());
        fb.pz.insert(fb.pz.end(), part.pz.begin(), part.pz.end());
        fb.nx.insert(fb.nx.end(), part.nx.begin(), part.nx.end());
        fb.ny.insert(fb.ny.end(), part.ny.begin(), part.ny.end());
        fb.nz.insert(fb.nz.end(), part.nz.begin(), part.nz.end());
        fb.pixel.insert(fb.pixel.end(), part.pixel.begin(), part.pixel.end());
        fb.depth.insert(fb.depth.end(), part.depth.begin(), part.depth.end());
        fb.triangle.insert(fb.triangle.end(), part.triangle.begin(), part.triangle.end());
        fb.b1.insert(fb.b1.end(), part.b1.begin(), part.b1.end());
        fb.b2.insert(fb.b2.end(), part.b2.begin(), part.b2.end());
    }
    fb.width = W;
    fb.height = H;
    st.fragments = fb.size();
    if (stats) *stats = st;
    return fb;
}

}  // namespace shadelab
