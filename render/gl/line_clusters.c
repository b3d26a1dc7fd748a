/* Cluster representatives as a per-vertex mask of the geometry passes: the
 * resampled lines kept with the GPU scene, one cached dendrogram and the
 * last cut, and the renderer's upload of the mask (lines.clusters). */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "cluster.h"
#include "renderer_internal.h"

#define MAX_CLUSTER_LINES LC_CLUSTER_MAX_LINES
/* What a dendrogram depends on: linkage, lift weights, and the importance and
 * colour mappings only where their lift weight is non-zero. */
typedef struct tree_key {
    int linkage;
    double lift_g, lift_c;
    int g_attr;
    double g_range[2], g_exp;
    int c_mode, c_attr;
    double c_range[2];
} tree_key;

/* What a cut depends on besides its tree: count, representative, and the
 * importance mapping that ranks the lines for "important". */
typedef struct cut_key {
    tree_key tree;
    uint32_t count;
    int representative;
    int g_attr;
    double g_range[2], g_exp;
} cut_key;

struct lc_line_clusters {
    pthread_mutex_t lock;
    lc_line_samples *samples; /* NULL when the dataset has too many lines */
    uint32_t vertex_count;
    uint32_t *offsets; /* copy of the scene's line offsets (they survive the release, but stay ours) */
    int has_tree, has_cut;
    tree_key tree;
    lc_dendrogram *dg;
    cut_key cut;
    uint32_t *bits; /* vertex_count bits: 1 = drawn */
    uint64_t stamp; /* changes with every new cut */
};

int lc_line_clusters_create(const lc_scene *s, lc_line_clusters **out, lc_error *err)
{
    *out = NULL;
    if (s->type != LC_PRIM_LINES || s->line_count == 0)
        return 0;
    lc_line_clusters *lc = calloc(1, sizeof *lc);
    if (!lc)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    pthread_mutex_init(&lc->lock, NULL);
    lc->vertex_count = s->vertex_count;
    if (s->line_count <= MAX_CLUSTER_LINES) {
        const float *attrs[LC_MAX_ATTRIBUTES];
        for (int a = 0; a < s->attribute_count; a++)
            attrs[a] = s->attributes[a].values;
        int rc = lc_line_samples_create(s->positions, s->line_offsets, s->line_count, 0, attrs, s->attribute_count,
                                        &lc->samples, err);
        lc->offsets = malloc(((size_t)s->line_count + 1) * sizeof *lc->offsets);
        if (rc || !lc->offsets) {
            lc_line_clusters_destroy(lc);
            return rc ? rc : lc_err(err, LC_ERR_NOMEM, "out of memory");
        }
        memcpy(lc->offsets, s->line_offsets, ((size_t)s->line_count + 1) * sizeof *lc->offsets);
    }
    *out = lc;
    return 0;
}

void lc_line_clusters_destroy(lc_line_clusters *lc)
{
    if (!lc)
        return;
    lc_line_samples_destroy(lc->samples);
    lc_dendrogram_destroy(lc->dg);
    free(lc->offsets);
    free(lc->bits);
    pthread_mutex_destroy(&lc->lock);
    free(lc);
}

uint64_t lc_line_clusters_bytes(const lc_line_clusters *lc)
{
    if (!lc)
        return 0;
    return lc_line_samples_bytes(lc->samples) + lc_dendrogram_bytes(lc->dg) +
           (lc->bits ? ((uint64_t)lc->vertex_count + 31) / 32 * 4 : 0);
}

/* The importance g of DLS Eq. 2 at every sample under the frame's mapping (the
 * shader's vertex_importance applied to the resampled values). */
static void map_samples(const lc_line_samples *ls, int attr, const double range[2], double exponent, int clamp_only,
                        float *out)
{
    size_t n = (size_t)ls->lines * ls->k;
    const float *v = ls->values + (size_t)attr * n;
    double span = range[1] - range[0];
    for (size_t i = 0; i < n; i++) {
        double t = span != 0 ? (v[i] - range[0]) / span : 1.0;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        out[i] = (float)(clamp_only ? t : pow(t, exponent));
    }
}

