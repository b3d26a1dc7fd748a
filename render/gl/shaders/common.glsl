// Shared declarations of every Lucent shader: scene buffers (vertex pulling),
// per-frame uniforms, importance/colour mapping and the Fourier series.
// The renderer prepends "#version 450" and the #defines (PRIM, BANDS, ...).

#define PRIM_POINTS 0
#define PRIM_LINES 1
#define PRIM_TRIANGLES 2
#define STRIP_RESTART 0xFFFFFFFFu // LC_STRIP_RESTART (renderer_internal.h): between line ribbon strips
#define PI 3.14159265358979

// The window position of the fragment being shaded: gl_FragCoord, or in the
// compute rasterizer (RASTER_STAGE, raster.comp.glsl) the pixel centre it is
// shading, with z the window depth and w 1/w_clip as gl_FragCoord's.
#ifdef RASTER_STAGE
vec4 raster_frag_coord;
#define FRAG_COORD raster_frag_coord
// and what the vertex stage reads and writes, as globals (geometry.vert.glsl)
vec4 raster_position;
int raster_vertex_id, raster_instance_id;
#else
#define FRAG_COORD gl_FragCoord
#endif

// Scene buffers as 32-bit words, in one of two layouts (docs/MEMORY.md):
// exact (u_compact = 0) holds the floats as uploaded before the compact layout,
// compact packs them (render/gl/vertex_pack.c encodes, the functions below decode).
layout(std430, binding = BIND_POSITIONS) readonly buffer Positions { uint position_words[]; }; // exact: xyz1 floats; compact: 3 x unorm16 per vertex
layout(std430, binding = BIND_POSITION_CHUNKS) readonly buffer PositionChunks { vec4 position_chunks[]; }; // compact: min, scale per chunk
layout(std430, binding = BIND_FRAMES) readonly buffer Frames { uint frame_words[]; }; // line tangent or surface normal: exact xyz0 floats; compact octahedral snorm16 x 2
layout(std430, binding = BIND_ATTRIBUTES) readonly buffer Attributes { uint attribute_words[]; }; // attribute a from word u_attr_offset[a]
layout(std430, binding = BIND_COLORS) readonly buffer Colors { uint color_words[]; }; // exact: rgb floats; compact: RGBA8
layout(std430, binding = BIND_VERTEX_ELEMENTS) readonly buffer VertexElements { uint vertex_elements[]; }; // per u_blend
layout(std430, binding = BIND_VERTEX_WEIGHTS) readonly buffer VertexWeights { float vertex_weights[]; }; // u_blend 0: 4 per vertex
layout(std430, binding = BIND_INDICES) readonly buffer Indices { uint indices[]; }; // line ribbon strips / 3 per triangle

#ifndef u_compact
uniform int u_compact;           // 0 exact float buffers, 1 compact
#endif
uniform uint u_element_offset;   // layers: the first element id of this draw's layer (0 for one dataset)
#ifndef u_blend
uniform int u_blend;             // 0 full (e0,e1,e2,primary + 4 weights), 1 implicit (points), 2 pair (lines), 3 triple (surfaces)
#endif
uniform uint u_attr_offset[MAX_ATTRIBUTES];
uniform int u_attr_format[MAX_ATTRIBUTES];  // 0 float, 1 unorm16
uniform vec2 u_attr_decode[MAX_ATTRIBUTES]; // unorm16: value = x + y * code

#define POSITION_CHUNK_SHIFT 10u
uint packed_u16(uint h, uint w) { return (w >> ((h & 1u) * 16u)) & 0xffffu; }

vec3 vertex_position(uint v)
{
    if (u_compact == 0)
        return vec3(uintBitsToFloat(position_words[4u * v]), uintBitsToFloat(position_words[4u * v + 1u]),
                    uintBitsToFloat(position_words[4u * v + 2u]));
    uint h = 3u * v;
    vec3 q = vec3(packed_u16(h, position_words[h >> 1]), packed_u16(h + 1u, position_words[(h + 1u) >> 1]),
                  packed_u16(h + 2u, position_words[(h + 2u) >> 1]));
    // A shard's chunks keep the whole scene's boundaries: the phase of its
    // first vertex rides in the first chunk's w (vertex_pack.h).
    uint c = (v + floatBitsToUint(position_chunks[0].w)) >> POSITION_CHUNK_SHIFT;
    return position_chunks[2u * c].xyz + position_chunks[2u * c + 1u].xyz * q;
}

