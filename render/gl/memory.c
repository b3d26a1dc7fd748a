/* Memory of a dataset while it is served; see memory.h. */
#include "memory.h"

#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cluster.h"

static uint64_t session_bytes(const lc_scene *s, const lc_gpu_scene_desc *desc, int sessions)
{
    uint64_t per = desc && desc->exact_positions ? 4 : 2;
    return (uint64_t)(sessions > 0 ? sessions : 0) * per * (s->elements.count ? s->elements.count : 1);
}

void lc_memory_report_of(const lc_scene *scene, const lc_gpu_scene *gs, const lc_gpu_scene_desc *desc, int workers,
                         int sessions, lc_memory_report *out)
{
    memset(out, 0, sizeof *out);
    lc_scene_memory_of(scene, &out->cpu);
    if (gs)
        lc_gpu_scene_memory(gs, &out->gpu);
    else
        lc_gpu_scene_estimate(scene, desc, &out->gpu);
    out->per_element = (uint64_t)(workers > 0 ? workers : 0) * LC_RENDERER_BYTES_PER_ELEMENT * scene->elements.count;
    out->per_session = session_bytes(scene, desc, sessions);
    out->total = out->cpu.total + out->gpu.total + out->per_element + out->per_session;
}

uint64_t lc_memory_estimate(const lc_scene *scene, const lc_gpu_scene_desc *desc, int workers, int sessions)
{
    lc_memory_report m;
    lc_memory_report_of(scene, NULL, desc, workers, sessions, &m);
    /* After the release the CPU keeps only the line offsets, and for line
     * clustering the resampled lines and a copy of the offsets
     * (line_clusters.c). */
    uint64_t kept = scene->line_offsets ? ((uint64_t)scene->line_count + 1) * 4 : 0;
    if (scene->type == LC_PRIM_LINES && scene->line_count > 0 && scene->line_count <= LC_CLUSTER_MAX_LINES)
        kept += lc_line_samples_estimate(scene->line_count, 0, scene->attribute_count) +
                ((uint64_t)scene->line_count + 1) * 4;
    return m.gpu.total + m.per_element + m.per_session + kept;
}

int lc_memory_check(const lc_scene *scene, const lc_gpu_scene_desc *desc, int workers, int sessions, uint64_t limit,
                    lc_error *err)
{
    if (!limit)
        return 0;
    uint64_t need = lc_memory_estimate(scene, desc, workers, sessions);
    if (need <= limit)
        return 0;
    return lc_err(err, LC_ERR_LIMIT,
                  "%s: needs an estimated %.1f MB resident (%u vertices, %.1f bytes each, %u elements) but "
                  "--max-memory is %.1f MB",
                  scene->name, need / 1e6, scene->vertex_count,
                  scene->vertex_count ? (double)need / scene->vertex_count : 0.0, scene->elements.count, limit / 1e6);
}

int lc_memory_parse_bytes(const char *text, unsigned long long *out)
{
    char *end;
    double v = strtod(text, &end);
    if (end == text || !(v >= 0) || !isfinite(v))
        return -1;
    double unit = 1;
    if (*end) {
        const char *units = "kmgt";
        const char *u = strchr(units, end[0] | 0x20);
        if (!u || !end[0])
            return -1;
        unit = pow(1024.0, (double)(u - units + 1));
        end++;
        if (*end == 'B' || *end == 'b')
            end++;
        if (*end)
            return -1;
    }
    v *= unit;
    if (v > 1.8e19)
        return -1;
    *out = (unsigned long long)v;
    return 0;
}

uint64_t lc_memory_resident_bytes(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    if (!f)
        return 0;
    unsigned long long size = 0, resident = 0;
    int ok = fscanf(f, "%llu %llu", &size, &resident) == 2;
    fclose(f);
    long page = sysconf(_SC_PAGESIZE);
    return ok && page > 0 ? resident * (uint64_t)page : 0;
}

void lc_memory_trim(void) { malloc_trim(0); }