static void line_means(const lc_line_samples *ls, const float *g, float *out)
{
    for (uint32_t i = 0; i < ls->lines; i++) {
        double s = 0;
        for (int p = 0; p < ls->k; p++)
            s += g[(size_t)i * ls->k + p];
        out[i] = (float)(s / ls->k);
    }
}

/* Builds the tree and the cut of fs's request under lc->lock. */
static int cut_locked(lc_line_clusters *lc, const lc_frame_setup *fs, lc_error *err)
{
    const lc_render_params *p = fs->params;
    const lc_line_samples *ls = lc->samples;
    size_t n = (size_t)ls->lines * ls->k;
    int g_attr = fs->importance_attr;
    tree_key tk = {.linkage = p->clusters.linkage,
                   .lift_g = p->clusters.lift_importance,
                   .lift_c = p->clusters.lift_color,
                   .g_attr = -1,
                   .c_mode = -1,
                   .c_attr = -1};
    if (tk.lift_g > 0) {
        tk.g_attr = g_attr;
        memcpy(tk.g_range, fs->importance_range, sizeof tk.g_range);
        tk.g_exp = fs->importance_exponent;
    }
    if (tk.lift_c > 0) {
        tk.c_mode = fs->color_mode;
        tk.c_attr = fs->color_attr;
        memcpy(tk.c_range, fs->color_range, sizeof tk.c_range);
        if (fs->color_mode == 1) { /* colour = importance */
            tk.g_attr = g_attr;
            memcpy(tk.g_range, fs->importance_range, sizeof tk.g_range);
            tk.g_exp = fs->importance_exponent;
        }
    }
    cut_key ck = {
        .tree = tk, .count = (uint32_t)p->clusters.count, .representative = p->clusters.representative, .g_attr = -1};
    if (ck.representative == LC_REPRESENTATIVE_IMPORTANT) {
        ck.g_attr = g_attr;
        memcpy(ck.g_range, fs->importance_range, sizeof ck.g_range);
        ck.g_exp = fs->importance_exponent;
    }
    if (lc->has_cut && memcmp(&ck, &lc->cut, sizeof ck) == 0)
        return 0;
    float *g = malloc((n + 1) * sizeof *g), *c = malloc((n + 1) * sizeof *c);
    float *line_g = malloc(((size_t)ls->lines + 1) * sizeof *line_g);
    uint8_t *keep = malloc((size_t)ls->lines + 1);
    int rc = 0;
    if (!g || !c || !line_g || !keep) {
        rc = lc_err(err, LC_ERR_NOMEM, "lines.clusters: out of memory");
        goto out;
    }
    /* A constant importance (no attribute) is g = 1 everywhere. */
    if (g_attr >= 0)
        map_samples(ls, g_attr, fs->importance_range, fs->importance_exponent, 0, g);
    else
        for (size_t i = 0; i < n; i++)
            g[i] = 1.0f;
    if (!lc->has_tree || memcmp(&tk, &lc->tree, sizeof tk) != 0) {
        const float *cs = NULL;
        if (tk.lift_c > 0 && fs->color_mode == 1)
            cs = g;
        else if (tk.lift_c > 0 && fs->color_mode == 0 && fs->color_attr >= 0) {
            map_samples(ls, fs->color_attr, fs->color_range, 1.0, 1, c);
            cs = c;
        }
        lc_cluster_desc desc = {.linkage = (lc_linkage)tk.linkage,
                                .lift_importance = (float)tk.lift_g,
                                .lift_color = (float)tk.lift_c,
                                .importance = tk.lift_g > 0 ? g : NULL,
                                .color = cs};
        lc_dendrogram_destroy(lc->dg);
        lc->dg = NULL;
        lc->has_tree = lc->has_cut = 0;
        rc = lc_dendrogram_build_samples(ls, &desc, &lc->dg, err);
        fs->info->clusters_built = 1;
        if (rc) {
            lc_err_prefix(err, "lines.clusters");
            goto out;
        }
        lc->tree = tk;
        lc->has_tree = 1;
    }
    line_means(ls, g, line_g);
    int k = lc_dendrogram_mask(lc->dg, ck.count, (lc_representative)ck.representative, line_g, keep, err);
    if (k < 0) {
        rc = k;
        goto out;
    }
    size_t words = ((size_t)lc->vertex_count + 31) / 32;
    if (!lc->bits && !(lc->bits = malloc(words * sizeof *lc->bits))) {
        rc = lc_err(err, LC_ERR_NOMEM, "lines.clusters: out of memory");
        goto out;
    }
    memset(lc->bits, 0, words * sizeof *lc->bits);
    for (uint32_t i = 0; i < ls->lines; i++)
        if (keep[i])
            for (uint32_t v = lc->offsets[i]; v < lc->offsets[i + 1]; v++)
                lc->bits[v >> 5] |= 1u << (v & 31u);
    lc->cut = ck;
    lc->has_cut = 1;
    /* Unique across scenes, so a renderer never mistakes one scene's mask for another's. */
    static uint64_t stamps;
    lc->stamp = __atomic_add_fetch(&stamps, 1, __ATOMIC_RELAXED);
out:
    free(g);
    free(c);
    free(line_g);
    free(keep);
    return rc;
}