// Unit tangent or normal (zero for degenerate surface vertices).
vec3 vertex_frame(uint v)
{
    if (u_compact == 0)
        return vec3(uintBitsToFloat(frame_words[4u * v]), uintBitsToFloat(frame_words[4u * v + 1u]),
                    uintBitsToFloat(frame_words[4u * v + 2u]));
    uint w = frame_words[v];
    if (w == 0x80008000u)
        return vec3(0.0);
    vec2 f = unpackSnorm2x16(w);
    vec3 n = vec3(f, 1.0 - abs(f.x) - abs(f.y));
    float t = max(-n.z, 0.0);
    n.xy += vec2(n.x >= 0.0 ? -t : t, n.y >= 0.0 ? -t : t);
    return normalize(n);
}

uniform mat4 u_view;
uniform mat4 u_view_proj;
uniform vec3 u_eye;
uniform vec3 u_view_dir;
#ifndef u_ortho
uniform int u_ortho;
#endif
uniform vec2 u_viewport;         // this pass's resolution in pixels
uniform float u_pixel_world;     // world size of one pixel at the focal distance, this pass
uniform float u_focal_dist;
uniform float u_line_half_width; // world units
uniform float u_min_half_pixels; // ribbons never thinner than 2x this many pixels
uniform float u_point_radius_px; // splat radius in pixels at this pass's resolution (lc_point_splat)
uniform float u_point_list_radius_px; // the same for the point list's entries (drawn in full)
uniform vec2 u_point_weight;     // weight of a splat's fragments in P0, P1 and P4: strided, listed
uniform uint u_vertex_count;
uniform uint u_subset;           // every n-th primitive (P1/P4 subset option)
uniform uint u_point_jitter;     // points under a moving frame's stride: each instance takes one point of its
                                 // block of u_subset at random (lc_renderer_bind_geometry); 1: the block's first
uniform uint u_first_primitive;  // points: first instance of this draw (large draws are batched)
uniform int u_keep_bin;          // points drawn with a stride: those in this importance bin or above are
                                 // drawn from the point list instead (POINT_BINS bins; > POINT_BINS: none)
uniform int u_point_list;        // 1: this draw's instances are the point list's entries
uniform int u_importance_attr;   // -1: g = 1
uniform vec2 u_importance_range;
uniform float u_importance_exp;
#ifndef u_color_mode
uniform int u_color_mode;        // 0: attribute through colormap, 1: importance through colormap, 2: rgb
#endif
uniform int u_color_attr;
uniform vec2 u_color_range;
layout(binding = TEX_COLORMAP) uniform sampler2D u_colormap; // 256x1 RGBA8
#ifndef u_shading
uniform int u_shading;           // 0 phong, 1 none
#endif
uniform vec2 u_depth_range;      // view-space [z_min, z_max] of the bounds this frame
uniform float u_depth_margin;    // delta of docs/ALGORITHM.md
#ifndef u_pixel_depth_range
uniform int u_pixel_depth_range; // 1: normalize by this pixel's own fragment range (P0)
#endif
layout(binding = TEX_PIXEL_RANGE) uniform sampler2D u_pixel_range; // (z_min, -z_max) per pixel of this pass

float attribute_value(int a, uint v)
{
    uint off = u_attr_offset[a];
    if (u_attr_format[a] == 0)
        return uintBitsToFloat(attribute_words[off + v]);
    return u_attr_decode[a].x + u_attr_decode[a].y * float(packed_u16(v, attribute_words[off + (v >> 1)]));
}

// Weighted importance terms (docs/ALGORITHM.md "Importance terms"); u_importance_terms = 0: the single form.
#ifndef u_importance_terms
uniform int u_importance_terms;
#endif
uniform int u_term_attr[MAX_IMPORTANCE_TERMS];
uniform vec2 u_term_range[MAX_IMPORTANCE_TERMS];
uniform float u_term_weight[MAX_IMPORTANCE_TERMS]; // in [-1, 1]
uniform int u_term_invert[MAX_IMPORTANCE_TERMS];
uniform float u_term_norm;                         // 1 / sum |w|
uniform int u_term_penalty;                        // sum w < 0: g = 1 + s

