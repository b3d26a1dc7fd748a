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
#define OPTIMIZED (M(FOURIER) | M(EXACT) | M(WBOIT))                /* P1-P3: the opacity optimization */
#define FOURIER_PASSES (M(FOURIER) | M(WBOIT))                      /* P1/P2 at resolutionScale */
#define SERIES (M(FOURIER) | M(DIRECT) | M(WBOIT))                  /* a Fourier transmittance in P4/P5 */
#define EQUALIZING (M(FOURIER) | M(DIRECT) | M(EXACT))              /* color.equalize's histogram */
#define NOT_SURFACES (P(POINTS) | P(LINES))

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
    {"params", "subset", SERIES, LC_PROTO_ALL_PRIMS},
    {"params", "resolutionScale", FOURIER_PASSES, LC_PROTO_ALL_PRIMS},
    {"params", "estimator", FOURIER_PASSES, LC_PROTO_ALL_PRIMS},
    {"params", "autoSubset", FOURIER_PASSES, LC_PROTO_ALL_PRIMS},
    {"params", "guardBand", FOURIER_PASSES, LC_PROTO_ALL_PRIMS},
    {"params", "directExponent", M(DIRECT), LC_PROTO_ALL_PRIMS},
    {"params", "excludeSelf", M(EXACT), LC_PROTO_ALL_PRIMS}, /* the exact sums know each fragment's element */
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
    {"style", NULL, DATASET_METHODS, LC_PROTO_ALL_PRIMS},
    {NULL, "filter", DATASET_METHODS, NOT_SURFACES},
    {"lines", NULL, DATASET_METHODS, P(LINES)},
    {"time", "markers", DATASET_METHODS, P(LINES)},
    {"time", NULL, DATASET_METHODS, NOT_SURFACES},
    {"surface", NULL, M(SURFACE_LAYERS), LC_PROTO_ALL_PRIMS},
};

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
