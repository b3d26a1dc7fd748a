/* The frame's density and visibility report (docs/ALGORITHM.md "Visibility
 * report"): a histogram of each pixel's total importance mass (how dense the
 * data is where it covers the image), and from the element opacities after P3
 * how visible the important and the unimportant elements are, and how opaque
 * the unimportant ones are where they hide importance. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "renderer_internal.h"

static void ensure_histogram(lc_renderer *r)
{
    if (r->mass_histogram)
        return;
    glCreateBuffers(1, &r->mass_histogram);
    glNamedBufferStorage(r->mass_histogram, MASS_BINS * 4, NULL, GL_DYNAMIC_STORAGE_BIT);
    r->bytes_elements += MASS_BINS * 4;
}

void lc_mass_clear(lc_renderer *r)
{
    ensure_histogram(r);
    const uint32_t zero = 0;
    glClearNamedBufferData(r->mass_histogram, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
}

/* Counts the .r channel of tex (w x h) into the histogram, cleared first. */
static int histogram_of(lc_renderer *r, GLuint tex, int w, int h, int effective, lc_error *err)
{
    GLuint prog = lc_renderer_fixed_program(r, PROG_MASS_HISTOGRAM, err);
    if (!prog)
        return LC_ERR_GL;
    lc_mass_clear(r);
    glUseProgram(prog);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_MASS_HISTOGRAM, r->mass_histogram);
    glBindTextureUnit(TEX_COEF_FIRST, tex);
    glProgramUniform2i(prog, glGetUniformLocation(prog, "u_size"), w, h);
    lc_uniform_i(prog, "u_effective", effective);
    glDispatchCompute((GLuint)(w + 7) / 8, (GLuint)(h + 7) / 8, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    return 0;
}

int lc_mass_histogram_fourier(lc_renderer *r, const lc_frame_setup *fs, lc_error *err)
{
    return histogram_of(r, r->coef_low.tex[0], fs->low_width, fs->low_height, 0, err);
}

/* Lower edge of bin k (mass_common.glsl). */
static double bin_mass(double k) { return exp2(MASS_LOG2_MIN + k / MASS_BINS_PER_OCTAVE); }

/* Mass at rank p of the covered pixels, interpolated in log space within its bin. */
static double mass_rank(const uint32_t *hist, uint64_t covered, double p)
{
    double rank = p * (double)(covered - 1), acc = 0;
    int k = 0;
    while (k < MASS_BINS - 1 && acc + hist[k] <= rank)
        acc += hist[k++];
    return bin_mass(k + (hist[k] ? (rank - acc + 0.5) / hist[k] : 0.5));
}

void lc_mass_report(lc_renderer *r, const lc_frame_setup *fs, lc_frame_info *info)
{
    uint32_t hist[MASS_BINS];
    glGetNamedBufferSubData(r->mass_histogram, 0, sizeof hist, hist);
    uint64_t covered = 0;
    for (int k = 0; k < MASS_BINS; k++)
        covered += hist[k];
    info->mass_median = covered ? mass_rank(hist, covered, 0.5) : 0.0;
    info->mass_p95 = covered ? mass_rank(hist, covered, 0.95) : 0.0;
    info->covered_fraction = (double)covered / ((double)fs->low_width * fs->low_height);
}

/* The histogram of tex (histogram_of's `effective` mode) read back into hist;
 * returns the covered pixels it counts, or -1. */
static int64_t read_histogram(lc_renderer *r, GLuint tex, int w, int h, int effective, uint32_t *hist, lc_error *err)
{
    if (histogram_of(r, tex, w, h, effective, err) != 0)
        return -1;
    glGetNamedBufferSubData(r->mass_histogram, 0, sizeof(uint32_t) * MASS_BINS, hist);
    int64_t covered = 0;
    for (int k = 0; k < MASS_BINS; k++)
        covered += hist[k];
    return covered;
}

double lc_moments_effective_median(lc_renderer *r, GLuint tex, int w, int h, lc_error *err)
{
    uint32_t hist[MASS_BINS];
    int64_t covered = read_histogram(r, tex, w, h, 1, hist, err);
    return covered < 0 ? -1 : covered ? mass_rank(hist, (uint64_t)covered, 0.5) : 0.0;
}

double lc_covered_fraction(lc_renderer *r, GLuint tex, int w, int h, lc_error *err)
{
    uint32_t hist[MASS_BINS];
    int64_t covered = read_histogram(r, tex, w, h, 0, hist, err);
    return covered < 0 ? -1 : (double)covered / ((double)w * h);
}

