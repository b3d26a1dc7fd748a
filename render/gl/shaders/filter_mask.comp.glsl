// The filters' visibility mask (filter.c): one invocation per line (or per
// point), which reduces each filtered attribute over the line's vertices and
// clears the visibility bit of every vertex of a line that fails a filter
// (a vertex-level filter on lines, a time window, clears single vertices).
// The mask starts as all ones.
layout(local_size_x = 256) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 256u + gl_GlobalInvocationID.x; }

layout(std430, binding = BIND_LINE_OFFSETS) readonly buffer LineOffsets { uint line_offsets[]; };
layout(std430, binding = BIND_VISIBLE_OUT) buffer VisibleOut { uint visible_out[]; };

uniform uint u_items;  // lines, or points
uniform int u_per_line; // 1: items are lines (line_offsets), 0: points
uniform int u_filters;
uniform int u_filter_attr[MAX_FILTERS];
uniform int u_filter_over[MAX_FILTERS]; // lc_filter_over: 0 vertex, 1 min, 2 max, 3 mean, 4 first, 5 last, 6 change
uniform vec2 u_filter_bounds[MAX_FILTERS];
uniform ivec2 u_filter_open[MAX_FILTERS];

// NaN passes no filter.
bool holds(int i, float x)
{
    vec2 b = u_filter_bounds[i];
    bool lo = u_filter_open[i].x != 0 ? x > b.x : x >= b.x;
    bool hi = u_filter_open[i].y != 0 ? x < b.y : x <= b.y;
    return lo && hi;
}

// The statistic filter i tests over vertices [a, b) (b > a).
float line_statistic(int i, uint a, uint b)
{
    int attr = u_filter_attr[i], over = u_filter_over[i];
    float first = attribute_value(attr, a), last = attribute_value(attr, b - 1u);
    if (over == 4)
        return first;
    if (over == 5)
        return last;
    if (over == 6)
        return last - first;
    float lo = first, hi = first, sum = 0.0;
    for (uint v = a; v < b; v++) {
        float x = attribute_value(attr, v);
        lo = min(lo, x);
        hi = max(hi, x);
        sum += x;
    }
    return over == 1 ? lo : over == 2 ? hi : sum / float(b - a);
}

void main()
{
    uint item = linear_invocation();
    if (item >= u_items)
        return;
    uint a = u_per_line != 0 ? line_offsets[item] : item;
    uint b = u_per_line != 0 ? line_offsets[item + 1u] : item + 1u;
    if (b <= a)
        return;
    bool pass = true;
    for (int i = 0; i < u_filters && pass; i++)
        if (u_per_line == 0 || u_filter_over[i] != 0)
            pass = holds(i, u_per_line != 0 ? line_statistic(i, a, b) : attribute_value(u_filter_attr[i], a));
    if (!pass) {
        for (uint v = a; v < b; v++)
            atomicAnd(visible_out[v >> 5], ~(1u << (v & 31u)));
        return;
    }
    // A line's vertex-level filters (a time window) clear single vertices;
    // the pulled segment draw then drops every segment with a cleared end.
    for (int i = 0; i < u_filters && u_per_line != 0; i++)
        if (u_filter_over[i] == 0)
            for (uint v = a; v < b; v++)
                if (!holds(i, attribute_value(u_filter_attr[i], v)))
                    atomicAnd(visible_out[v >> 5], ~(1u << (v & 31u)));
}
