// Vertex pulling for points (splat quads), lines (screen-facing ribbons mitred
// by the vertex tangent, so adjacent segments share edges: no gaps, no overlap)
// and triangles. One draw covers every pass. Each fragment's element is the
// primary element of its primitive's provoking (last) vertex.

// In the compute rasterizer (RASTER_STAGE, raster.comp.glsl) main() runs as a
// function per corner and the outputs are plain globals it reads back.
#ifdef RASTER_STAGE
#define VARYING
#define FLAT_VARYING
#else
#define VARYING out
#define FLAT_VARYING flat out
#endif

VARYING float v_g;        // importance g
VARYING float v_cscalar;  // colour scalar in colormap coordinates
VARYING vec3 v_rgb;       // per-vertex colour (colour mode 2)
VARYING float v_alpha;    // blended element opacity (passes that read them)
VARYING float v_zview;    // view-space depth (distance along the view direction)
VARYING vec3 v_wpos;
VARYING vec3 v_normal;    // triangles: normal; lines: ribbon side vector
VARYING vec2 v_quad;      // points: disc coordinates; lines: (across in [-1,1], |<tangent, view>|)
FLAT_VARYING uvec3 v_primary; // primary elements of the primitive's vertices
VARYING vec2 v_halo;      // lines: (signed distance from the centre, ribbon half width), output pixels
#if defined(KANZLER_MAPS) && PRIM == PRIM_LINES
VARYING vec3 v_tangent;   // lines: the vertex tangent (kanzler_maps.frag.glsl)
#endif
#ifndef u_halo_px
uniform float u_halo_px; // lines, compositing passes with style.haloWidth: halo band width in pixels; 0 = none
#endif

#ifdef READ_ALPHA
layout(std430, binding = BIND_ELEMENT_ALPHA) readonly buffer ElementAlpha { float element_alpha[]; };
float vertex_alpha(uint v)
{
    uint o = u_element_offset; // layers: this layer's first element
    if (u_blend == 1)
        return element_alpha[o + v];
    if (u_blend == 2) { // e0 and e0 + 1; a weight of 1 never reads past the last element
        uint e = o + vertex_elements[2u * v];
        float w = float(vertex_elements[2u * v + 1u] & 0xffffu) / 65535.0;
        return w < 1.0 ? w * element_alpha[e] + (1.0 - w) * element_alpha[e + 1u] : element_alpha[e];
    }
    uvec4 e = uvec4(vertex_elements[4u * v], vertex_elements[4u * v + 1u], vertex_elements[4u * v + 2u],
                    vertex_elements[4u * v + 3u]) + uvec4(o);
    if (u_blend == 3) {
        vec2 w = unpackUnorm2x16(vertex_elements[4u * v + 3u]);
        return w.x * element_alpha[e.x] + w.y * element_alpha[e.y] + max(1.0 - w.x - w.y, 0.0) * element_alpha[e.z];
    }
    vec4 w = vec4(vertex_weights[4u * v], vertex_weights[4u * v + 1u], vertex_weights[4u * v + 2u],
                  vertex_weights[4u * v + 3u]);
    return w.x * element_alpha[e.x] + w.y * element_alpha[e.y] + w.z * element_alpha[e.z];
}
#else
float vertex_alpha(uint v) { return 1.0; }
#endif

void emit(uint v, vec3 wpos)
{
    v_g = vertex_importance(v);
    v_cscalar = vertex_color_scalar(v, v_g);
    v_rgb = u_color_mode == 2 ? vertex_rgb(v) : vec3(0.0);
    v_alpha = vertex_alpha(v);
    v_wpos = wpos;
    v_zview = -(u_view * vec4(wpos, 1.0)).z;
    // A filtered vertex lies beyond the far plane: its line (or point) draws nothing.
    gl_Position = vertex_visible(v) ? u_view_proj * vec4(wpos, 1.0) : vec4(0.0, 0.0, 2.0, 1.0);
    v_normal = vec3(0.0);
    v_quad = vec2(0.0);
    v_halo = vec2(0.0);
}

// The ribbon at line vertex v: its centre p, side vector (cross(tangent, view
// ray), unit), half width (never under the pixel minimum), outer half width
// (with the halo band) and the world size of a pixel at its depth.
void ribbon_frame(uint v, out vec3 p, out vec3 to_cam, out vec3 side, out float half_width, out float outer,
                  out float pixel)
{
    p = vertex_position(v);
    to_cam = u_ortho != 0 ? -u_view_dir : normalize(u_eye - p);
    vec3 tangent = vertex_frame(v);
    side = cross(tangent, to_cam);
    if (dot(side, side) < 1e-12) // tangent along the view ray: any perpendicular works
        side = cross(abs(to_cam.x) < 0.9 ? vec3(1, 0, 0) : vec3(0, 1, 0), to_cam);
    side = normalize(side);
    float depth = u_ortho != 0 ? u_focal_dist : max(dot(p - u_eye, u_view_dir), 1e-6 * u_focal_dist);
    pixel = u_pixel_world * depth / u_focal_dist;
    half_width = max(u_line_half_width, u_min_half_pixels * pixel);
    // Depth-dependent halos widen the ribbon by a band beside it (fragment_common.glsl).
    outer = half_width;
    if (u_halo_px > 0.0)
        outer += u_halo_px * pixel;
}

