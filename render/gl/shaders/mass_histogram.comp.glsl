// Counts each pixel's P1 zeroth coefficient (its total sum of g^2 at the
// optimization resolution) into the mass histogram.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = TEX_COEF_FIRST) uniform sampler2D u_coef0;
uniform ivec2 u_size;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    mass_count(texelFetch(u_coef0, p, 0).r);
}
