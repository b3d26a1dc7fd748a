// Opaque baseline: depth-tested lit geometry.
out vec4 o_color;

void main()
{
    if (outside_primitive())
        discard;
    FLOOR_RETURN
    o_color = vec4(fragment_color(), 1.0);
}
