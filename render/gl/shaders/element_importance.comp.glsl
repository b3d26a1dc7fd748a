// Per-element importance for the visibility report: every vertex adds its
// importance g (fixed point, 1/1024) and a count to its primary element, so
// an element's importance is the mean over its vertices.
layout(local_size_x = 256) in;
// Item index of a 1D dispatch that lc_dispatch_linear may split into rows.
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 256u + gl_GlobalInvocationID.x; }

layout(std430, binding = BIND_ELEMENT_IMPORTANCE) buffer ElementImportance { uvec2 element_importance[]; };

void main()
{
    uint v = linear_invocation();
    if (v >= u_vertex_count || !vertex_visible(v))
        return;
    uint e = vertex_primary(v);
    atomicAdd(element_importance[e].x, uint(round(vertex_importance(v) * 1024.0)));
    atomicAdd(element_importance[e].y, 1u);
}
