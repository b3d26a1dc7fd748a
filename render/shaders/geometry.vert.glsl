// Vertex pulling for points (splat quads), lines (screen-facing ribbons mitred
// by the vertex tangent, so adjacent segments share edges: no gaps, no overlap)
// and triangles. One draw covers every pass; gl_VertexID selects primitive and corner.

out float v_g;        // importance g
out float v_cscalar;  // colour scalar in colormap coordinates
out vec3 v_rgb;       // per-vertex colour (colour mode 2)
out float v_alpha;    // blended element opacity (passes that read them)
out float v_zview;    // view-space depth (distance along the view direction)
out vec3 v_wpos;
out vec3 v_normal;    // triangles: normal; lines: ribbon side vector
out vec2 v_quad;      // points: disc coordinates; lines: (across in [-1,1], along in [0,1])
out vec3 v_bary;      // triangles: barycentric coordinates
flat out uvec3 v_primary; // primary elements of the primitive's vertices

#ifdef READ_ALPHA
layout(std430, binding = 8) readonly buffer ElementAlpha { float element_alpha[]; };
float vertex_alpha(uint v)
{
    uvec4 e = vertex_elements[v];
    vec4 w = vertex_weights[v];
    return w.x * element_alpha[e.x] + w.y * element_alpha[e.y] + w.z * element_alpha[e.z];
}
#else
float vertex_alpha(uint v) { return 1.0; }
#endif

void emit(uint v, vec3 wpos)
{
    v_g = vertex_importance(v);
    v_cscalar = vertex_color_scalar(v, v_g);
    v_rgb = u_color_mode == 2 ? vertex_rgb(v) : vec3(0.0);
    v_alpha = vertex_alpha(v);
    v_wpos = wpos;
    v_zview = -(u_view * vec4(wpos, 1.0)).z;
    gl_Position = u_view_proj * vec4(wpos, 1.0);
    v_normal = vec3(0.0);
    v_quad = vec2(0.0);
    v_bary = vec3(0.0);
}

void main()
{
#if PRIM == PRIM_TRIANGLES
    uint prim = uint(gl_VertexID) / 3u * u_subset;
    uint corner = uint(gl_VertexID) % 3u;
    uint i0 = indices[3u * prim], i1 = indices[3u * prim + 1u], i2 = indices[3u * prim + 2u];
    uint v = corner == 0u ? i0 : (corner == 1u ? i1 : i2);
    emit(v, positions[v].xyz);
    v_normal = frames[v].xyz;
    v_bary = vec3(corner == 0u, corner == 1u, corner == 2u);
    v_primary = uvec3(vertex_elements[i0].w, vertex_elements[i1].w, vertex_elements[i2].w);
#else
    const vec2 quad[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    uint prim = uint(gl_VertexID) / 6u * u_subset;
    vec2 q = quad[gl_VertexID % 6];
#if PRIM == PRIM_POINTS
    uint v = prim;
    emit(v, positions[v].xyz);
    gl_Position.xy += q * (2.0 * u_point_radius_px / u_viewport) * gl_Position.w;
    v_quad = q;
    v_primary = uvec3(vertex_elements[v].w);
#else
    uint a = indices[2u * prim], b = indices[2u * prim + 1u];
    uint v = q.x < 0.0 ? a : b;
    vec3 p = positions[v].xyz;
    vec3 to_cam = u_ortho != 0 ? -u_view_dir : normalize(u_eye - p);
    vec3 side = cross(frames[v].xyz, to_cam);
    if (dot(side, side) < 1e-12) // tangent along the view ray: any perpendicular works
        side = cross(abs(to_cam.x) < 0.9 ? vec3(1, 0, 0) : vec3(0, 1, 0), to_cam);
    side = normalize(side);
    float depth = u_ortho != 0 ? u_focal_dist : max(dot(p - u_eye, u_view_dir), 1e-6 * u_focal_dist);
    float pixel = u_pixel_world * depth / u_focal_dist;
    float half_width = max(u_line_half_width, u_min_half_pixels * pixel);
    emit(v, p + side * (half_width * q.y));
    v_normal = side;
    // Tube shading needs a few pixels across; on thinner ribbons the pixel
    // centres would sample the tube profile unevenly along the line (a dotted
    // look), so the profile flattens as the ribbon narrows.
    float width_px = 2.0 * half_width / pixel;
    v_quad = vec2(q.y * clamp((width_px - 1.0) / 4.0, 0.0, 0.85), q.x < 0.0 ? 0.0 : 1.0);
    v_primary = uvec3(vertex_elements[a].w, vertex_elements[b].w, 0u);
#endif
#endif
}
