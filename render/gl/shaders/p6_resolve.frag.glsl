// P6 resolve (FOO Eq. 19): normalized fragment colour blended with the
// background through the exact transmittance T = exp(-A''_0).
layout(binding = TEX_RESOLVE_A) uniform sampler2D u_accum;
layout(binding = TEX_RESOLVE_B) uniform sampler2D u_optical0; // first coefficient target of P4: .r = A''_0
uniform vec3 u_background;
out vec4 o_color;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 acc = texelFetch(u_accum, p, 0);
    float T = exp(-texelFetch(u_optical0, p, 0).r);
    vec3 c = acc.a > 0.0 ? acc.rgb / acc.a * (1.0 - T) + u_background * T : u_background;
    o_color = vec4(c, 1.0);
}
