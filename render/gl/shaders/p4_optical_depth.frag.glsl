// P4 optical-depth projection: f = -ln(1 - alpha) of the fragment's blended
// element opacity (or alpha = g^k for the "direct" baseline), full resolution;
// TAU_BINS: into depth bins instead of a Fourier series (method "binning").
// COMPOSITE_LIST: records what P4's and P5's sums need of the fragment instead
// (fragment_list.glsl); compute passes over the list make both.

uniform float u_weight; // subset stride
#ifdef SHADOW_MAP
// shadow.c's light pass: also the colour weighted by optical depth, (sum f C, sum f).
layout(location = NTARGETS) out vec4 o_shadow_color;
#endif

#ifdef KANZLER_PENALTY
// Method "kanzler"'s visibility report (docs/ALGORITHM.md §28): each element's
// least opacity over its fragments, and as the importance a fragment hides the
// pixel's maximum M where it lies in front of M's depth (occluders.glsl).
layout(std430, binding = BIND_ELEMENT_ALPHA_MIN) buffer ElementAlphaMin { uint element_alpha_min[]; };

void kanzler_report(float alpha)
{
    if (halo_position() >= 0.0)
        return;
    uint e = fragment_element();
    atomicMin(element_alpha_min[e], floatBitsToUint(alpha));
    vec4 s = texelFetch(u_kanzler_maps, ivec2(gl_FragCoord.xy), 0);
    add_behind(e, fragment_series_depth() < s.z - 1.0 / 65535.0 ? s.y : 0.0);
}
#endif

void main()
{
    if (outside_primitive())
        DISCARD;
    FLOOR_RETURN
#ifdef COMPOSITE_LIST
    // The sums come from the list (p4_list.comp.glsl): nothing is blended.
    record_composite_fragment(fragment_alpha(), fragment_importance(), normalized_depth(fragment_zview()),
                              halo_position() >= 0.0, fragment_color_word());
    return;
#endif
    float c[NTARGETS * 4];
    float f = -log(1.0 - fragment_alpha()) * draw_weight(u_weight);
#ifdef TAU_BINS
    bins_project(fragment_series_depth(), f, c);
#else
    fourier_project(fragment_series_depth(), f, c);
#endif
    write_coefficients(c);
#ifdef KANZLER_PENALTY
    kanzler_report(fragment_alpha());
#endif
#ifdef SHADOW_MAP
    o_shadow_color = vec4(f * fragment_color(), f);
#endif
}