void lc_occluders_clear(lc_renderer *r)
{
    const uint32_t zero = 0;
    glClearNamedBufferData(r->element_behind, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_BEHIND, r->element_behind);
    if (!r->important_occluded) {
        glCreateBuffers(1, &r->important_occluded);
        glNamedBufferStorage(r->important_occluded, 8, NULL, GL_DYNAMIC_STORAGE_BIT);
        r->bytes_elements += 8;
    }
    glClearNamedBufferData(r->important_occluded, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_IMPORTANT_OCCLUDED, r->important_occluded);
}

#define REACH_SLOTS 64 /* p5_accumulate.frag.glsl: four 64-bit sums a slot */

void lc_reach_begin(lc_renderer *r, const lc_frame_setup *fs, int drawn)
{
    if (!r->top_reach) {
        glCreateBuffers(1, &r->top_reach);
        glNamedBufferStorage(r->top_reach, REACH_SLOTS * 8 * 4, NULL, GL_DYNAMIC_STORAGE_BIT);
        r->bytes_elements += REACH_SLOTS * 8 * 4;
    }
    const uint32_t zero = 0;
    glClearNamedBufferData(r->top_reach, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_TOP_REACH, r->top_reach);
    r->reach_g =
        fs->info && fs->info->has_visibility && fs->info->visible_elements > 0 ? (float)fs->info->top_decile_g : 2.0f;
    r->reach_drawn = drawn && r->reach_g <= 1.0f;
    if (!r->reach_drawn)
        return;
    /* The drawn P5 writes the accumulation and these sums through one
     * framebuffer of both (the accumulation's own keeps its one target). */
    lc_targets_ensure(&r->reach_sums, fs->width, fs->height, 1, GL_RGBA32F, &r->bytes_targets);
    if (!r->reach_fbo)
        glCreateFramebuffers(1, &r->reach_fbo);
    glNamedFramebufferTexture(r->reach_fbo, GL_COLOR_ATTACHMENT0, r->accum.tex[0], 0);
    glNamedFramebufferTexture(r->reach_fbo, GL_COLOR_ATTACHMENT1, r->reach_sums.tex[0], 0);
    static const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(r->reach_fbo, 2, both);
    static const float none[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(r->reach_fbo, GL_COLOR, 1, none);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->reach_fbo);
}

/* The drawn P5's per-pixel sums into top_reach's slots (reach_reduce.comp.glsl). */
static int reduce_drawn(lc_renderer *r, lc_error *err)
{
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->accum.fbo);
    GLuint prog = lc_renderer_fixed_program(r, PROG_REACH_REDUCE, err);
    if (!prog)
        return LC_ERR_GL;
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    glUseProgram(prog);
    glBindTextureUnit(TEX_REACH_SUMS, r->reach_sums.tex[0]);
    glProgramUniform2i(prog, glGetUniformLocation(prog, "u_size"), r->reach_sums.width, r->reach_sums.height);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_TOP_REACH, r->top_reach);
    glDispatchCompute(((GLuint)r->reach_sums.height + 63u) / 64u, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    /* An attached texture outlives its deletion: the targets go when freed. */
    glNamedFramebufferTexture(r->reach_fbo, GL_COLOR_ATTACHMENT0, 0, 0);
    glNamedFramebufferTexture(r->reach_fbo, GL_COLOR_ATTACHMENT1, 0, 0);
    return 0;
}

