// P0 (depthRange "pixel"): each pixel's nearest and farthest fragment depth,
// as (z, -z) under GL_MIN blending, so one min gives both ends.
layout(location = 0) out vec2 o_range;

void main()
{
    if (outside_primitive())
        discard;
    FLOOR_RETURN
    o_range = vec2(v_zview, -v_zview);
}