// The varyings of the ribbon's side side_sign at line vertex v (side_sign 0:
// its centre, for one-primitive lines, whose fragments scale the across
// profile and the halo position by their own distance from the centre line).
void ribbon_outputs(uint v, vec3 p, vec3 to_cam, vec3 side, float half_width, float outer, float pixel,
                    float side_sign)
{
    emit(v, p + side * (outer * side_sign));
    v_normal = side;
#if defined(KANZLER_MAPS) && PRIM == PRIM_LINES
    v_tangent = vertex_frame(v);
#endif
    // Tube shading needs a few pixels across; on thinner ribbons the pixel
    // centres would sample the tube profile unevenly along the line (a dotted
    // look), so the profile flattens as the ribbon narrows.
    float width_px = 2.0 * half_width / pixel;
    // .y: |<t, v>|, the direct method's angle-based opacities (fragment_common.glsl's view_cosine).
    vec3 tangent = vertex_frame(v);
    float tlen = length(tangent);
    float sign_or_one = side_sign == 0.0 ? 1.0 : side_sign;
    v_quad = vec2(sign_or_one * clamp((width_px - 1.0) / 4.0, 0.0, 0.85),
                  tlen > 0.0 ? abs(dot(tangent / tlen, to_cam)) : 0.0);
    if (u_halo_px > 0.0) {
        v_quad.x *= outer / half_width; // the same profile across the core
        v_halo = vec2(sign_or_one * outer / pixel, half_width / pixel);
    }
}

// One side of a screen-facing ribbon at line vertex v: offset along
// cross(tangent, view ray) by the half width.
void ribbon_vertex(uint v, float side_sign)
{
    vec3 p, to_cam, side;
    float half_width, outer, pixel;
    ribbon_frame(v, p, to_cam, side, half_width, outer, pixel);
    ribbon_outputs(v, p, to_cam, side, half_width, outer, pixel, side_sign);
}

#ifdef LINE_PRIMITIVE
// Lines as one wide GL_LINES primitive a segment (docs/ALGORITHM.md, "Lines as
// one primitive"): the line's width covers the widest ribbon of the frame, and
// the fragment shader keeps the pixels within the ribbon's half width of the
// segment's centre line, in window pixels (fragment_common.glsl).
uniform vec2 u_window_origin;          // the viewport's lower left corner
noperspective out vec2 v_centre_px;    // the centre line on screen (window pixels)
noperspective out float v_outer_px;    // the ribbon's outer half width in pixels

vec2 window_of(vec4 clip) { return (clip.xy / clip.w * 0.5 + 0.5) * u_viewport + u_window_origin; }
#endif
// Cluster representatives (line_clusters.c): a vertex whose bit is clear
// belongs to a hidden line; its ribbon corners leave the clip volume.
layout(std430, binding = BIND_LINE_MASK) readonly buffer LineMask { uint line_mask[]; };
#ifndef u_line_mask
uniform int u_line_mask;
#endif
bool line_hidden(uint v) { return u_line_mask != 0 && (line_mask[v >> 5] & (1u << (v & 31u))) == 0u; }

#ifdef MARKERS
// time.markers (markers.c): the time attribute and the window's end t1.
uniform int u_marker_attr;
uniform float u_marker_t1;
#endif

#ifdef POINT_SPRITES
uniform vec2 u_clip_scale; // the target's share of the viewport, per axis
#endif

#if PRIM == PRIM_POINTS
layout(std430, binding = BIND_POINT_LIST) readonly buffer PointList { uint point_count; uint point_list[]; };
#endif