int lc_reach_end(lc_renderer *r, const lc_frame_setup *fs, lc_error *err)
{
    int pixels = r->reach_drawn;
    r->reach_drawn = 0;
    if (pixels && reduce_drawn(r, err) != 0)
        return err->code;
    if (r->reach_g > 1.0f || !fs->info)
        return 0;
    uint32_t words[REACH_SLOTS * 8];
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(r->top_reach, 0, sizeof words, words);
    /* Each sum as 20-bit pieces, so that adding them over MPI ranks cannot
     * wrap a 32-bit count. */
    uint32_t parts[4][3];
    for (int k = 0; k < 4; k++) {
        uint64_t v = 0;
        for (int slot = 0; slot < REACH_SLOTS; slot++)
            v += ((uint64_t)words[8 * slot + 2 * k + 1] << 32) + words[8 * slot + 2 * k];
        parts[k][0] = (uint32_t)(v & 0xFFFFF), parts[k][1] = (uint32_t)((v >> 20) & 0xFFFFF);
        parts[k][2] = (uint32_t)(v >> 40);
    }
    int rc = lc_reduce_counts(r, &parts[0][0], 12, err);
    if (rc)
        return rc;
    lc_frame_info *info = fs->info;
    for (int k = 0; k < 4; k++)
        info->reach_sums[k] += (parts[k][0] + parts[k][1] * 1048576.0 + parts[k][2] * 1099511627776.0) / 65536.0;
    /* (top's share of the shown importance) / (its share of the drawn importance) */
    double shown = info->reach_sums[0] > 0 ? info->reach_sums[2] / info->reach_sums[0] : 0.0;
    double drawn = info->reach_sums[1] > 0 ? info->reach_sums[3] / info->reach_sums[1] : 0.0;
    info->has_reach = drawn > 0;
    info->top_decile_reach = drawn > 0 ? shown / drawn : 0.0;
    return 0;
}

/* Each element's importance (the mean of its vertices'), in r->importance_cache:
 * kept while the scene and the mapping stay; a layered frame's is computed
 * for every layer's elements at their offsets, each layer with its mapping. */
/* A layered frame's key: each layer's scene, visibility, offset and mapping (FNV-1a). */
static uint64_t layered_key(const lc_frame_setup *fs)
{
    uint64_t h = 1469598103934665603ULL;
    for (int i = 0; i < fs->layer_count; i++) {
        const lc_layer_setup *l = &fs->layers[i];
        struct {
            uint64_t serial;
            int visible, attr;
            uint32_t offset;
            double range[2], exponent;
        } k;
        memset(&k, 0, sizeof k); /* padding too: it is hashed */
        k.serial = l->gs->serial, k.visible = l->visible, k.attr = l->importance_attr, k.offset = l->element_offset;
        k.range[0] = l->importance_range[0], k.range[1] = l->importance_range[1], k.exponent = l->importance_exponent;
        const unsigned char *b = (const unsigned char *)&k;
        for (size_t j = 0; j < sizeof k; j++)
            h = (h ^ b[j]) * 1099511628211ULL;
        b = (const unsigned char *)&l->terms;
        for (size_t j = 0; j < sizeof l->terms; j++)
            h = (h ^ b[j]) * 1099511628211ULL;
    }
    return h | 1; /* never 0, the key of one dataset */
}

static int ensure_importance(lc_renderer *r, const lc_frame_setup *fs, lc_error *err)
{
    uint32_t count = fs->layer_count ? fs->element_total : fs->gs->scene->elements.count;
    uint64_t layered = fs->layer_count ? layered_key(fs) : 0;
    if (layered && r->importance_cache && r->importance_key.layered == layered && r->importance_cache_count == count)
        return 0;
    if (!layered && r->importance_key.layered == 0 && r->importance_cache &&
        r->importance_key.scene == fs->gs->serial && r->importance_key.attr == fs->importance_attr &&
        r->importance_key.range[0] == fs->importance_range[0] &&
        r->importance_key.range[1] == fs->importance_range[1] &&
        r->importance_key.exponent == fs->importance_exponent && r->importance_cache_count == count &&
        memcmp(&r->importance_key.terms, &fs->terms, sizeof fs->terms) == 0)
        return 0;
    GLuint prog = lc_renderer_fixed_program(r, PROG_ELEMENT_IMPORTANCE, err);
    if (!prog)
        return LC_ERR_GL;
    uint32_t *sums = malloc((size_t)(count ? count : 1) * 8);
    float *cache = realloc(r->importance_cache, (size_t)(count ? count : 1) * sizeof(float));
    if (!sums || !cache) {
        free(sums);
        if (cache)
            r->importance_cache = cache;
        return lc_err(err, LC_ERR_NOMEM, "out of memory (element importance of %u elements)", count);
    }
    r->importance_cache = cache;
    if (r->element_importance)
        glDeleteBuffers(1, &r->element_importance);
    glCreateBuffers(1, &r->element_importance);
    glNamedBufferStorage(r->element_importance, (GLsizeiptr)(count ? count : 1) * 8, NULL, GL_DYNAMIC_STORAGE_BIT);
    const uint32_t zero = 0;
    glClearNamedBufferData(r->element_importance, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    /* The geometry bindings give the shader the attributes, the mapping and
     * (layers) the layer's first element. */
    for (int i = 0; i < (fs->layer_count ? fs->layer_count : 1); i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *l = fs->layer_count ? lc_frame_layer(fs, i, &tmp) : fs;
        if (!l)
            continue;
        lc_renderer_bind_geometry(r, prog, l, fs->low_width, fs->low_height, 1);
        glUseProgram(prog);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_IMPORTANCE, r->element_importance);
        uint32_t vertices = l->gs->scene->vertex_count;
        if (vertices)
            lc_dispatch_linear((vertices + 255) / 256);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    }
    glGetNamedBufferSubData(r->element_importance, 0, (GLsizeiptr)count * 8, sums);
    int rc = lc_reduce_counts(r, sums, 2 * (size_t)count, err); /* an element's vertices may lie on several ranks */
    if (rc) {
        free(sums);
        return rc;
    }
    for (uint32_t e = 0; e < count; e++)
        cache[e] = sums[2 * e + 1] ? (float)(sums[2 * e] / 1024.0 / sums[2 * e + 1]) : 0.0f;
    free(sums);
    glDeleteBuffers(1, &r->element_importance);
    r->element_importance = 0;
    r->importance_cache_count = count;
    r->importance_key.scene = fs->layer_count ? 0 : fs->gs->serial; /* a layered cache matches no one scene */
    r->importance_key.layered = layered;
    r->importance_key.attr = fs->importance_attr;
    r->importance_key.range[0] = fs->importance_range[0];
    r->importance_key.range[1] = fs->importance_range[1];
    r->importance_key.exponent = fs->importance_exponent;
    r->importance_key.terms = fs->terms;
    r->importance_serial++;
    return 0;
}

