// P2 over P1's fragment list (fragment_list.glsl): one invocation a recorded
// fragment, the same opacity as the fragment shader's (opacity_common.glsl)
// without a second traversal of the geometry. The clarity loop's tries run it
// again on the same list.
layout(local_size_x = 256) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 256u + gl_GlobalInvocationID.x; }

uniform uint u_fragments;

void main()
{
    uint i = linear_invocation();
    if (i >= u_fragments)
        return;
    uvec4 f = fragments[i];
    float c[NTARGETS * 4];
    read_coefficients(ivec2(f.x & 0xffffu, f.x >> 16), c);
    fragment_opacity(f.y, uintBitsToFloat(f.z), uintBitsToFloat(f.w), c);
}