void main()
{
#if PRIM == PRIM_POINTS
    // Instanced triangle strip: one instance per (subset-th) point, 4 corners;
    // or per entry of the list of important points, which the strided draw
    // then leaves out (they would count twice).
#ifdef POINT_SPRITES
    uint k = uint(gl_VertexID); // one GL point per splat
#else
    uint k = uint(gl_InstanceID); // one quad (4-vertex strip) per splat
#endif
    uint b = u_first_primitive + k;
    uint v = u_point_list != 0 ? point_list[b] : b * u_subset;
    if (u_point_list == 0 && u_point_jitter > 1u) {
        // A point of the block at random (an integer hash of its number): a
        // regular stride aliases with data stored in periods (an MD dump's
        // atoms frame after frame: every 64th of 16384 atoms a frame is the
        // same atoms in every frame, their paths instead of the cloud).
        uint h = b * 0x9E3779B1u;
        h = (h ^ (h >> 15)) * 0x85EBCA77u;
        h ^= h >> 13;
        uint j = v + h % u_point_jitter;
        v = j < u_vertex_count ? j : v;
    }
    if (u_point_list == 0 && u_keep_bin <= POINT_BINS - 1 && point_bin(vertex_importance(v)) >= u_keep_bin) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    vec2 q = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
    emit(v, vertex_position(v));
    float radius = u_point_list != 0 ? u_point_list_radius_px : u_point_radius_px;
#ifdef POINT_SPRITES
    gl_PointSize = 2.0 * radius;
    gl_Position.xy *= u_clip_scale; // the guard band's wider viewport (lc_renderer_bind_geometry)
#else
    gl_Position.xy += q * (2.0 * radius / u_viewport) * gl_Position.w;
    v_quad = q;
#endif
    v_primary = uvec3(vertex_primary(v));
#elif defined(PULL_PRIMITIVES)
    // Subset draws (every n-th primitive): unindexed, six corners per segment
    // or three per triangle, pulled by primitive number.
#if PRIM == PRIM_TRIANGLES
    uint prim = uint(gl_VertexID) / 3u * u_subset;
    uint corner = uint(gl_VertexID) % 3u;
    uint v = indices[3u * prim + corner];
    emit(v, vertex_position(v));
    v_normal = vertex_frame(v);
    v_primary = uvec3(vertex_primary(indices[3u * prim + 2u]));
#else
    // Ribbon slot q of the strip spans indices 2q .. 2q+3 (runs start at even
    // offsets, gpu_scene.c); a slot across a run break is no segment and is
    // placed outside the clip volume.
    const vec2 quad[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    uint slot = uint(gl_VertexID) / 6u * u_subset;
    vec2 q = quad[gl_VertexID % 6];
    uint ia = indices[2u * slot], ib = indices[2u * slot + 2u];
#ifdef MARKERS
    // A marker where the line leaves the window: its kept vertex a is followed by a vertex b after t1 (the
    // splat sits at t1 on the segment) or by the end of its run (the splat sits at a). Six corners of a
    // screen-aligned square of u_point_radius_px around it, in the colour of a.
    {
        bool ends = ib == STRIP_RESTART;
        uint a = ia >> 1, b = ends ? a : ib >> 1;
        if (ia == STRIP_RESTART || line_hidden(a) || !vertex_visible(a) || (!ends && vertex_visible(b))) {
            gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
            return;
        }
        float ta = attribute_value(u_marker_attr, a), tb = attribute_value(u_marker_attr, b);
        float s = tb > ta ? clamp((u_marker_t1 - ta) / (tb - ta), 0.0, 1.0) : 0.0;
        emit(a, mix(vertex_position(a), vertex_position(b), s));
        gl_Position.xy += q * (2.0 * u_point_radius_px / u_viewport) * gl_Position.w;
        v_primary = uvec3(vertex_primary(a));
        return;
    }
#endif
    if (ia == STRIP_RESTART || ib == STRIP_RESTART) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    uint a = ia >> 1, b = ib >> 1;
    // A time window (filter.c) hides a segment unless both its vertices are kept.
    if (line_hidden(a) || !vertex_visible(a) || !vertex_visible(b)) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    uint v = q.x < 0.0 ? a : b;
    ribbon_vertex(v, q.y);
    v_primary = uvec3(vertex_primary(b));
#endif
#elif PRIM == PRIM_LINES && defined(LINE_PRIMITIVE)
    // Indexed line strips: one vertex a line vertex, on the centre line.
    uint v = uint(gl_VertexID);
    if (line_hidden(v)) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    vec3 p, to_cam, side;
    float half_width, outer, pixel;
    ribbon_frame(v, p, to_cam, side, half_width, outer, pixel);
    ribbon_outputs(v, p, to_cam, side, half_width, outer, pixel, 0.0);
    v_outer_px = outer / pixel;
    v_centre_px = window_of(gl_Position);
    v_primary = uvec3(vertex_primary(v));
#elif PRIM == PRIM_LINES
    // Indexed ribbon strips: two vertices (sides) per line vertex, shared by the
    // two segments that meet there, so each is shaded once.
    uint v = uint(gl_VertexID) >> 1;
    if (line_hidden(v)) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    ribbon_vertex(v, (gl_VertexID & 1) != 0 ? 1.0 : -1.0);
    v_primary = uvec3(vertex_primary(v));
#else
    // Indexed triangles: the scene's own index buffer, shared vertices shaded once.
    uint v = uint(gl_VertexID);
    emit(v, vertex_position(v));
    v_normal = vertex_frame(v);
    v_primary = uvec3(vertex_primary(v));
#endif
}