/* The mask slot for scene gs's current cut: the one holding it; else one not
 * drawn with this frame, preferring gs's own, an empty one, the least recently used. */
static struct lc_line_mask *pick_mask(lc_renderer *r, const lc_gpu_scene *gs, uint64_t stamp, int *fresh)
{
    struct lc_line_mask *best = NULL;
    int rank = 0;
    for (int i = 0; i < LC_MAX_LAYERS; i++) {
        struct lc_line_mask *m = &r->line_masks[i];
        if (m->buffer && m->scene == gs && m->stamp == stamp) {
            *fresh = 0;
            return m;
        }
        if (m->buffer && m->used == r->filter_frame) /* another layer of this frame draws with it */
            continue;
        int k = m->scene == gs ? 3 : !m->buffer ? 2 : 1;
        if (k > rank || (k == rank && m->used < best->used))
            best = m, rank = k;
    }
    *fresh = 1;
    return best;
}

int lc_line_clusters_prepare(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    const lc_render_params *p = fs->params;
    fs->line_mask = 0;
    fs->line_mask_buffer = 0;
    if (p->clusters.count <= 0)
        return 0;
    lc_line_clusters *lc = fs->gs->clusters;
    /* Other kinds of data: a value kept in a session for when it applies
     * again (request_scope.c refuses one given where it does not). */
    if (fs->gs->scene->type != LC_PRIM_LINES || !lc)
        return 0;
    if (!lc->samples || fs->gs->scene->part_of > 0 || fs->gs->scene->vertex_base > 0) /* lc_render_check refuses */
        return lc_err_field(err, LC_ERR_INTERNAL, "lines.clusters", "the clustering was not checked against %s",
                            fs->gs->scene->name);
    double t0 = lc_now();
    pthread_mutex_lock(&lc->lock);
    int rc = cut_locked(lc, fs, err);
    fs->info->clusters_ms = (lc_now() - t0) * 1e3;
    int fresh = 0;
    struct lc_line_mask *m = rc == 0 ? pick_mask(r, fs->gs, lc->stamp, &fresh) : NULL;
    if (rc == 0 && !m) /* more clustered layers than masks: there are LC_MAX_LAYERS of both */
        rc = lc_err(err, LC_ERR_INTERNAL, "more clustered layers than line masks");
    if (m && fresh) {
        size_t bytes = ((size_t)lc->vertex_count + 31) / 32 * 4;
        if (!m->buffer)
            glCreateBuffers(1, &m->buffer);
        glNamedBufferData(m->buffer, (GLsizeiptr)bytes, lc->bits, GL_DYNAMIC_DRAW);
        r->bytes_targets += bytes - m->bytes;
        m->bytes = bytes;
        m->scene = fs->gs;
        m->stamp = lc->stamp;
    }
    pthread_mutex_unlock(&lc->lock);
    if (m)
        m->used = r->filter_frame;
    fs->line_mask = m != NULL;
    fs->line_mask_buffer = m ? m->buffer : 0;
    return rc;
}
