// Fragment-side helpers shared by all geometry passes: splat discard, the
// fragment's element (primary of the nearest vertex) and lit colour.

// The compute rasterizer (RASTER_STAGE) has the vertex stage's outputs as
// globals (geometry.vert.glsl), interpolated into them per pixel, and runs
// the pass's main() as a function: DISCARD ends it without adding anything.
#ifdef RASTER_STAGE
#undef main
#define main raster_fragment_main
#define DISCARD return
// The pass's sums, per pixel of u_raster_size its u_raster_planes output
// channels side by side (a fragment's adds share a cache line or two), in
// 64-bit fixed point as (low, high) word pairs: the sum is high * 4096 +
// low / 2^20 with low a signed word, so that integer atomic adds give the same
// sums in any order and a frame is the same bit for bit on every run (float
// atomics would round in the order the threads came). A value adds its part
// below 2048 in magnitude to low, one atomic add; the high word takes the
// rest and low's overflows, both rare. raster_store.comp.glsl turns the sums
// into the pass's targets afterwards.
layout(std430, binding = BIND_RASTER_SUMS) buffer RasterSums { int raster_sums[]; };
uniform ivec2 u_raster_size;
uniform int u_raster_planes;
void raster_add(int plane, float value)
{
    if (value == 0.0 || isnan(value))
        return;
    ivec2 p = ivec2(FRAG_COORD.xy);
    int i = 2 * ((p.y * u_raster_size.x + p.x) * u_raster_planes + plane);
    int high = 0;
    if (abs(value) >= 2047.0) { // whole units of 4096 go to the high word
        float whole = round(clamp(value, -1e12, 1e12) / 4096.0);
        value -= whole * 4096.0;
        high = int(whole);
    }
    int low = int(clamp(round(value * 1048576.0), -2147483647.0, 2147483647.0));
    int old = atomicAdd(raster_sums[i], low);
    if (low > 0 && old > 2147483647 - low) // low wrapped past its top: 2^32 / 2^20 = 4096 more
        high += 1;
    else if (low < 0 && old < -2147483647 - 1 - low)
        high -= 1;
    if (high != 0)
        atomicAdd(raster_sums[i + 1], high);
}
#else
#define DISCARD discard
in float v_g;
in float v_cscalar;
in vec3 v_rgb;
in float v_alpha;
in float v_zview;
in vec3 v_wpos;
in vec3 v_normal;
in vec2 v_quad;
#endif
// Points: the disc coordinate of the fragment, from the quad's corners or, for
// GL point sprites (POINT_SPRITES), from gl_PointCoord.
#ifdef POINT_SPRITES
#define SPLAT (gl_PointCoord * 2.0 - 1.0)
#else
#define SPLAT v_quad
#endif
#ifndef RASTER_STAGE
flat in uvec3 v_primary;
in vec2 v_halo;
#endif

// One-primitive lines (LINE_PRIMITIVE, geometry.vert.glsl): the wide line
// covers more than the ribbon; a fragment's across coordinate is its distance
// from the segment's centre line over the ribbon's outer half width, and the
// ribbon's across-varying outputs (.x of v_quad and v_halo, which the vertices
// give for the ribbon's +1 side) scale by it. Beyond 1 it is not part of the line.
#ifdef LINE_PRIMITIVE
noperspective in vec2 v_centre_px;
noperspective in float v_outer_px;
float line_across_cached = -1.0;
float line_across()
{
    // Computed once, at outside_primitive's call on entry to main (in
    // uniform control flow, where derivatives are defined).
    if (line_across_cached >= 0.0)
        return line_across_cached;
    // The centre line's point the rasterizer interpolated here lies on the
    // segment, beside the fragment or straight above it (a rasterizer may
    // interpolate lines along their major axis only); its change per pixel
    // gives the segment's direction either way.
    vec2 dx = dFdx(v_centre_px), dy = dFdy(v_centre_px);
    vec2 t = dot(dx, dx) >= dot(dy, dy) ? dx : dy;
    vec2 r = FRAG_COORD.xy - v_centre_px;
    float len2 = dot(t, t);
    float dist = len2 > 0.0 ? abs(t.x * r.y - t.y * r.x) * inversesqrt(len2) : length(r);
    line_across_cached = v_outer_px > 0.0 ? dist / v_outer_px : 2.0;
    return line_across_cached;
}
#define v_quad vec2(v_quad.x * line_across(), v_quad.y)
#define v_halo vec2(v_halo.x * line_across(), v_halo.y)
#endif

// Depth-dependent halos (style.halo*, Everts et al. 2009; docs/ALGORITHM.md
// "Perception aids"): in the compositing passes a line's ribbon is widened by
// a band of u_halo_px pixels whose fragments carry the background colour, the
// line's opacity times u_halo_strength, and a view depth pushed back by
// u_halo_depth at the ribbon's edge, growing linearly to twice that at the
// band's outer edge. The depth order then lets it hide only lines far enough
// behind. The optimization passes never see halos (u_halo_px = 0 there).
#if !defined(RASTER_STAGE) && !defined(u_halo_px)
uniform float u_halo_px; // declared by geometry.vert.glsl in the compute rasterizer
#endif
uniform float u_halo_depth;    // view-space units
uniform float u_halo_strength; // [0, 1]
uniform vec3 u_halo_color;     // the background