int lc_element_emphasis(const lc_frame_setup *fs)
{
    /* Not on layered frames: the element importance ranks one dataset's elements. */
    /* Lines only where the clarity loop asks (params.foo.element_emphasis: a
     * strength beyond the paper's, clarity.c): at (1, 1) lines keep the
     * paper's per-fragment emphasis. */
    lc_prim_type type = fs->gs->scene->type;
    int kind = type == LC_PRIM_TRIANGLES || (type == LC_PRIM_LINES && fs->params->foo.element_emphasis);
    return !fs->layer_count && kind && fs->params->foo.normalize == LC_NORMALIZE_AUTO;
}

/* Lines' element emphasis (docs/ALGORITHM.md §25): each element's rank above
 * the median of the elements' importance, max(0, 2 rank - 1), rank the
 * element's mid-rank in [0, 1] (from a histogram of RANK_BINS bins). An
 * element's importance is a mean over its segments, and of noise-like values
 * (an atom's speed in a liquid) the means crowd around the mean (the LAMMPS
 * melt: the 10th to 90th percentile within 0.29..0.38), where (1 - g)^(2λ)
 * hardly tells them apart; the rank spreads them whatever the distribution:
 * the least important half gets no protection, the top decile g >= 0.8.
 * NULL when out of memory (the means are used). */
#define RANK_BINS 65536
float *lc_emphasis_ranks(const float *g, uint32_t n)
{
    uint64_t *hist = calloc(RANK_BINS, sizeof *hist);
    float *out = malloc((size_t)(n ? n : 1) * sizeof *out);
    if (!hist || !out) {
        free(hist);
        free(out);
        return NULL;
    }
    for (uint32_t e = 0; e < n; e++) {
        int k = (int)(g[e] * (RANK_BINS - 1) + 0.5f);
        hist[k < 0 ? 0 : k >= RANK_BINS ? RANK_BINS - 1 : k]++;
    }
    /* hist[k] becomes the bin's mid-rank x 2n: 2 (elements below) + (its own). */
    uint64_t below = 0;
    for (int k = 0; k < RANK_BINS; k++) {
        uint64_t c = hist[k];
        hist[k] = 2 * below + c;
        below += c;
    }
    for (uint32_t e = 0; e < n; e++) {
        int k = (int)(g[e] * (RANK_BINS - 1) + 0.5f);
        double rank = hist[k < 0 ? 0 : k >= RANK_BINS ? RANK_BINS - 1 : k] / (2.0 * n);
        out[e] = (float)(rank > 0.5 ? 2 * rank - 1 : 0);
    }
    free(hist);
    return out;
}

