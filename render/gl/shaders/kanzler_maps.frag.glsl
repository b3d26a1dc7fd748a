// Method "kanzler", the view-dependent per-pixel maps (M3D §3.2): every
// fragment counts once in the coverage C and adds its unit line tangent
// (world space: |sum| is the view space's, rotation keeps lengths) for the
// directional variance; the maximum importance and its depth go into one
// imageAtomicMax of packUnorm2x16(d, g), g in the high bits, so the maximum
// of g decides and carries its depth along. kanzler_blur.comp.glsl finishes them.

layout(binding = IMG_KANZLER_MAX, r32ui) uniform coherent uimage2D u_kanzler_max;
#if PRIM == PRIM_LINES
in vec3 v_tangent;
#endif

layout(location = 0) out vec4 o_sums;

void main()
{
    if (outside_primitive())
        discard;
    FLOOR_RETURN
    float d = fragment_series_depth();
    imageAtomicMax(u_kanzler_max, ivec2(gl_FragCoord.xy), packUnorm2x16(vec2(d, fragment_importance())));
    vec3 t = vec3(0.0);
#if PRIM == PRIM_LINES
    float len = length(v_tangent);
    if (len > 0.0)
        t = v_tangent / len;
#endif
    o_sums = vec4(t, 1.0);
}
