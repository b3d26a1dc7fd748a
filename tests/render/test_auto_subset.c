/* params.autoSubset (docs/ALGORITHM.md §10): on stacked full-screen quads
 * (every pixel covered by all of them) the effective fragment count P0
 * measures, (sum g^2)^2 / sum g^4, against the same sum on the CPU, and the
 * stride P1 draws with against the rule (largest power of two <= 1 + N/4,
 * capped by autoSubset, only from 4 on); sparse stacks, autoSubset 1,
 * normalize "off" and an explicit subset keep P1 on every primitive; P1's
 * sums under the stride against the CPU's sums over the primitives it keeps,
 * after a clarity loop of several tries that draws P1 once. */
#include <math.h>

#include "render_util.h"

/* n quads, importance alternating between hi and lo, front to back. */
static void make_stack(test_quad *q, int n, double hi, double lo)
{
    for (int i = 0; i < n; i++) {
        q[i].z = 0.4 - 0.8 * i / (n > 1 ? n - 1 : 1);
        q[i].g = i % 2 ? lo : hi;
        q[i].rgb[0] = 0.2 + 0.6 * (i % 3) / 2.0, q[i].rgb[1] = 0.5, q[i].rgb[2] = 1.0 - 0.5 * (i % 2);
        q[i].half = 2;
    }
}

static double cpu_effective(const test_quad *q, int n)
{
    double s2 = 0, s4 = 0;
    for (int i = 0; i < n; i++)
        s2 += q[i].g * q[i].g, s4 += q[i].g * q[i].g * q[i].g * q[i].g;
    return s2 * s2 / s4;
}

static int rule(double effective, int cap)
{
    int n = 1;
    while (2 * n <= cap && 2 * n <= 1 + effective / 4)
        n *= 2;
    return n >= 4 ? n : 1;
}

enum { SIZE = 32 };
static int most_tries; /* the clarity loop's tries on the stacks (one must iterate for the P1 check to say much) */

/* Renders the stack; returns the frame's report in *info and the image in rgba. */
static int render_clarity(test_gl *t, lc_gpu_scene *gs, int auto_subset, lc_normalize normalize, int subset,
                          double clarity, lc_frame_info *info, uint8_t *rgba)
{
    lc_render_params p;
    test_quad_params(&p, SIZE);
    p.foo.auto_subset = auto_subset;
    p.foo.normalize = normalize;
    p.foo.subset = subset;
    p.foo.clarity = clarity;
    lc_error err = {0};
    memset(info, 0, sizeof *info);
    int rc = lc_render_frame(t->renderer, gs, &p, NULL, 0, rgba, info, &err);
    CHECK(rc == 0, "render: %s", err.msg);
    return rc;
}

static int render(test_gl *t, lc_gpu_scene *gs, int auto_subset, lc_normalize normalize, int subset,
                  lc_frame_info *info, uint8_t *rgba)
{
    return render_clarity(t, gs, auto_subset, normalize, subset, 0 /* one optimization */, info, rgba);
}

