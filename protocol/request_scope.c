/* Where each request field applies: the methods and primitive kinds whose
 * frames read it. A field given with a value other than its default where it
 * does not apply is refused naming it (lc_proto_check_scope, request.c), so no
 * request is accepted and silently ignored; `lucent schema` publishes the same
 * table ("methods", "primitives") for clients and the page. */
#include <stdio.h>
#include <string.h>

#include "request_scope.h"

#define M(x) (1u << LC_METHOD_##x)
#define P(x) (1u << LC_PRIM_##x)
#define DATASET_METHODS (LC_PROTO_ALL_METHODS & ~M(SURFACE_LAYERS)) /* everything that draws a dataset */
#define BLENDS (M(WBOIT) | M(WEIGHTED_AVERAGE) | M(BINNING))        /* FOO opacities, another compositing */
#define OPTIMIZED (M(FOURIER) | M(EXACT) | BLENDS)                  /* P1-P3: the opacity optimization */
#define FOURIER_PASSES (M(FOURIER) | BLENDS)                        /* P1/P2 at resolutionScale */
#define SERIES (M(FOURIER) | M(DIRECT) | BLENDS | M(KANZLER))       /* a Fourier series in P1/P2 or P4/P5 */
#define STRIDED (M(FOURIER) | M(DIRECT) | BLENDS)                   /* params.subset: P4 weights a stride */
#define EQUALIZING (M(FOURIER) | M(DIRECT) | M(EXACT))              /* color.equalize's histogram */
#define NOT_SURFACES (P(POINTS) | P(LINES))
#define COMPOSITED (M(FOURIER) | M(DIRECT)) /* P4-P6: ground shadows, smart transparency */

typedef struct scope_rule {
    const char *section; /* NULL = top level */
    const char *name;    /* NULL = every field of the section without a rule of its own */
    unsigned methods, prims;
} scope_rule;

/* First match wins: a field's own row, then its section's. */
static const scope_rule rules[] = {
    {"params", "q", OPTIMIZED, LC_PROTO_ALL_PRIMS},
    {"params", "r", OPTIMIZED, LC_PROTO_ALL_PRIMS},
    {"params", "lambda", OPTIMIZED, LC_PROTO_ALL_PRIMS},
    {"params", "smoothing", OPTIMIZED, LC_PROTO_ALL_PRIMS},
    {"params", "smoothingWeight", OPTIMIZED, LC_PROTO_ALL_PRIMS},
    {"params", "smoothingWeights", OPTIMIZED, LC_PROTO_ALL_PRIMS},
    {"params", "fadeHalfLife", OPTIMIZED, LC_PROTO_ALL_PRIMS},
    {"params", "clarity", OPTIMIZED, LC_PROTO_ALL_PRIMS},
    {"params", "bands", SERIES, LC_PROTO_ALL_PRIMS},
    {"params", "depthMargin", SERIES, LC_PROTO_ALL_PRIMS},
    {"params", "depthRange", SERIES, LC_PROTO_ALL_PRIMS},
    {"params", "subset", STRIDED, LC_PROTO_ALL_PRIMS}, /* kanzler: its maps count every fragment */
    {"params", "resolutionScale", FOURIER_PASSES, LC_PROTO_ALL_PRIMS},
    {"params", "estimator", FOURIER_PASSES, LC_PROTO_ALL_PRIMS},
    {"params", "autoSubset", FOURIER_PASSES, LC_PROTO_ALL_PRIMS},
    {"params", "guardBand", FOURIER_PASSES, LC_PROTO_ALL_PRIMS},
    {"params", "progressive", M(FOURIER), NOT_SURFACES}, /* its batches add into the Fourier sums */
    {"params", "directExponent", M(DIRECT) | M(KANZLER), LC_PROTO_ALL_PRIMS},
    {"params", "alphaSource", M(DIRECT), LC_PROTO_ALL_PRIMS},
    {"params", "alphaConstant", M(DIRECT), LC_PROTO_ALL_PRIMS},
    {"params", "gamma", M(DIRECT), LC_PROTO_ALL_PRIMS},
    {"params", "kanzlerImportance", M(KANZLER), NOT_SURFACES},
    {"params", "kanzlerCoverage", M(KANZLER), NOT_SURFACES},
    {"params", "kanzlerVariance", M(KANZLER), P(LINES)}, /* points have no direction */
    {"params", "kanzlerDepth", M(KANZLER), NOT_SURFACES},
    {"params", "kanzlerLambda", M(KANZLER), NOT_SURFACES},
    {"params", "excludeSelf", M(EXACT), LC_PROTO_ALL_PRIMS},     /* the exact sums know each fragment's element */
    {"params", "lod", DATASET_METHODS, P(LINES) | P(TRIANGLES)}, /* simplified polylines and meshes */
    {"params", NULL, DATASET_METHODS, LC_PROTO_ALL_PRIMS},
    {"importance", NULL, DATASET_METHODS, LC_PROTO_ALL_PRIMS},
    {"color", "equalize", EQUALIZING, LC_PROTO_ALL_PRIMS},
    {"color", "fixed", EQUALIZING, LC_PROTO_ALL_PRIMS},
    {"color", "fadeHalfLife", EQUALIZING, LC_PROTO_ALL_PRIMS},
    {"color", NULL, DATASET_METHODS, LC_PROTO_ALL_PRIMS},
    {"style", "background", LC_PROTO_ALL_METHODS, LC_PROTO_ALL_PRIMS},
    {"style", "lineWidth", DATASET_METHODS, P(LINES)},
    {"style", "minLinePixels", DATASET_METHODS, P(LINES)},
    {"style", "haloWidth", DATASET_METHODS, P(LINES)},
    {"style", "haloDepth", DATASET_METHODS, P(LINES)},
    {"style", "haloStrength", DATASET_METHODS, P(LINES)},
    {"style", "pointSize", DATASET_METHODS, P(POINTS)},
    {"style", "silhouetteExponent", DATASET_METHODS, P(TRIANGLES)},
    {"style", "antialias", SERIES, LC_PROTO_ALL_PRIMS},
    {"style", "shadow", COMPOSITED, LC_PROTO_ALL_PRIMS},
    {"style", "shadowLight", COMPOSITED, LC_PROTO_ALL_PRIMS},
    {"style", "shadowColored", COMPOSITED, LC_PROTO_ALL_PRIMS},
    {"style", "ground", COMPOSITED, LC_PROTO_ALL_PRIMS},
    {"style", "groundColor", COMPOSITED, LC_PROTO_ALL_PRIMS},
    {"style", "groundOffset", COMPOSITED, LC_PROTO_ALL_PRIMS},
    {"style", "smartTransparency", COMPOSITED, LC_PROTO_ALL_PRIMS},
    {"style", "smartIterations", COMPOSITED, LC_PROTO_ALL_PRIMS},
    {"style", NULL, DATASET_METHODS, LC_PROTO_ALL_PRIMS},
    {NULL, "filter", DATASET_METHODS, NOT_SURFACES},
    {"lines", NULL, DATASET_METHODS, P(LINES)},
    {"time", "markers", DATASET_METHODS, P(LINES)},
    {"time", NULL, DATASET_METHODS, NOT_SURFACES},
    {"surface", NULL, M(SURFACE_LAYERS), LC_PROTO_ALL_PRIMS},
    {"streamlines", NULL, DATASET_METHODS, P(LINES)}, /* the set a field's dataset traces (request_streamlines.c) */
};