// Position across the halo band, 0 at the ribbon's edge to 1 outside; < 0: the line itself.
float halo_position()
{
#if PRIM == PRIM_LINES
    if (u_halo_px > 0.0 && abs(v_halo.x) > v_halo.y)
        return min((abs(v_halo.x) - v_halo.y) / u_halo_px, 1.0);
#endif
    return -1.0;
}

// The fragment's view depth: the halo's pushed back.
float fragment_zview()
{
    float u = halo_position();
    return u < 0.0 ? v_zview : v_zview + u_halo_depth * (1.0 + u);
}

// Opaque context layers (docs/ALGORITHM.md §24): a transparent fragment
// behind the context's depth at this pass's resolution is dropped, as by a
// depth test with writes off, but before any side effect of the shader.
uniform int u_context_depth;
layout(binding = TEX_CONTEXT_DEPTH) uniform sampler2D u_context_depth_tex;

// Round splats: fragments outside the unit disc are not part of the point;
// nothing behind the opaque context is part of the picture.
bool outside_primitive()
{
#ifdef CONTEXT_DEPTH
    // Compiled only into the programs of frames with a context layer: on
    // llvmpipe the test cost every pass about a third more even when its
    // uniform switched it off (docs/EVALUATION.md, "The geometry path").
    if (u_context_depth != 0 && FRAG_COORD.z > texelFetch(u_context_depth_tex, ivec2(FRAG_COORD.xy), 0).r)
        return true;
#endif
#if PRIM == PRIM_POINTS
    return dot(SPLAT, SPLAT) > 1.0;
#elif defined(LINE_PRIMITIVE)
    return line_across() > 1.0;
#else
    return false;
#endif
}

// `lucent bench --floor` (lc_renderer_set_floor): the FLOOR_EMPTY programs
// return right after the coverage test, leaving their outputs unwritten, so
// blending and every fixed stage still run. The return is compiled in:
// llvmpipe runs both sides of a branch on a uniform under masks, so a branch
// taken at run time would still run the whole shader. The linker then drops
// the inputs nothing reads, and the vertex stage writes fewer outputs.
// Production programs compile it to nothing.
#if defined(FLOOR_EMPTY) && defined(HEADS_FETCH)
// (A recording pass writes its chain head on every path: fragment_list.glsl.)
#define FLOOR_RETURN                                                                                                   \
    {                                                                                                                  \
        drop_chain_head();                                                                                             \
        return;                                                                                                        \
    }
#elif defined(FLOOR_EMPTY)
#define FLOOR_RETURN return;
#else
#define FLOOR_RETURN
#endif

uint fragment_element() { return v_primary.x; }

float fragment_importance() { return clamp(v_g, 0.0, 1.0); }

// The weight of a fragment in P0/P1/P4's sums: the subset stride's (every n-th
// primitive counts n times) times a splat's (lc_point_splat: a point stride's
// n where splats keep the still's size, less where they spread; 1 for lines
// and surfaces); the important points that a draw of the point list
// (point_subset.c) adds in full take their splat's weight alone.
float draw_weight(float stride_weight) { return u_point_list != 0 ? u_point_weight.y : stride_weight * u_point_weight.x; }

uniform float u_direct_exponent;
#ifndef u_silhouette_exponent
uniform float u_silhouette_exponent; // eta of OOS Eq. 8 (style.silhouetteExponent); <= 1 off
#endif

#ifdef DIRECT_ALPHA
uniform int u_alpha_source; // params.alphaSource: 0 importance, 1 constant, 2 angle, 3 normal variation
uniform float u_alpha_constant;
uniform float u_gamma;

// |<n, v>| at the fragment, n its unit normal and v the unit vector to the eye:
// surfaces their normal; points the splat's sphere; lines the normal in the
// plane of tangent and view, so |<n, v>| = sqrt(1 - <t, v>^2) (v_quad.y = |<t, v>|).
float view_cosine()
{
#if PRIM == PRIM_POINTS
    return sqrt(max(1.0 - dot(SPLAT, SPLAT), 0.0));
#elif PRIM == PRIM_LINES
    return sqrt(max(1.0 - v_quad.y * v_quad.y, 0.0));
#else
    float len = length(v_normal);
    vec3 to_cam = u_ortho != 0 ? -u_view_dir : normalize(u_eye - v_wpos);
    return len > 0.0 ? abs(dot(v_normal / len, to_cam)) : 1.0;
#endif
}