float mapped_attribute(int a, vec2 range, uint v)
{
    float span = range.y - range.x;
    return span != 0.0 ? (attribute_value(a, v) - range.x) / span : 1.0;
}

// Transfer functions (importance.curve, color.curve): piecewise linear through
// u_curve_n.x points u_curve[i].xy (importance) and u_curve_n.y points .zw (colour);
// no points: identity. Exact at the points, so [[0,0],[1,1]] is the identity bit for bit.
#ifndef u_curve_n
uniform ivec2 u_curve_n;
#endif
uniform vec4 u_curve[MAX_CURVE_POINTS];

float curve_eval(int c, float t)
{
    int n = c == 0 ? u_curve_n.x : u_curve_n.y;
    vec2 a = c == 0 ? u_curve[0].xy : u_curve[0].zw;
    if (t <= a.x)
        return a.y;
    for (int i = 1; i < n; i++) {
        vec2 b = c == 0 ? u_curve[i].xy : u_curve[i].zw;
        if (t <= b.x)
            return b.x > a.x ? a.y + (t - a.x) / (b.x - a.x) * (b.y - a.y) : b.y;
        a = b;
    }
    return a.y;
}

float vertex_importance(uint v)
{
    if (u_importance_attr < 0)
        return 1.0;
    float t = mapped_attribute(u_importance_attr, u_importance_range, v);
    if (u_importance_terms > 0) {
        float s = 0.0;
        for (int i = 0; i < u_importance_terms; i++) {
            float ti = clamp(mapped_attribute(u_term_attr[i], u_term_range[i], v), 0.0, 1.0);
            s += u_term_weight[i] * (u_term_invert[i] != 0 ? 1.0 - ti : ti);
        }
        s *= u_term_norm;
        t = u_term_penalty != 0 ? 1.0 + s : s;
    }
    t = clamp(t, 0.0, 1.0);
    if (u_curve_n.x > 0)
        t = curve_eval(0, t);
    return pow(t, u_importance_exp);
}

// Per-vertex visibility of the request's filters (filter.c): a hidden vertex draws nothing and counts in no sum.
layout(std430, binding = BIND_VISIBLE) readonly buffer Visible { uint visible_bits[]; };
#ifndef u_filtered
uniform int u_filtered; // 0: no filter, every vertex is visible
#endif
bool vertex_visible(uint v) { return u_filtered == 0 || (visible_bits[v >> 5] & (1u << (v & 31u))) != 0u; }

// Importance bin of g for the point subsets (point_subset.c).
int point_bin(float g) { return min(int(g * float(POINT_BINS)), POINT_BINS - 1); }

// Scalar that the fragment shader maps through the colormap (or unused for rgb).
float vertex_color_scalar(uint v, float g)
{
    float value = u_color_mode == 1 ? g : (u_color_attr >= 0 ? attribute_value(u_color_attr, v) : g);
    float span = u_color_range.y - u_color_range.x;
    float t = span != 0.0 ? (value - u_color_range.x) / span : 0.5;
    return u_curve_n.y > 0 ? curve_eval(1, clamp(t, 0.0, 1.0)) : t;
}

vec3 vertex_rgb(uint v)
{
    if (u_compact != 0)
        return unpackUnorm4x8(color_words[v]).rgb;
    return vec3(uintBitsToFloat(color_words[3u * v]), uintBitsToFloat(color_words[3u * v + 1u]),
                uintBitsToFloat(color_words[3u * v + 2u]));
}

// The element that receives the fragments of primitives this vertex provokes.
uint vertex_primary(uint v)
{
    if (u_blend == 1)
        return u_element_offset + v;
    if (u_blend == 2)
        return u_element_offset + vertex_elements[2u * v] + (vertex_elements[2u * v + 1u] >> 16);
    return u_element_offset + vertex_elements[4u * v + (u_blend == 0 ? 3u : 0u)];
}

// (One level, linear both ways: the explicit level is what an implicit one
// would choose, without the derivatives; compute passes have none.)
vec3 colormap_lookup(float t)
{
    return textureLod(u_colormap, vec2(clamp(t, 0.0, 1.0) * (255.0 / 256.0) + 0.5 / 256.0, 0.5), 0.0).rgb;
}