static void check_stack(test_gl *t, int n, double hi, double lo)
{
    test_quad q[64];
    make_stack(q, n, hi, lo);
    lc_scene *s = test_quad_scene(q, n);
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    CHECK(s && lc_gpu_scene_create(s, &gs, &err) == 0, "gpu scene: %s", err.msg);
    if (!gs) {
        lc_scene_destroy(s);
        return;
    }
    uint8_t *a = malloc(SIZE * SIZE * 4), *b = malloc(SIZE * SIZE * 4);
    lc_frame_info info;
    double want = cpu_effective(q, n);
    /* The histogram has 16 bins per octave; the median is interpolated within one. */
    double tol = want * (exp2(1.0 / 16) - 1);
    for (int cap = 4; cap <= 8; cap *= 2) {
        if (render(t, gs, cap, LC_NORMALIZE_AUTO, 1, &info, a) != 0)
            break;
        printf("%d quads (g %.2f/%.2f), autoSubset %d: P0 measured N %.3f (cpu %.3f), P1 stride %d (rule %d)\n", n, hi,
               lo, cap, info.p0_fragments_median, want, info.p1_subset, rule(want, cap));
        CHECK_NEAR(info.p0_fragments_median, want, tol, "effective fragments");
        CHECK(info.p1_subset == rule(want, cap), "%d quads, autoSubset %d: P1 stride %d, rule %d", n, cap,
              info.p1_subset, rule(want, cap));
    }
    /* Off three ways: every primitive in P1 and no measurement. */
    const struct {
        int cap;
        lc_normalize normalize;
        int subset;
        const char *what;
    } off[] = {{1, LC_NORMALIZE_AUTO, 1, "autoSubset 1"},
               {8, LC_NORMALIZE_OFF, 1, "normalize off"},
               {8, LC_NORMALIZE_AUTO, 2, "subset 2"}};
    for (size_t k = 0; k < sizeof off / sizeof off[0]; k++) {
        if (render(t, gs, off[k].cap, off[k].normalize, off[k].subset, &info, b) != 0)
            break;
        CHECK(info.p1_subset == off[k].subset && info.p0_fragments_median == 0, "%d quads, %s: P1 stride %d, N %.3f", n,
              off[k].what, info.p1_subset, info.p0_fragments_median);
    }
    /* P1's zeroth coefficient (sum of g^2, weighted by the stride) against the
     * CPU: a stride n over the triangles (two per quad, even n) keeps the first
     * triangle of every (n/2)-th quad, the half of the view below its diagonal
     * (x > y), and nothing above it. */
    /* With the clarity loop trying several strengths (a target the stack cannot meet at strength 1), P1 draws
     * once: the sums below must still be the whole frame's after the last try. */
    render_clarity(t, gs, 8, LC_NORMALIZE_AUTO, 1, 0.99, &info, a);
    printf("%d quads, clarity 0.99: %d tries, P1 drawn %d time(s)\n", n, info.clarity_tries, info.importance_passes);
    CHECK(info.clarity_tries >= 1 && info.importance_passes == 1,
          "%d quads: the loop tried %d strengths and P1 ran "
          "%d times (once)",
          n, info.clarity_tries, info.importance_passes);
    most_tries = info.clarity_tries > most_tries ? info.clarity_tries : most_tries;
    int stride = info.p1_subset;
    size_t count = lc_renderer_read_targets(t->renderer, 0, NULL, 0);
    float *coef = count ? malloc(count * sizeof *coef) : NULL;
    CHECK(coef != NULL, "P1 targets");
    if (coef) {
        lc_renderer_read_targets(t->renderer, 0, coef, count);
        enum { LOW = SIZE / 2 };
        double below = 0, above = 0;
        for (int i = 0; i < n; i++) {
            double g2 = q[i].g * q[i].g;
            if (stride == 1)
                below += g2, above += g2;
            else if (i % (stride / 2) == 0)
                below += stride * g2;
        }
        double got_below = coef[(3 * LOW + 12) * 4], got_above = coef[(12 * LOW + 3) * 4];
        printf("%d quads, P1 stride %d: sum g^2 below the diagonal %.4f (cpu %.4f), above %.4f (cpu %.4f)\n", n, stride,
               got_below, below, got_above, above);
        CHECK_NEAR(got_below, below, 1e-4 * below + 1e-6, "P1 sum of g^2 below the diagonal");
        CHECK_NEAR(got_above, above, 1e-4 * above + 1e-6, "P1 sum of g^2 above the diagonal");
        free(coef);
    }
    /* autoSubset 1 is the frame without the rule: where the rule keeps every
     * primitive, the same pixels. */
    render(t, gs, 1, LC_NORMALIZE_AUTO, 1, &info, b);
    if (stride == 1)
        CHECK(memcmp(a, b, SIZE * SIZE * 4) == 0, "%d quads: the rule kept every primitive, yet the image changed", n);
    free(a);
    free(b);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    printf("renderer: %s\n", lc_gl_renderer(t.gl));
    check_stack(&t, 40, 1.0, 0.5);  /* N = 29.4: stride 8 (4 under autoSubset 4) */
    check_stack(&t, 24, 0.9, 0.15); /* dominated by the 12 important quads: N = 12.3, stride 4 */
    check_stack(&t, 6, 1.0, 0.5);   /* sparse: N = 4.4 allows 2, which is not taken */
    CHECK(most_tries >= 2, "the clarity loop tried several strengths on some stack (%d at most)", most_tries);
    test_gl_close(&t);
    return lc_test_finish();
}