// The direct baseline's opacity (docs/ALGORITHM.md §12): g^k, a constant, or
// the local transparency of OOS §2.1: angle-based (2/pi) arccos <n, v> (Eq. 1),
// normal variation ((d n_z/du)^2 + (d n_z/dv)^2)^(gamma/2) per pixel (Eq. 2).
float direct_alpha()
{
    if (u_alpha_source == 1)
        return u_alpha_constant;
    if (u_alpha_source == 0)
        return pow(fragment_importance(), u_direct_exponent);
    float c = view_cosine();
#ifdef RASTER_STAGE
    vec2 grad = vec2(0.0); // no derivatives in a compute invocation: normalVariation draws (fourier.c)
#else
    vec2 grad = vec2(dFdx(c), dFdy(c)); // in uniform control flow (u_alpha_source)
#endif
    if (u_alpha_source == 2)
        return (2.0 / PI) * acos(clamp(c, 0.0, 1.0));
    return pow(dot(grad, grad), 0.5 * u_gamma);
}
#endif

#ifdef KANZLER_PENALTY
float kanzler_rho();
#endif

// Opacity of the fragment in the compositing passes: the blended element
// opacity, or the "direct" baseline's (direct_alpha; times Kanzler's penalty
// for the "kanzler" method); clamped so -ln(1 - alpha) stays finite.
float fragment_alpha()
{
#ifdef DIRECT_ALPHA
    float alpha = clamp(direct_alpha(), 0.0, 0.9999);
#ifdef KANZLER_PENALTY
    alpha *= kanzler_rho();
#endif
#else
    float alpha = clamp(v_alpha, 0.0, 0.9999);
#endif
#if PRIM == PRIM_TRIANGLES
    // Silhouettes (OOS Eq. 8) by the smooth measure s = 1 - |n.v|:
    // alpha' = 1 - (1 - alpha)^(1 + (eta - 1) s) (lc_foo_silhouette_alpha).
    if (u_silhouette_exponent > 1.0) {
        float len = length(v_normal);
        vec3 to_cam = u_ortho != 0 ? -u_view_dir : normalize(u_eye - v_wpos);
        float s = len > 0.0 ? 1.0 - abs(dot(v_normal / len, to_cam)) : 0.0;
        alpha = clamp(1.0 - pow(1.0 - alpha, 1.0 + (u_silhouette_exponent - 1.0) * s), 0.0, 0.9999);
    }
#endif
    if (halo_position() >= 0.0)
        alpha = clamp(u_halo_strength * alpha, 0.0, 0.9999);
    return alpha;
}

#ifdef BANDS
// The depth of the Fourier series (series_depth) at the fragment: a halo
// pushed past the pixel's far end stays off the series' periodic seam at 1,
// where it would count as in front of everything.
float fragment_series_depth()
{
    float d = series_depth(fragment_zview());
    return halo_position() >= 0.0 ? min(d, 1.0 - max(u_depth_margin, 0.01)) : d;
}
#endif

#ifdef KANZLER_PENALTY
// Kanzler's occlusion penalty (M3D Eq. 3.2-3.3) from the pixel's maps
// (kanzler_blur.comp.glsl): rho = 1/(1 + (1 - g^lambda) P), P = m M + c C +
// v V + d less(i, D), less = 1 in front of the maximum's depth by more than
// one 16-bit step (D is rounded to half a step: the maximum's own fragment
// never counts as in front of itself). lc_foo_kanzler_rho is the CPU reference.
layout(binding = TEX_KANZLER_MAPS) uniform sampler2D u_kanzler_maps; // (C, M, D, V)
uniform vec4 u_kanzler_weights;                                      // m, c, v, d
uniform float u_kanzler_lambda;

float kanzler_rho()
{
    vec4 s = texelFetch(u_kanzler_maps, ivec2(gl_FragCoord.xy), 0);
    float less = fragment_series_depth() < s.z - 1.0 / 65535.0 ? 1.0 : 0.0;
    float p = dot(u_kanzler_weights, vec4(s.y, s.x, s.w, less));
    float g = fragment_importance();
    float gl = u_kanzler_lambda > 0.0 ? pow(g, u_kanzler_lambda) : 1.0;
    return 1.0 / (1.0 + (1.0 - gl) * p);
}
#endif

// Headlight shading: lines as tubes (normal swings across the ribbon), points
// as spheres, surfaces two-sided. <n, l> with the light at the eye:
float fragment_ndotl()
{
#if PRIM == PRIM_POINTS
    return sqrt(max(1.0 - dot(SPLAT, SPLAT), 0.0));
#elif PRIM == PRIM_LINES
    // The tube's normal at `across` is side * across + v * sqrt(1 - across^2),
    // side (the ribbon's, v_normal) perpendicular to v, the unit vector to the
    // eye, at the ribbon's vertices; so <n, v> = sqrt(1 - across^2), and the
    // lines' programs interpolate neither the position nor the side vector.
    float across = clamp(v_quad.x, -1.0, 1.0);
    return sqrt(max(1.0 - across * across, 0.0));
#else
    vec3 to_cam = u_ortho != 0 ? -u_view_dir : normalize(u_eye - v_wpos);
    vec3 n = v_normal;
    float len = length(n);
    return len > 0.0 ? abs(dot(n / len, to_cam)) : 1.0;
#endif
}

vec3 fragment_color()
{
    if (halo_position() >= 0.0)
        return u_halo_color;
    vec3 base = u_color_mode == 2 ? v_rgb : colormap_lookup(v_cscalar);
    return shade_color(base, fragment_ndotl());
}