// Headlight shading of a base colour at <n, l> = ndotl (style.shading "none":
// the base): fragment_color, and P5 over P4's list (fragment_list.glsl).
vec3 shade_color(vec3 base, float ndotl)
{
    if (u_shading != 0)
        return base;
    // ndotl^40 by squaring (x^8 * x^32): pow's exp2/log2 cost more per fragment.
    float x2 = ndotl * ndotl, x4 = x2 * x2, x8 = x4 * x4, x16 = x8 * x8;
    float spec = x8 * x16 * x16;
    return clamp(base * (0.3 + 0.7 * ndotl) + vec3(0.25 * spec), 0.0, 1.0);
}

// Normalized depth d in [0,1] (docs/ALGORITHM.md): the series is periodic, so the margin
// keeps fragments away from d = 0 and d = 1.
float normalized_depth(float z_view)
{
    vec2 range = u_depth_range;
#ifdef FRAGMENT_STAGE
    if (u_pixel_depth_range != 0) {
        vec2 r = texelFetch(u_pixel_range, ivec2(FRAG_COORD.xy), 0).xy;
        // A pixel the range pass missed (sub-pixel geometry) keeps the global range.
        if (r.x <= -r.y)
            range = vec2(r.x, -r.y);
    }
#endif
    float t = (z_view - range.x) / max(range.y - range.x, 1e-20 + 1e-6 * abs(range.y));
    return clamp(u_depth_margin + (1.0 - 2.0 * u_depth_margin) * t, 0.0, 1.0);
}

#if defined(FRAGMENT_STAGE) || defined(SERIES_DEPTH_AT)
#ifndef u_depth_moments
uniform int u_depth_moments;   // 1: P0 "moments" ran, warp the series' depth
#endif
uniform vec2 u_moments_scale;  // moments texels per pixel of this pass
uniform vec2 u_moments_offset; // params.guardBand: texels of the moments beyond the view (0 in P0-P2)
uniform vec2 u_pixel_origin;   // tiled stills: the frame's pixel at this target's (0, 0); else 0
layout(binding = TEX_DEPTH_MOMENTS) uniform sampler2D u_moments; // sum g^2 (1, u, u^2), u = d - 1/2

// The depth the Fourier series of P1, P2, P4 and P5 use: the normalized
// depth d of the fragment at window position frag_xy (gl_FragCoord.xy),
// warped per pixel around its importance mass when P0 "moments" ran
// (lc_foo_moment_depth in foo_math.h is the CPU reference). P1 over P0's
// fragments (p1_list.comp.glsl) and the walks over P4's fragments read the
// pixel's moments and make its warp once (series_warp_of) and warp each
// fragment's recorded d by it (series_depth_warped).
vec4 series_moments_at(vec2 frag_xy)
{
    if (u_depth_moments == 0)
        return vec4(0.0);
    return texelFetch(u_moments, ivec2((frag_xy + u_pixel_origin) * u_moments_scale + u_moments_offset), 0);
}

// A pixel's warp from its moments m: (mu, s, 1), or 0 where the pixel has no
// importance mass (no warp).
vec3 series_warp_of(vec4 m)
{
    if (!(m.x > 0.0))
        return vec3(0.0);
    float mu = m.y / m.x;
    return vec3(mu, max(sqrt(max(m.z / m.x - mu * mu, 0.0)), MOMENT_MIN_SPREAD), 1.0);
}

float series_depth_warped(vec3 w, float d)
{
    if (w.z == 0.0)
        return d;
    float t = 1.0 / (1.0 + exp(-((d - 0.5) - w.x) / w.y));
    return u_depth_margin + (1.0 - 2.0 * u_depth_margin) * t;
}

float series_depth_at(vec2 frag_xy, float d) { return series_depth_warped(series_warp_of(series_moments_at(frag_xy)), d); }
#endif

// P5's weight of a fragment with opacity alpha behind optical depth tau (FOO
// Eq. 17: alpha/(1-alpha) exp(-tau); midpoint, estimator 1: alpha exp(-max(tau
// - f/2, 0)) with f = -ln(1 - alpha)). The colour histogram measures shares of
// it; P5 over P4's fragments (p5_list.comp.glsl) computes it too.
float composite_weight(float alpha, float tau, int estimator)
{
    if (estimator == 1)
        return alpha * exp(-max(tau + 0.5 * log(1.0 - alpha), 0.0));
    return alpha / (1.0 - alpha) * exp(-tau);
}

