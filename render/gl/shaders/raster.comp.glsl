// The compute rasterizer of the additive passes (docs/ALGORITHM.md "Compute
// rasterization"; compute_raster.c). One invocation per point splat or line
// segment (ribbon slot) runs the vertex stage (geometry.vert.glsl) for its
// corners, covers the pixel centres of its quad as the fixed pipeline does, and
// runs the pass's fragment stage per covered pixel, which adds into
// raster_sums with float atomics (raster_add, fragment_common.glsl). Sums need
// no primitive order, so invocations run in any order on any thread.
// A primitive whose quad spans more than u_raster_large_px rows is listed for a
// second dispatch instead, one work group per listed primitive with its rows
// shared among the group's invocations, so that a long segment does not hold
// the other 63 primitives of its group back.

#undef main
layout(local_size_x = 64) in;

uniform uint u_raster_first;    // the first primitive (splat or ribbon slot) of this dispatch
uniform uint u_raster_count;    // and the end of its primitives
uniform vec4 u_raster_viewport; // the viewport of the fixed pipeline's draw: x, y, width, height
uniform uint u_raster_large_px; // a quad of more pixel rows than this goes to the large list (0: none)
uniform uint u_raster_large_capacity; // entries of large_list
uniform int u_raster_large_pass;      // 1: the second dispatch, one group per listed primitive
uniform int u_raster_pulled;          // lines: the draw it replaces pulls segments (its triangles' diagonal)

// Primitives the first dispatch left to the second: the indirect dispatch's
// group count (x, 1, 1) and the entries taken (w), then the primitive numbers.
layout(std430, binding = BIND_RASTER_LARGE) buffer RasterLarge { uvec4 large_groups; uint large_list[]; };

struct Corner {
    vec4 pos;
    float g, cscalar, alpha, zview;
    vec3 rgb, wpos, normal;
    vec2 quad, halo;
};

Corner run_corner(int vertex_id, int instance_id)
{
    raster_vertex_id = vertex_id;
    raster_instance_id = instance_id;
    raster_vertex_main();
    Corner c;
    c.pos = raster_position;
    c.g = v_g, c.cscalar = v_cscalar, c.alpha = v_alpha, c.zview = v_zview;
    c.rgb = v_rgb, c.wpos = v_wpos, c.normal = v_normal;
    c.quad = v_quad, c.halo = v_halo;
    return c;
}

vec2 window_xy(vec4 clip) { return (clip.xy / clip.w * 0.5 + 0.5) * u_raster_viewport.zw + u_raster_viewport.xy; }

// Outside the view volume's near or far plane at every corner (the fixed
// pipeline's clipping drops it), or behind the eye at some corner (not drawn
// here: the camera sits outside the data, so ribbons never reach it).
bool culled(vec4 a, vec4 b, vec4 c)
{
    if (a.w <= 0.0 || b.w <= 0.0 || c.w <= 0.0)
        return true;
    return (a.z > a.w && b.z > b.w && c.z > c.w) || (a.z < -a.w && b.z < -b.w && c.z < -c.w);
}

float edge(vec2 a, vec2 b, vec2 p) { return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x); }

// The tie rule: a pixel centre on an edge belongs to the triangle on one side
// only (the edge's direction decides, and a shared edge runs both ways).
bool inside_edge(float e, vec2 d) { return e > 0.0 || (e == 0.0 && (d.y > 0.0 || (d.y == 0.0 && d.x < 0.0))); }

