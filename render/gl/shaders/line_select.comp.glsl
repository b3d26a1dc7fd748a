// Importance-aware line subsets (line_subset.c), one invocation per run of a
// level's ribbon strip (a line, or the part of one a level keeps together):
// mode 0 bins the run by its mean vertex importance g (POINT_BINS bins over
// [0, 1]; a line's largest g saturates on long noisy lines) and histograms the
// bins; mode 1 copies the runs whose bin is at least u_keep_bin to the front
// of the kept strip, and about one in u_stride of the others to its back, each
// followed by two restart indices so every run keeps an even offset. Order
// does not matter: the passes it feeds add.
layout(local_size_x = 64) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x; }

layout(std430, binding = BIND_LINE_RUNS) readonly buffer Runs { uvec2 runs[]; };  // (first index, indices)
layout(std430, binding = BIND_LINE_SELECT) buffer Select { uint kept_count[2]; uint run_bin[]; };
layout(std430, binding = BIND_POINT_HISTOGRAM) buffer RunHistogram { uint run_histogram[]; };
layout(std430, binding = BIND_LINE_KEPT) writeonly buffer Kept { uint kept[]; };

uniform int u_mode;     // 0 bins, 1 copy
uniform uint u_runs;    // runs in the level
uniform uint u_stride;  // mode 1: every n-th run below the cut
uniform uint u_total;   // mode 1: indices the kept strip holds

void main()
{
    uint r = linear_invocation();
    if (r >= u_runs)
        return;
    uvec2 run = runs[r];
    if (u_mode == 0) {
        float g = 0.0;
        for (uint i = run.x; i < run.x + run.y; i += 2u)
            g += vertex_importance(indices[i] >> 1);
        int bin = point_bin(run.y > 0u ? g / float(run.y / 2u) : 0.0);
        run_bin[r] = uint(bin);
        atomicAdd(run_histogram[bin], 1u);
        return;
    }
    // One run in u_stride by a hash of its number, not every u_stride-th:
    // files list atoms or seeds in a periodic order (a molecule's atoms, a
    // grid's rows), and a plain stride would pick one kind or one row.
    bool full = int(run_bin[r]) >= u_keep_bin;
    uint h = r * 0x9E3779B1u;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12;
    if (!full && h % u_stride != 0u)
        return;
    uint n = run.y + 2u;
    uint at = full ? atomicAdd(kept_count[0], n) : u_total - atomicAdd(kept_count[1], n) - n;
    for (uint i = 0u; i < run.y; i++)
        kept[at + i] = indices[run.x + i];
    kept[at + run.y] = 0xFFFFFFFFu;
    kept[at + run.y + 1u] = 0xFFFFFFFFu;
}