#ifdef FRAGMENT_STAGE
float series_depth(float z_view) { return series_depth_at(FRAG_COORD.xy, normalized_depth(z_view)); }
#endif

#ifdef BANDS
// Coefficients c[0] = A0, c[2k-1] = A_k, c[2k] = B_k, packed four per RGBA32F target.
#define NCOEF (2 * BANDS + 1)
#define NTARGETS ((NCOEF + 3) / 4)

// (cos, sin) of 2 pi d for d in [0, 1]. On llvmpipe (SOFTWARE_GL) sin() and
// cos() each reduce the angle and evaluate two polynomials, per fragment of
// P4 and P5; here one reduction to the nearest quarter turn serves both, and
// the remainder |x| <= pi/4 takes Cephes' single-precision polynomials (the
// ones llvmpipe's own sin and cos evaluate; errors about 1e-7). GPUs have
// both as instructions.
vec2 turn_cos_sin(float d)
{
#ifdef SOFTWARE_GL
    float q = round(4.0 * d);
    float x = (2.0 * PI) * (d - 0.25 * q), x2 = x * x;
    float s = x + x * x2 * (-1.6666654611e-1 + x2 * (8.3321608736e-3 + x2 * -1.9515295891e-4));
    float c = 1.0 - 0.5 * x2 + x2 * x2 * (4.166664568298827e-2 + x2 * (-1.388731625493765e-3 + x2 * 2.443315711809948e-5));
    int k = int(q) & 3; // 2 pi d = x + k quarter turns
    vec2 r = (k & 1) != 0 ? vec2(-s, c) : vec2(c, s);
    return (k & 2) != 0 ? -r : r;
#else
    return vec2(cos(2.0 * PI * d), sin(2.0 * PI * d));
#endif
}

// Projects value f at depth d: c[j] = f cos / f sin of 2 pi k d (FOO Eq. 11).
void fourier_project(float d, float f, out float c[NTARGETS * 4])
{
    for (int j = 0; j < NTARGETS * 4; j++)
        c[j] = 0.0;
    c[0] = f;
    vec2 cs = turn_cos_sin(d);
    float c1 = cs.x, s1 = cs.y;
    float ck = c1, sk = s1; // cos/sin(2 pi k d) by angle addition
    for (int k = 1; k <= BANDS; k++) {
        c[2 * k - 1] = f * ck;
        c[2 * k] = f * sk;
        float cn = ck * c1 - sk * s1;
        sk = sk * c1 + ck * s1;
        ck = cn;
    }
}

// Running sum F(d) = A0 d + sum_k [A_k sin(2 pi k d) + B_k (1 - cos(2 pi k d))] / (pi k).
float fourier_eval(float c[NTARGETS * 4], float d)
{
    float sum = c[0] * d;
    vec2 cs = turn_cos_sin(d);
    float c1 = cs.x, s1 = cs.y;
    float ck = c1, sk = s1;
    for (int k = 1; k <= BANDS; k++) {
        sum += (c[2 * k - 1] * sk + c[2 * k] * (1.0 - ck)) / (PI * float(k));
        float cn = ck * c1 - sk * s1;
        sk = sk * c1 + ck * s1;
        ck = cn;
    }
    return sum;
}

// The binning baseline (method "binning", FOO §5.3) in the same three targets
// as 5 bands: c[0] = the pixel's total optical depth (P6 reads it as A0),
// c[1 + k] = the optical depth of the fragments in depth bin k of TAU_BINS.
#ifdef TAU_BINS
void bins_project(float d, float f, out float c[NTARGETS * 4])
{
    for (int j = 0; j < NTARGETS * 4; j++)
        c[j] = 0.0;
    c[0] = f;
    c[1 + min(int(d * float(TAU_BINS)), TAU_BINS - 1)] = f;
}

// tau(d): the bins before d's in full, d's own bin linearly in d (the running
// sum interpolated linearly between the bins' boundaries).
float bins_eval(float c[NTARGETS * 4], float d)
{
    float x = clamp(d, 0.0, 1.0) * float(TAU_BINS);
    int k = min(int(x), TAU_BINS - 1);
    float sum = 0.0;
    for (int j = 0; j < k; j++)
        sum += c[1 + j];
    return sum + (x - float(k)) * c[1 + k];
}
#endif
#endif
