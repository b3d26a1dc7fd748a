// P2 optimal opacity drawn as a geometry pass: each fragment's opacity
// (opacity_common.glsl) from the coefficients P1 summed at its pixel. Frames
// whose P1 recorded its fragments run p2_list.comp.glsl instead.

void main()
{
    if (outside_primitive())
        discard;
    FLOOR_RETURN
    float g = fragment_importance();
    float c[NTARGETS * 4];
    read_coefficients(ivec2(gl_FragCoord.xy), c);
    fragment_opacity(fragment_element(), g, series_depth(v_zview), c);
}
