// Shared declarations of every Lucent shader: scene buffers (vertex pulling),
// per-frame uniforms, importance/colour mapping and the Fourier series.
// The renderer prepends "#version 450" and the #defines (PRIM, BANDS, ...).

#define PRIM_POINTS 0
#define PRIM_LINES 1
#define PRIM_TRIANGLES 2
#define PI 3.14159265358979

layout(std430, binding = BIND_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = BIND_FRAMES) readonly buffer Frames { vec4 frames[]; };       // line tangent or surface normal
layout(std430, binding = BIND_ATTRIBUTES) readonly buffer Attributes { float attributes[]; }; // attribute a of vertex v at a*n+v
layout(std430, binding = BIND_COLORS) readonly buffer Colors { float colors[]; };       // rgb, 3 per vertex
layout(std430, binding = BIND_VERTEX_ELEMENTS) readonly buffer VertexElements { uvec4 vertex_elements[]; }; // e0,e1,e2,primary
layout(std430, binding = BIND_VERTEX_WEIGHTS) readonly buffer VertexWeights { vec4 vertex_weights[]; };
layout(std430, binding = BIND_INDICES) readonly buffer Indices { uint indices[]; }; // 2 per segment / 3 per triangle

uniform mat4 u_view;
uniform mat4 u_view_proj;
uniform vec3 u_eye;
uniform vec3 u_view_dir;
uniform int u_ortho;
uniform vec2 u_viewport;         // this pass's resolution in pixels
uniform float u_pixel_world;     // world size of one pixel at the focal distance, this pass
uniform float u_focal_dist;
uniform float u_line_half_width; // world units
uniform float u_min_half_pixels; // ribbons never thinner than 2x this many pixels
uniform float u_point_radius_px; // splat radius in pixels at this pass's resolution
uniform uint u_vertex_count;
uniform uint u_subset;           // every n-th primitive (P1/P4 subset option)
uniform int u_importance_attr;   // -1: g = 1
uniform vec2 u_importance_range;
uniform float u_importance_exp;
uniform int u_color_mode;        // 0: attribute through colormap, 1: importance through colormap, 2: rgb
uniform int u_color_attr;
uniform vec2 u_color_range;
layout(binding = TEX_COLORMAP) uniform sampler2D u_colormap; // 256x1 RGBA8
uniform int u_shading;           // 0 phong, 1 none
uniform vec2 u_depth_range;      // view-space [z_min, z_max] of the bounds this frame
uniform float u_depth_margin;    // delta of docs/ALGORITHM.md
uniform int u_pixel_depth_range; // 1: normalize by this pixel's own fragment range (P0)
layout(binding = TEX_PIXEL_RANGE) uniform sampler2D u_pixel_range; // (z_min, -z_max) per pixel of this pass

float attribute_value(int a, uint v) { return attributes[uint(a) * u_vertex_count + v]; }

float vertex_importance(uint v)
{
    if (u_importance_attr < 0)
        return 1.0;
    float span = u_importance_range.y - u_importance_range.x;
    float t = span != 0.0 ? (attribute_value(u_importance_attr, v) - u_importance_range.x) / span : 1.0;
    return pow(clamp(t, 0.0, 1.0), u_importance_exp);
}

// Scalar that the fragment shader maps through the colormap (or unused for rgb).
float vertex_color_scalar(uint v, float g)
{
    float value = u_color_mode == 1 ? g : (u_color_attr >= 0 ? attribute_value(u_color_attr, v) : g);
    float span = u_color_range.y - u_color_range.x;
    return span != 0.0 ? (value - u_color_range.x) / span : 0.5;
}

vec3 vertex_rgb(uint v) { return vec3(colors[3u * v], colors[3u * v + 1u], colors[3u * v + 2u]); }

vec3 colormap_lookup(float t) { return texture(u_colormap, vec2(clamp(t, 0.0, 1.0) * (255.0 / 256.0) + 0.5 / 256.0, 0.5)).rgb; }

// Normalized depth d in [0,1] (docs/ALGORITHM.md): the series is periodic, so the margin
// keeps fragments away from d = 0 and d = 1.
float normalized_depth(float z_view)
{
    vec2 range = u_depth_range;
#ifdef FRAGMENT_STAGE
    if (u_pixel_depth_range != 0) {
        vec2 r = texelFetch(u_pixel_range, ivec2(gl_FragCoord.xy), 0).xy;
        // A pixel the range pass missed (sub-pixel geometry) keeps the global range.
        if (r.x <= -r.y)
            range = vec2(r.x, -r.y);
    }
#endif
    float t = (z_view - range.x) / max(range.y - range.x, 1e-20 + 1e-6 * abs(range.y));
    return clamp(u_depth_margin + (1.0 - 2.0 * u_depth_margin) * t, 0.0, 1.0);
}

#ifdef BANDS
// Coefficients c[0] = A0, c[2k-1] = A_k, c[2k] = B_k, packed four per RGBA32F target.
#define NCOEF (2 * BANDS + 1)
#define NTARGETS ((NCOEF + 3) / 4)

// Projects value f at depth d: c[j] = f cos / f sin of 2 pi k d (FOO Eq. 11).
void fourier_project(float d, float f, out float c[NTARGETS * 4])
{
    for (int j = 0; j < NTARGETS * 4; j++)
        c[j] = 0.0;
    c[0] = f;
    float c1 = cos(2.0 * PI * d), s1 = sin(2.0 * PI * d);
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
    float c1 = cos(2.0 * PI * d), s1 = sin(2.0 * PI * d);
    float ck = c1, sk = s1;
    for (int k = 1; k <= BANDS; k++) {
        sum += (c[2 * k - 1] * sk + c[2 * k] * (1.0 - ck)) / (PI * float(k));
        float cn = ck * c1 - sk * s1;
        sk = sk * c1 + ck * s1;
        ck = cn;
    }
    return sum;
}
#endif
