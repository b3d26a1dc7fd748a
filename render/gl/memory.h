/* Memory of a dataset while it is served (docs/MEMORY.md): bytes by kind (the
 * scene's CPU arrays, its GPU buffers, the per-element state of each render
 * worker and the opacities of each session), the estimate a --max-memory
 * limit is checked against, and the process's resident size.
 * Threading: plain functions; reentrant. */
#ifndef LC_MEMORY_H
#define LC_MEMORY_H

#include <stdint.h>

#include "renderer.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_memory_report {
    lc_scene_memory cpu;  /* the scene's arrays now */
    lc_gpu_memory gpu;    /* its GPU buffers (estimated when there is no GPU copy yet) */
    uint64_t per_element; /* opacity buffers and caches of `workers` renderers */
    uint64_t per_session; /* frame states of `sessions` viewers */
    uint64_t total;
} lc_memory_report;

/* Fills out for scene with GPU copy gs (NULL: the layout desc gives, estimated). */
void lc_memory_report_of(const lc_scene *scene, const lc_gpu_scene *gs, const lc_gpu_scene_desc *desc, int workers,
                         int sessions, lc_memory_report *out);
/* Resident bytes the scene will take once uploaded and released (GPU buffers,
 * per-element state of `workers`, `sessions` viewers, what the CPU keeps). */
uint64_t lc_memory_estimate(const lc_scene *scene, const lc_gpu_scene_desc *desc, int workers, int sessions);
/* LC_ERR_LIMIT when limit > 0 and lc_memory_estimate exceeds it; the message
 * names the scene, the estimate (and its bytes per vertex) and the limit. */
int lc_memory_check(const lc_scene *scene, const lc_gpu_scene_desc *desc, int workers, int sessions, uint64_t limit,
                    lc_error *err);
/* "123", "64k", "512M", "20G", "1.5T" (powers of 1024) -> bytes; -1 if malformed. */
int lc_memory_parse_bytes(const char *text, unsigned long long *out);
/* Resident bytes of this process (/proc/self/statm); 0 where unknown. */
uint64_t lc_memory_resident_bytes(void);
/* Hands freed heap pages back to the system (after releasing large arrays). */
void lc_memory_trim(void);

#ifdef __cplusplus
}
#endif
#endif
