// Fragment-side helpers shared by all geometry passes: splat discard, the
// fragment's element (primary of the nearest vertex) and lit colour.

in float v_g;
in float v_cscalar;
in vec3 v_rgb;
in float v_alpha;
in float v_zview;
in vec3 v_wpos;
in vec3 v_normal;
in vec2 v_quad;
flat in uvec3 v_primary;

// Round splats: fragments outside the unit disc are not part of the point.
bool outside_primitive()
{
#if PRIM == PRIM_POINTS
    return dot(v_quad, v_quad) > 1.0;
#else
    return false;
#endif
}

uint fragment_element() { return v_primary.x; }

float fragment_importance() { return clamp(v_g, 0.0, 1.0); }

// The weight of a fragment in P1/P4's sums: the subset stride's (every n-th
// primitive counts n times), but once for the important points that a draw of
// the point list (point_subset.c) adds in full.
float draw_weight(float stride_weight) { return u_point_list != 0 ? 1.0 : stride_weight; }

uniform float u_direct_exponent;

// Opacity of the fragment in the compositing passes: the blended element
// opacity, or g^k for the "direct" baseline; clamped so -ln(1 - alpha) stays finite.
float fragment_alpha()
{
#ifdef DIRECT_ALPHA
    return clamp(pow(fragment_importance(), u_direct_exponent), 0.0, 0.9999);
#else
    return clamp(v_alpha, 0.0, 0.9999);
#endif
}

// Headlight shading: lines as tubes (normal swings across the ribbon), points
// as spheres, surfaces two-sided.
vec3 fragment_color()
{
    vec3 base = u_color_mode == 2 ? v_rgb : colormap_lookup(v_cscalar);
    if (u_shading != 0)
        return base;
    vec3 to_cam = u_ortho != 0 ? -u_view_dir : normalize(u_eye - v_wpos);
    float ndotl;
#if PRIM == PRIM_POINTS
    ndotl = sqrt(max(1.0 - dot(v_quad, v_quad), 0.0));
#elif PRIM == PRIM_LINES
    float across = clamp(v_quad.x, -1.0, 1.0);
    vec3 n = normalize(v_normal * across + to_cam * sqrt(max(1.0 - across * across, 0.0)));
    ndotl = max(dot(n, to_cam), 0.0);
#else
    vec3 n = v_normal;
    float len = length(n);
    ndotl = len > 0.0 ? abs(dot(n / len, to_cam)) : 1.0;
#endif
    // ndotl^40 by squaring (x^8 * x^32): pow's exp2/log2 cost more per fragment.
    float x2 = ndotl * ndotl, x4 = x2 * x2, x8 = x4 * x4, x16 = x8 * x8;
    float spec = x8 * x16 * x16;
    return clamp(base * (0.3 + 0.7 * ndotl) + vec3(0.25 * spec), 0.0, 1.0);
}
