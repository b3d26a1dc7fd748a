// Counts each pixel's P1 zeroth coefficient (its total sum of g^2 at the
// optimization resolution) into the mass histogram, or P0's effective
// fragment count for params.autoSubset.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = TEX_COEF_FIRST) uniform sampler2D u_coef0;
uniform ivec2 u_size;
uniform int u_effective; // 1: count (sum g^2)^2 / sum g^4 of P0's moments (r, a) instead of r

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    vec4 m = texelFetch(u_coef0, p, 0);
    mass_count(u_effective != 0 ? (m.a > 0.0 ? m.r * m.r / m.a : 0.0) : m.r);
}
