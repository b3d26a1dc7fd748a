// Reads the Fourier coefficients that an earlier pass accumulated at this pixel.
layout(binding = TEX_COEF_FIRST) uniform sampler2D u_coef_tex0;
layout(binding = TEX_COEF_FIRST + 1) uniform sampler2D u_coef_tex1;
layout(binding = TEX_COEF_FIRST + 2) uniform sampler2D u_coef_tex2;
layout(binding = TEX_COEF_FIRST + 3) uniform sampler2D u_coef_tex3;
layout(binding = TEX_COEF_FIRST + 4) uniform sampler2D u_coef_tex4;

void read_coefficients(ivec2 p, out float c[NTARGETS * 4])
{
    vec4 t[5];
    t[0] = texelFetch(u_coef_tex0, p, 0);
    t[1] = NTARGETS > 1 ? texelFetch(u_coef_tex1, p, 0) : vec4(0.0);
    t[2] = NTARGETS > 2 ? texelFetch(u_coef_tex2, p, 0) : vec4(0.0);
    t[3] = NTARGETS > 3 ? texelFetch(u_coef_tex3, p, 0) : vec4(0.0);
    t[4] = NTARGETS > 4 ? texelFetch(u_coef_tex4, p, 0) : vec4(0.0);
    for (int j = 0; j < NTARGETS * 4; j++)
        c[j] = t[j / 4][j % 4];
}
