// Importance-aware point subsets (point_subset.c): mode 0 histograms every
// point's importance g into POINT_BINS bins over [0, 1]; mode 1 lists the
// points whose bin is at least u_keep_bin, which interactive frames draw in
// full while the rest are thinned to every n-th.
layout(local_size_x = 256) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 256u + gl_GlobalInvocationID.x; }

layout(std430, binding = BIND_POINT_HISTOGRAM) buffer PointHistogram { uint point_histogram[]; };
layout(std430, binding = BIND_POINT_LIST) buffer PointList { uint point_count; uint point_list[]; };

uniform int u_mode;      // 0 histogram, 1 list
uniform uint u_capacity; // entries point_list holds

void main()
{
    uint v = linear_invocation();
    if (v >= u_vertex_count || !vertex_visible(v))
        return;
    int bin = point_bin(vertex_importance(v));
    if (u_mode == 0) {
        atomicAdd(point_histogram[bin], 1u);
    } else if (bin >= u_keep_bin) {
        uint slot = atomicAdd(point_count, 1u);
        if (slot < u_capacity)
            point_list[slot] = v;
    }
}