// Shades the pixels of triangle (a, b, c) in rows row0, row0 + row_step, ...
// of its bounding box, interpolating the corners' outputs perspective-correctly.
void raster_triangle(Corner a, Corner b, Corner c, int row0, int row_step)
{
    if (culled(a.pos, b.pos, c.pos))
        return;
    vec2 sa = window_xy(a.pos), sb = window_xy(b.pos), sc = window_xy(c.pos);
    float area = edge(sa, sb, sc);
    if (area == 0.0 || isnan(area))
        return;
    float sgn = area > 0.0 ? 1.0 : -1.0;
    vec3 iw = vec3(1.0 / a.pos.w, 1.0 / b.pos.w, 1.0 / c.pos.w);
    vec3 zn = vec3(a.pos.z, b.pos.z, c.pos.z) * iw;
    vec2 lo = min(sa, min(sb, sc)), hi = max(sa, max(sb, sc));
    int x0 = max(int(ceil(lo.x - 0.5)), 0), x1 = min(int(floor(hi.x - 0.5)), u_raster_size.x - 1);
    int y0 = max(int(ceil(lo.y - 0.5)), 0), y1 = min(int(floor(hi.y - 0.5)), u_raster_size.y - 1);
    vec2 dab = (sb - sa) * sgn, dbc = (sc - sb) * sgn, dca = (sa - sc) * sgn;
    for (int y = y0 + row0; y <= y1; y += row_step) {
        float yc = float(y) + 0.5;
        // The row's span from the three edges (e = A x + B >= 0), widened by a
        // pixel and then tested exactly, so the span's rounding decides nothing.
        float xl = lo.x, xr = hi.x;
        vec2 p0 = vec2(0.0, yc);
        float ea = sgn * edge(sa, sb, p0), eb = sgn * edge(sb, sc, p0), ec = sgn * edge(sc, sa, p0);
        vec3 A = vec3(-dab.y, -dbc.y, -dca.y), B = vec3(ea, eb, ec);
        for (int i = 0; i < 3; i++) {
            if (A[i] > 0.0)
                xl = max(xl, -B[i] / A[i]);
            else if (A[i] < 0.0)
                xr = min(xr, -B[i] / A[i]);
            else if (B[i] < 0.0)
                xr = xl - 2.0;
        }
        int xs = max(int(ceil(xl - 0.5)) - 1, x0), xe = min(int(floor(xr - 0.5)) + 1, x1);
        for (int x = xs; x <= xe; x++) {
            vec2 p = vec2(float(x) + 0.5, yc);
            float wa = sgn * edge(sb, sc, p), wb = sgn * edge(sc, sa, p), wc = sgn * edge(sa, sb, p);
            if (!inside_edge(wa, dbc) || !inside_edge(wb, dca) || !inside_edge(wc, dab))
                continue;
            vec3 l = vec3(wa, wb, wc) / abs(area);
            float z = dot(l, zn);
            if (z < -1.0 || z > 1.0) // the near and far planes, as the fixed pipeline clips them
                continue;
            float inv_w = dot(l, iw);
            vec3 pl = l * iw / inv_w; // perspective-correct weights
            v_g = dot(pl, vec3(a.g, b.g, c.g));
            v_cscalar = dot(pl, vec3(a.cscalar, b.cscalar, c.cscalar));
            v_alpha = dot(pl, vec3(a.alpha, b.alpha, c.alpha));
            v_zview = dot(pl, vec3(a.zview, b.zview, c.zview));
            v_rgb = pl.x * a.rgb + pl.y * b.rgb + pl.z * c.rgb;
            v_wpos = pl.x * a.wpos + pl.y * b.wpos + pl.z * c.wpos;
            v_normal = pl.x * a.normal + pl.y * b.normal + pl.z * c.normal;
            v_quad = pl.x * a.quad + pl.y * b.quad + pl.z * c.quad;
            v_halo = pl.x * a.halo + pl.y * b.halo + pl.z * c.halo;
            raster_frag_coord = vec4(p, z * 0.5 + 0.5, inv_w);
            raster_fragment_main();
        }
    }
}

// Leaves primitive k to the second dispatch where its quad spans more than
// u_raster_large_px rows and the list has room.
bool deferred(uint k, int rows, bool first)
{
    if (!first || u_raster_large_px == 0u || rows <= int(u_raster_large_px))
        return false;
    uint slot = atomicAdd(large_groups.w, 1u);
    if (slot >= u_raster_large_capacity)
        return false;
    large_list[slot] = k;
    atomicMax(large_groups.x, slot + 1u);
    return true;
}

