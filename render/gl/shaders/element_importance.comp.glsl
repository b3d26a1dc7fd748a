// Per-element importance for the visibility report: every vertex adds its
// importance g (fixed point, 1/1024) and a count to its primary element, so
// an element's importance is the mean over its vertices.
layout(local_size_x = 256) in;

layout(std430, binding = BIND_ELEMENT_IMPORTANCE) buffer ElementImportance { uvec2 element_importance[]; };

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    uint e = vertex_elements[v].w;
    atomicAdd(element_importance[e].x, uint(round(vertex_importance(v) * 1024.0)));
    atomicAdd(element_importance[e].y, 1u);
}