/* Fields that apply under one value of another field (docs/ALGORITHM.md §12). */
static const struct {
    const char *section, *name, *when_path, *when_value;
} conditions[] = {
    {"params", "directExponent", "params.alphaSource", "importance"},
    {"params", "alphaConstant", "params.alphaSource", "constant"},
    {"params", "gamma", "params.alphaSource", "normalVariation"},
    {"streamlines", "separation", "streamlines.seeding", "density"},
};

int lc_proto_field_condition(const char *section, const char *name, const char **when_path, const char **when_value)
{
    for (size_t i = 0; i < sizeof conditions / sizeof conditions[0]; i++)
        if (section && strcmp(conditions[i].section, section) == 0 && strcmp(conditions[i].name, name) == 0) {
            *when_path = conditions[i].when_path, *when_value = conditions[i].when_value;
            return 1;
        }
    return 0;
}

static bool same(const char *a, const char *b) { return (a == NULL && b == NULL) || (a && b && strcmp(a, b) == 0); }

void lc_proto_field_scope(const char *section, const char *name, unsigned *methods, unsigned *prims)
{
    *methods = LC_PROTO_ALL_METHODS, *prims = LC_PROTO_ALL_PRIMS;
    for (size_t i = 0; i < sizeof rules / sizeof rules[0]; i++) {
        const scope_rule *r = &rules[i];
        if (same(r->section, section) && (r->name == NULL || strcmp(r->name, name) == 0)) {
            *methods = r->methods, *prims = r->prims;
            return;
        }
    }
}

const char *lc_proto_prim_name(int prim)
{
    static const char *const names[] = {
        [LC_PRIM_POINTS] = "points", [LC_PRIM_LINES] = "lines", [LC_PRIM_TRIANGLES] = "surfaces"};
    return prim >= 0 && prim < 3 ? names[prim] : "unknown";
}

/* The methods of mask as "fourier, exact or wboit". */
void lc_proto_method_list(unsigned mask, char *out, size_t size)
{
    out[0] = 0;
    int n = 0, total = __builtin_popcount(mask);
    for (int m = 0; m < LC_METHOD_COUNT; m++) {
        if (!(mask & (1u << m)))
            continue;
        size_t len = strlen(out);
        snprintf(out + len, size - len, "%s%s", n == 0 ? "" : n == total - 1 ? " or " : ", ", lc_method_name(m));
        n++;
    }
}