#if PRIM == PRIM_POINTS
// A splat is a screen-aligned square of u_point_radius_px around its centre at
// one depth: its pixels and disc coordinates follow from corner 0 alone.
void raster_primitive(uint k, int row0, int row_step, bool first)
{
    Corner a = run_corner(0, int(k));
    vec4 pos = a.pos;
    if (pos.w <= 0.0 || pos.z > pos.w || pos.z < -pos.w)
        return;
    float r = u_point_radius_px;
    vec2 corner = window_xy(pos);
    vec2 centre = corner + vec2(r) * u_raster_viewport.zw / u_viewport;
    float rr = r * u_raster_viewport.z / u_viewport.x;
    int x0 = max(int(ceil(centre.x - rr - 0.5)), 0), x1 = min(int(ceil(centre.x + rr - 0.5)) - 1, u_raster_size.x - 1);
    int y0 = max(int(ceil(centre.y - rr - 0.5)), 0), y1 = min(int(ceil(centre.y + rr - 0.5)) - 1, u_raster_size.y - 1);
    if (deferred(k, y1 - y0 + 1, first))
        return;
    float z = pos.z / pos.w * 0.5 + 0.5;
    for (int y = y0 + row0; y <= y1; y += row_step)
        for (int x = x0; x <= x1; x++) {
            vec2 p = vec2(float(x) + 0.5, float(y) + 0.5);
            v_g = a.g, v_cscalar = a.cscalar, v_alpha = a.alpha, v_zview = a.zview;
            v_rgb = a.rgb, v_wpos = a.wpos, v_normal = a.normal, v_halo = a.halo;
            v_quad = (p - centre) / rr;
            raster_frag_coord = vec4(p, z, 1.0 / pos.w);
            raster_fragment_main();
        }
}
#else
// Ribbon slot k (PULL_PRIMITIVES): corners 0, 1, 2 and 5 of its six are the
// quad (-1, -1), (1, -1), (1, 1), (-1, 1) = (a-, b-, b+, a+), drawn as the two
// triangles of the draw it replaces, so that the outputs interpolate across
// the same diagonal: the indexed strips' (a-, a+, b-) and (a+, b-, b+), or
// the pulled segments' (a-, b-, b+) and (a-, b+, a+).
void raster_primitive(uint k, int row0, int row_step, bool first)
{
    int id = int(k) * 6;
    Corner a = run_corner(id, 0), b = run_corner(id + 1, 0), c = run_corner(id + 2, 0), d = run_corner(id + 5, 0);
    if (culled(a.pos, b.pos, c.pos) && culled(a.pos, c.pos, d.pos) && culled(a.pos, d.pos, b.pos))
        return;
    vec2 sa = window_xy(a.pos), sb = window_xy(b.pos), sc = window_xy(c.pos), sd = window_xy(d.pos);
    float lo = min(min(sa.y, sb.y), min(sc.y, sd.y)), hi = max(max(sa.y, sb.y), max(sc.y, sd.y));
    if (deferred(k, int(clamp(hi - lo + 1.0, 0.0, 1e6)), first))
        return;
    if (u_raster_pulled != 0) {
        raster_triangle(a, b, c, row0, row_step);
        raster_triangle(a, c, d, row0, row_step);
    } else {
        raster_triangle(a, d, b, row0, row_step);
        raster_triangle(d, b, c, row0, row_step);
    }
}
#endif

void main()
{
    if (u_raster_large_pass != 0) { // one group per listed primitive: invocation i shades rows i, i + 64, ...
        raster_primitive(large_list[gl_WorkGroupID.x], int(gl_LocalInvocationID.x), 64, false);
        return;
    }
    uint k = u_raster_first + gl_GlobalInvocationID.x +
             gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (k < u_raster_count)
        raster_primitive(k, 0, 1, true);
}
