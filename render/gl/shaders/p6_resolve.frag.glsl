// P6 resolve (FOO Eq. 19): normalized fragment colour blended with the
// background through the exact transmittance T = exp(-A''_0).
layout(binding = TEX_RESOLVE_A) uniform sampler2D u_accum;
layout(binding = TEX_RESOLVE_B) uniform sampler2D u_optical0; // first coefficient target of P4: .r = A''_0
uniform vec3 u_background;
uniform int u_context; // layers: the opaque context's colour (alpha 1 where it covers) replaces the background
layout(binding = TEX_CONTEXT_COLOR) uniform sampler2D u_context_color;
out vec4 o_color;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 acc = texelFetch(u_accum, p, 0);
    float T = exp(-texelFetch(u_optical0, p, 0).r);
    vec3 bg = u_background;
    if (u_context != 0) {
        vec4 k = texelFetch(u_context_color, p, 0);
        bg = k.a > 0.0 ? k.rgb : bg;
    }
    vec3 c = acc.a > 0.0 ? acc.rgb / acc.a * (1.0 - T) + bg * T : bg;
    o_color = vec4(c, 1.0);
}
