/* params.progressive (docs/ALGORITHM.md §34; PRT §2.2, §2.4): a still drawn
 * in n batches of the primitives, one a frame. Every pass but P2's minima and
 * P3 is a sum over fragments, so, as the shards of one dataset add over MPI
 * ranks (reduce.c), batch k's fragments add to the sums the batches before it
 * left in the renderer's targets: each frame draws 1/n of the data and shows
 * the picture of the batches so far. P0 runs whole in the first frame (every
 * later sum is warped by it); P1 adds batch k, so after the last batch its
 * sums are the one-shot frame's. While batches arrive, P2 gives batch k's
 * elements their opacity against the importance that has arrived and the
 * elements before keep theirs (their P4/P5 sums are not drawn again); the
 * last batch's frame, with P1's sums complete, runs P2, P4 and P5 over every
 * primitive, so its image is the one-shot frame's. */
#include <stdlib.h>
#include <string.h>

#include "renderer_internal.h"

static int active(const lc_render_params *p) { return p->foo.progressive > 1; }

/* The request without the per-frame batch: what must not change between batches. */
static void request_key(const lc_render_params *p, lc_render_params *key)
{
    memcpy(key, p, sizeof *key);
    key->foo.batch = 0;
}

int lc_progressive_begin(lc_renderer *r, const lc_frame_setup *fs, lc_error *err)
{
    const lc_render_params *p = fs->params;
    int expected = r->progressive_next;
    r->progressive_next = 0; /* any other frame ends the still under way */
    if (!active(p) || p->foo.batch_prefix)
        return 0;
    int n = p->foo.progressive, k = p->foo.batch - 1; /* from 0 here */
    if (k < 0 || k >= n)
        return lc_err_field(err, LC_ERR_INVALID, "params.progressive", "batch %d of %d", k + 1, n);
    if (r->desc.reducer && r->desc.reducer->size > 1)
        return lc_err_field(err, LC_ERR_INVALID, "params.progressive",
                            "the batches' sums are kept by one renderer, not split over processes");
    if (!r->progressive_params && !(r->progressive_params = malloc(sizeof *r->progressive_params)))
        return lc_err(err, LC_ERR_NOMEM, "out of memory (progressive)");
    lc_render_params key;
    request_key(p, &key);
    if (k > 0 && (expected != k || r->progressive_scene != fs->gs || memcmp(&key, r->progressive_params, sizeof key)))
        return lc_err_field(err, LC_ERR_INVALID, "params.progressive",
                            "batch %d must follow batch %d of the same request on the same renderer; start at 1", k + 1,
                            k);
    memcpy(r->progressive_params, &key, sizeof key);
    r->progressive_scene = fs->gs;
    r->progressive_next = k + 1 < n ? k + 1 : 0;
    return 0;
}

void lc_progressive_pass(lc_frame_setup *fs, lc_pass pass)
{
    const lc_foo_params *foo = &fs->params->foo;
    fs->batch_count = fs->batch_first = fs->batch_end = fs->keep_sums = 0;
    if (foo->progressive <= 1)
        return;
    int n = foo->progressive, k = foo->batch - 1;
    if (foo->batch_prefix) { /* the reference: every pass over batches 1 .. batch */
        fs->batch_count = n, fs->batch_end = foo->batch;
        return;
    }
    if (k < 0) /* not a batch frame (lc_render_frame runs every batch) */
        return;
    int last = k == n - 1;
    switch (pass) {
    case LC_PASS_DEPTH_RANGE: fs->keep_sums = k > 0; break; /* whole, in the first frame */
    case LC_PASS_IMPORTANCE:
        fs->batch_count = n, fs->batch_first = k, fs->batch_end = k + 1;
        fs->keep_sums = k > 0;
        break;
    default: /* P2, P4 and P5: batch k, or every primitive once P1's sums are complete */
        if (!last) {
            fs->batch_count = n, fs->batch_first = k, fs->batch_end = k + 1;
            fs->keep_sums = k > 0;
        }
        break;
    }
}

void lc_progressive_range(const lc_frame_setup *fs, uint64_t n, uint64_t *lo, uint64_t *hi)
{
    if (fs->batch_count <= 0) {
        *lo = 0, *hi = n;
        return;
    }
    *lo = n * (uint64_t)fs->batch_first / (uint64_t)fs->batch_count;
    *hi = n * (uint64_t)fs->batch_end / (uint64_t)fs->batch_count;
}