int lc_element_emphasis_bind(lc_renderer *r, const lc_frame_setup *fs, GLuint prog, lc_error *err)
{
    int use = lc_element_emphasis(fs) && fs->gs->scene->elements.count > 0;
    if (use) {
        int rc = ensure_importance(r, fs, err);
        if (rc)
            return rc;
        if (!r->element_g || r->element_g_serial != r->importance_serial) {
            if (r->element_g) {
                glDeleteBuffers(1, &r->element_g);
                r->bytes_elements -= (uint64_t)r->element_g_count * 4;
            }
            uint32_t count = r->importance_cache_count;
            r->element_g_count = count;
            glCreateBuffers(1, &r->element_g);
            float *ranked = fs->gs->scene->type == LC_PRIM_LINES ? lc_emphasis_ranks(r->importance_cache, count) : NULL;
            glNamedBufferStorage(r->element_g, (GLsizeiptr)count * 4, ranked ? ranked : r->importance_cache, 0);
            free(ranked);
            r->bytes_elements += (uint64_t)count * 4;
            r->element_g_serial = r->importance_serial;
        }
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_G, use ? r->element_g : r->dummy_buffer);
    lc_uniform_i(prog, "u_element_emphasis", use);
    return 0;
}

#define VIS_BINS 1024
#define VIS_CHUNK 65536u /* elements read back at a time */

/* Mean of `want` values taken from the bins in the order of `step` (+1 from
 * the least important, -1 from the most); a bin taken in part contributes
 * its mean (its elements differ by less than 1/VIS_BINS in importance). */
static double take_mean(const double *count, const double *sum, double want, int step)
{
    double taken = 0, acc = 0;
    for (int i = 0; i < VIS_BINS && taken < want; i++) {
        int k = step > 0 ? i : VIS_BINS - 1 - i;
        if (count[k] <= 0)
            continue;
        double part = want - taken < count[k] ? want - taken : count[k];
        acc += sum[k] * (part / count[k]);
        taken += part;
    }
    return taken > 0 ? acc / taken : 0.0;
}

/* The least important `want` elements' opacity, each weighted by the mass
 * behind it (w: per bin the weights, wa: weight x opacity); 0 when that half
 * hides nothing. */
static double take_weighted(const double *count, const double *w, const double *wa, double want)
{
    double taken = 0, acc_w = 0, acc_wa = 0;
    for (int k = 0; k < VIS_BINS && taken < want; k++) {
        if (count[k] <= 0)
            continue;
        double part = want - taken < count[k] ? want - taken : count[k];
        acc_w += w[k] * (part / count[k]);
        acc_wa += wa[k] * (part / count[k]);
        taken += part;
    }
    return acc_w > 0 ? acc_wa / acc_w : 0.0;
}

/* The report's sums per importance bin, for one layer or the whole frame. */
typedef struct vis_bins {
    double n[VIS_BINS], sum[VIS_BINS], w[VIS_BINS], wa[VIS_BINS];
    double raw[VIS_BINS], wraw[VIS_BINS]; /* sum and wa of P2's opacities, before P3 */
    uint32_t visible;
} vis_bins;

static void report(const vis_bins *b, uint32_t *visible, double *top, double *bottom, double *occluder)
{
    *visible = b->visible;
    *top = take_mean(b->n, b->sum, ceil(0.1 * b->visible), -1);
    *bottom = take_mean(b->n, b->sum, ceil(0.5 * b->visible), +1);
    *occluder = take_weighted(b->n, b->w, b->wa, ceil(0.5 * b->visible));
}

/* topDecileReach's threshold: the lower edge of the bin where the top decile
 * starts, less one bin (an element's importance is its vertices' mean summed
 * in 1/1024 steps, a fragment's is interpolated: they differ by that much). */
static double top_bin(const vis_bins *b)
{
    double want = ceil(0.1 * b->visible), taken = 0;
    int k = VIS_BINS - 1;
    for (; k > 0; k--) {
        taken += b->n[k];
        if (taken >= want)
            break;
    }
    return (double)(k > 0 ? k - 1 : 0) / VIS_BINS;
}

