// Reads the Fourier coefficients that an earlier pass accumulated at this pixel
// (image loads: see lc_bind_coefficients).
layout(binding = IMG_COEF_FIRST, rgba32f) readonly uniform image2D u_coef0;
layout(binding = IMG_COEF_FIRST + 1, rgba32f) readonly uniform image2D u_coef1;
layout(binding = IMG_COEF_FIRST + 2, rgba32f) readonly uniform image2D u_coef2;
layout(binding = IMG_COEF_FIRST + 3, rgba32f) readonly uniform image2D u_coef3;
layout(binding = IMG_COEF_FIRST + 4, rgba32f) readonly uniform image2D u_coef4;

void read_coefficients(ivec2 p, out float c[NTARGETS * 4])
{
    vec4 t[5];
    t[0] = imageLoad(u_coef0, p);
    t[1] = NTARGETS > 1 ? imageLoad(u_coef1, p) : vec4(0.0);
    t[2] = NTARGETS > 2 ? imageLoad(u_coef2, p) : vec4(0.0);
    t[3] = NTARGETS > 3 ? imageLoad(u_coef3, p) : vec4(0.0);
    t[4] = NTARGETS > 4 ? imageLoad(u_coef4, p) : vec4(0.0);
    for (int j = 0; j < NTARGETS * 4; j++)
        c[j] = t[j / 4][j % 4];
}
