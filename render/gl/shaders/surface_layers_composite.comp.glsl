// Surface layers, compositing (PRT Alg. 2 on the sorted array): front to back
// with one opacity for every layer, C = sum a c_i (1 - a)^i + (1 - a)^n C_bg,
// each layer shaded two-sided by a headlight on its mean normal.
// u_composite 1 and 2 are the count-based OIT baselines of PRT Fig. 5 over the
// same fragments (a layer of m merged fragments stands for m fragments of its
// mean colour): weighted average (weighted_average.glsl, the datasets' method
// "weighted-average" too) C = avg(c) (1 - (1 - a)^N) + (1 - a)^N C_bg
// and weighted sum C = sum a c + max(0, 1 - N a) C_bg, N = fragments in the pixel.
layout(local_size_x = 64) in;

layout(std430, binding = BIND_SURFACE_LAYERS) readonly buffer SurfaceLayers { SurfaceLayer layers[]; };

uniform uint u_max_layers;
uniform float u_opacity;
uniform vec3 u_background;
uniform float u_ambient; // shade = ambient + (1 - ambient) |n.z|
uniform int u_composite; // 0 layers, 1 weighted average, 2 weighted sum

void main()
{
    uint pix = gl_GlobalInvocationID.x;
    if (pix >= u_pixel_count)
        return;
    uint n = pixels[counts_at(pix)];
    uint base = pix * u_max_layers;
    vec3 color = vec3(0.0), sum = vec3(0.0);
    float transmittance = 1.0, fragments = 0.0;
    for (uint k = 0u; k < n; k++) {
        SurfaceLayer l = layers[base + k];
        float len = length(l.normal_count.xyz);
        float facing = len > 0.0 ? abs(l.normal_count.z) / len : 1.0;
        vec3 shaded = l.color_depth.rgb * (u_ambient + (1.0 - u_ambient) * facing);
        color += transmittance * u_opacity * shaded;
        transmittance *= 1.0 - u_opacity;
        sum += l.normal_count.w * shaded;
        fragments += l.normal_count.w;
    }
    if (u_composite == 1 && fragments > 0.0) {
        // Every fragment has opacity a: the mean opacity is a, the mean colour avg(c).
        color = weighted_average_blend(u_opacity * sum, u_opacity * fragments, fragments, u_background);
        transmittance = 0.0;
    } else if (u_composite == 2) {
        color = u_opacity * sum;
        transmittance = max(0.0, 1.0 - fragments * u_opacity);
    }
    color += transmittance * u_background;
    pixels[output_at(pix)] = packUnorm4x8(vec4(clamp(color, 0.0, 1.0), 1.0));
}