int lc_visibility_measure(lc_renderer *r, const lc_frame_setup *fs, const float *alphas, lc_frame_info *info,
                          lc_error *err)
{
    uint32_t count = fs->layer_count ? fs->element_total : fs->gs->scene->elements.count;
    if (count == 0)
        return 0;
    int rc = ensure_importance(r, fs, err);
    if (rc)
        return rc;
    /* Read back in chunks: the report needs no O(elements) scratch (800 MB a
     * frame for 100 M points otherwise). */
    uint32_t chunk = count < VIS_CHUNK ? count : VIS_CHUNK;
    uint32_t *seen = malloc((size_t)chunk * 4), *behind = malloc((size_t)chunk * 4);
    float *own = alphas ? NULL : malloc((size_t)chunk * 4);
    int nl = fs->layer_count; /* bins[0]: the frame; bins[1 + i]: layer i */
    vis_bins *bins = calloc((size_t)(1 + nl), sizeof *bins);
    if (!seen || !behind || (!alphas && !own) || !bins) {
        free(seen);
        free(behind);
        free(own);
        free(bins);
        return lc_err(err, LC_ERR_NOMEM, "out of memory (visibility of %u elements)", count);
    }
    int layer = -1;
    uint32_t layer_end = 0;
    for (uint32_t first = 0; first < count; first += chunk) {
        uint32_t m = count - first < chunk ? count - first : chunk;
        glGetNamedBufferSubData(r->element_alpha_min, (GLintptr)first * 4, (GLsizeiptr)m * 4, seen);
        if (!alphas)
            glGetNamedBufferSubData(r->element_alpha, (GLintptr)first * 4, (GLsizeiptr)m * 4, own);
        glGetNamedBufferSubData(r->element_behind, (GLintptr)first * 4, (GLsizeiptr)m * 4, behind);
        if ((rc = lc_reduce_counts(r, behind, m, err)) != 0) /* fragments of an element may lie on several ranks */
            break;
        const float *cur = alphas ? alphas + first : own;
        for (uint32_t i = 0; i < m; i++) {
            uint32_t e = first + i;
            while (nl && e >= layer_end && layer + 1 < nl) { /* layers hold consecutive element ranges */
                layer++;
                layer_end = fs->layers[layer].element_offset + fs->layers[layer].gs->scene->elements.count;
            }
            if (nl && fs->layers[layer].context) /* opaque context: not optimized, not reported */
                continue;
            float a_min;
            memcpy(&a_min, &seen[i], 4);
            if (!(a_min <= 1.0f)) /* no fragment this frame (the P2 sentinel is 2) */
                continue;
            float g = r->importance_cache[e];
            int k = (int)(g * VIS_BINS);
            k = k < 0 ? 0 : k >= VIS_BINS ? VIS_BINS - 1 : k;
            vis_bins *into[2] = {&bins[0], nl ? &bins[1 + layer] : NULL};
            for (int j = 0; j < 2 && into[j]; j++) {
                into[j]->n[k] += 1;
                into[j]->sum[k] += cur[i];
                into[j]->w[k] += behind[i] / 4096.0; /* occluders.glsl's units */
                into[j]->wa[k] += behind[i] / 4096.0 * cur[i];
                into[j]->raw[k] += a_min;
                into[j]->wraw[k] += behind[i] / 4096.0 * a_min;
                into[j]->visible++;
            }
        }
    }
    free(seen);
    free(behind);
    free(own);
    uint32_t counts[2] = {0, 0};
    if (!rc && r->important_occluded) {
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glGetNamedBufferSubData(r->important_occluded, 0, sizeof counts, counts);
        rc = lc_reduce_counts(r, counts, 2, err); /* summed over MPI ranks */
    }
    if (!rc) {
        info->important_fragments = counts[0];
        info->important_occluded = counts[0] ? (double)counts[1] / counts[0] : 0.0;
        info->has_visibility = 1;
        report(&bins[0], &info->visible_elements, &info->top_decile_alpha, &info->bottom_half_alpha,
               &info->occluder_alpha);
        info->top_decile_g = top_bin(&bins[0]);
        uint32_t visible;
        vis_bins *b = &bins[0];
        memcpy(b->sum, b->raw, sizeof b->sum), memcpy(b->wa, b->wraw, sizeof b->wa);
        report(b, &visible, &info->raw_top_decile_alpha, &info->raw_bottom_half_alpha, &info->raw_occluder_alpha);
        info->layer_count = nl;
        for (int i = 0; i < nl; i++)
            report(&bins[1 + i], &info->layers[i].visible_elements, &info->layers[i].top_decile_alpha,
                   &info->layers[i].bottom_half_alpha, &info->layers[i].occluder_alpha);
    }
    free(bins);
    return rc;
}
