/* The render request's field table: every field's section, name, query
 * alias, type, bounds and place in lc_request; the one source of the request
 * schema, which request.c parses, checks, emits and prints. */
#include "request_table.h"

#include <stddef.h>

const enum_name lc_request_method_names[] = {{"fourier", LC_METHOD_FOURIER},
                                             {"exact", LC_METHOD_EXACT},
                                             {"opaque", LC_METHOD_OPAQUE},
                                             {"direct", LC_METHOD_DIRECT},
                                             {"wboit", LC_METHOD_WBOIT},
                                             {"surface-layers", LC_METHOD_SURFACE_LAYERS},
                                             {"weighted-average", LC_METHOD_WEIGHTED_AVERAGE},
                                             {"binning", LC_METHOD_BINNING},
                                             {"kanzler", LC_METHOD_KANZLER},
                                             {NULL, 0}};
static const enum_name format_names[] = {
    {"png", LC_FORMAT_PNG}, {"jpeg", LC_FORMAT_JPEG}, {"jpg", LC_FORMAT_JPEG}, {NULL, 0}};
static const enum_name normalize_names[] = {{"auto", LC_NORMALIZE_AUTO}, {"off", LC_NORMALIZE_OFF}, {NULL, 0}};
static const enum_name alpha_source_names[] = {{"importance", LC_ALPHA_IMPORTANCE},
                                               {"constant", LC_ALPHA_CONSTANT},
                                               {"angle", LC_ALPHA_ANGLE},
                                               {"normalVariation", LC_ALPHA_NORMAL_VARIATION},
                                               {NULL, 0}};
static const enum_name estimator_names[] = {{"foo", LC_ESTIMATOR_FOO}, {"midpoint", LC_ESTIMATOR_MIDPOINT}, {NULL, 0}};
static const enum_name depth_range_names[] = {{"auto", LC_DEPTH_RANGE_AUTO},
                                              {"global", LC_DEPTH_RANGE_GLOBAL},
                                              {"pixel", LC_DEPTH_RANGE_PIXEL},
                                              {"moments", LC_DEPTH_RANGE_MOMENTS},
                                              {NULL, 0}};
static const enum_name smoothing_weights_names[] = {
    {"uniform", LC_SMOOTHING_UNIFORM}, {"distance", LC_SMOOTHING_DISTANCE}, {NULL, 0}};
static const enum_name shading_names[] = {{"phong", LC_SHADING_PHONG}, {"none", LC_SHADING_NONE}, {NULL, 0}};
static const enum_name ground_names[] = {
    {"auto", LC_GROUND_AUTO}, {"on", LC_GROUND_ON}, {"off", LC_GROUND_OFF}, {NULL, 0}};
static const enum_name representative_names[] = {{"important", 0}, {"mean", 1}, {"leastDistance", 2}, {NULL, 0}};
static const enum_name composite_names[] = {{"layers", LC_SURFACE_LAYERS},
                                            {"weighted-average", LC_SURFACE_WEIGHTED_AVERAGE},
                                            {"weighted-sum", LC_SURFACE_WEIGHTED_SUM},
                                            {NULL, 0}};
static const enum_name direction_names[] = {{"forward", 0}, {"backward", 1}, {"both", 2}, {NULL, 0}};
static const enum_name seeding_names[] = {{"points", 0}, {"rake", 1}, {"box", 2}, {"density", 3}, {NULL, 0}};
static const enum_name linkage_names[] = {{"complete", 0}, {"single", 1}, {"average", 2}, {NULL, 0}};
#define COLORMAP_ENUM_NAME(n) {#n, 0},
static const enum_name colormap_names[] = {LC_COLORMAP_LIST(COLORMAP_ENUM_NAME){NULL, 0}};
#undef COLORMAP_ENUM_NAME

#define OFF(member) offsetof(lc_request, member)
#define NOFLAG (-1L)
/* A ribbon wider than 1e9 world units covers any data that float positions
 * resolve at that scale; beyond, the width overflows the cost model and the
 * shaders' float half-width. */
#define LINE_WIDTH_MAX 1e9
/* Caps beyond the useful ranges (q, r, λ, exponents, dt) keep values in float
 * range for the shaders; the documented ranges in README.md match. */
const field lc_request_fields[] = {
    {NULL, "version", "version", T_INT, 1, 1, CHECK_ONLY, 0, 0, NOFLAG, NULL},
    {NULL, "dataset", "dataset", T_STR, 0, 0, 0, OFF(dataset), LC_PROTO_DATASET_LEN, NOFLAG, NULL},
    {NULL, "width", "width", T_INT, 0, 0, SIZE_LIMIT, OFF(render.width), 0, NOFLAG, NULL},
    {NULL, "height", "height", T_INT, 0, 0, SIZE_LIMIT, OFF(render.height), 0, NOFLAG, NULL},
    {NULL, "method", "method", T_ENUM, 0, 0, 0, OFF(render.method), 0, NOFLAG, lc_request_method_names},
    {NULL, "format", "format", T_ENUM, 0, 0, 0, OFF(format), 0, NOFLAG, format_names},
    {NULL, "quality", "quality", T_INT, 1, 100, 0, OFF(quality), 0, NOFLAG, NULL},
    {NULL, "dt", "dt", T_NUM, 0, 3600, 0, OFF(dt), 0, (long)OFF(has_dt), NULL},

    {"camera", "position", "position", T_VEC3, 0, 0, 0, OFF(render.camera.position), 0, NOFLAG, NULL},
    {"camera", "focalPoint", "focalPoint", T_VEC3, 0, 0, 0, OFF(render.camera.focal_point), 0, NOFLAG, NULL},
    {"camera", "viewUp", "viewUp", T_VEC3, 0, 0, 0, OFF(render.camera.view_up), 0, NOFLAG, NULL},
    {"camera", "viewAngle", "viewAngle", T_NUM, 0, 180, LO_OPEN | HI_OPEN, OFF(render.camera.view_angle), 0, NOFLAG,
     NULL},
    {"camera", "parallelProjection", "parallelProjection", T_BOOL, 0, 0, 0, OFF(render.camera.parallel_projection), 0,
     NOFLAG, NULL},
    {"camera", "parallelScale", "parallelScale", T_NUM, 0, BIG, LO_OPEN, OFF(render.camera.parallel_scale), 0, NOFLAG,
     NULL},

    {"params", "q", "q", T_NUM, 0, 1e6, ALWAYS_EMIT, OFF(render.foo.q), 0, (long)OFF(render.foo.strength_given), NULL},
    {"params", "r", "r", T_NUM, 0, 1e6, ALWAYS_EMIT, OFF(render.foo.r), 0, (long)OFF(render.foo.strength_given), NULL},
    {"params", "lambda", "lambda", T_NUM, 0, 1000, ALWAYS_EMIT, OFF(render.foo.lambda), 0,
     (long)OFF(render.foo.strength_given), NULL},
    {"params", "bands", "bands", T_INT, LC_MIN_BANDS, LC_MAX_BANDS, 0, OFF(render.foo.bands), 0, NOFLAG, NULL},
    {"params", "smoothing", "smoothing", T_INT, 0, 1000, 0, OFF(render.foo.smoothing), 0, NOFLAG, NULL},
    {"params", "smoothingWeight", "smoothingWeight", T_NUM, 0, 1, 0, OFF(render.foo.smoothing_weight), 0, NOFLAG, NULL},
    {"params", "fadeHalfLife", "fadeHalfLife", T_NUM, 0, 60, 0, OFF(render.foo.fade_half_life), 0, NOFLAG, NULL},
    {"params", "resolutionScale", "resolutionScale", T_NUM, 0, 1, LO_OPEN, OFF(render.foo.resolution_scale), 0, NOFLAG,
     NULL},
    {"params", "subset", "subset", T_INT, 1, 1024, 0, OFF(render.foo.subset), 0, NOFLAG, NULL},
    {"params", "depthMargin", "depthMargin", T_NUM, 0, 0.25, 0, OFF(render.foo.depth_margin), 0, NOFLAG, NULL},
    {"params", "estimator", "estimator", T_ENUM, 0, 0, 0, OFF(render.foo.estimator), 0, NOFLAG, estimator_names},
    {"params", "depthRange", "depthRange", T_ENUM, 0, 0, 0, OFF(render.foo.depth_range), 0, NOFLAG, depth_range_names},
    {"params", "normalize", "normalize", T_ENUM, 0, 0, 0, OFF(render.foo.normalize), 0, NOFLAG, normalize_names},
    {"params", "lod", "lod", T_NUM, 0, 16, 0, OFF(render.detail.lod_pixels), 0, NOFLAG, NULL},
    {"params", "directExponent", "directExponent", T_NUM, 0, 100, LO_OPEN, OFF(render.foo.direct_exponent), 0, NOFLAG,
     NULL},
    /* The direct method's opacity source: the local transparency baselines (OOS §2.1) */
    {"params", "alphaSource", "alphaSource", T_ENUM, 0, 0, 0, OFF(render.foo.alpha_source), 0, NOFLAG,
     alpha_source_names},
    {"params", "alphaConstant", "alphaConstant", T_NUM, 0, 1, 0, OFF(render.foo.alpha_constant), 0, NOFLAG, NULL},
    {"params", "gamma", "gamma", T_NUM, 0, 100, LO_OPEN, OFF(render.foo.gamma), 0, NOFLAG, NULL},
    /* method "kanzler": the weights of Kanzler's occlusion penalty (render/gl/kanzler.c) */
    {"params", "kanzlerImportance", "kanzlerImportance", T_NUM, 0, 1000, 0, OFF(render.foo.kanzler_importance), 0,
     NOFLAG, NULL},
    {"params", "kanzlerCoverage", "kanzlerCoverage", T_NUM, 0, 1000, 0, OFF(render.foo.kanzler_coverage), 0, NOFLAG,
     NULL},
    {"params", "kanzlerVariance", "kanzlerVariance", T_NUM, 0, 1000, 0, OFF(render.foo.kanzler_variance), 0, NOFLAG,
     NULL},
    {"params", "kanzlerDepth", "kanzlerDepth", T_NUM, 0, 1000, 0, OFF(render.foo.kanzler_depth), 0, NOFLAG, NULL},
    {"params", "kanzlerLambda", "kanzlerLambda", T_NUM, 0, 1000, 0, OFF(render.foo.kanzler_lambda), 0, NOFLAG, NULL},
    {"params", "targetOpacity", "targetOpacity", T_NUM, 0, 1, LO_OPEN, OFF(render.foo.target_opacity), 0, NOFLAG, NULL},
    {"params", "smoothingWeights", "smoothingWeights", T_ENUM, 0, 0, 0, OFF(render.foo.smoothing_weights), 0, NOFLAG,
     smoothing_weights_names},
    {"params", "guardBand", "guardBand", T_NUM, 0, 1, 0, OFF(render.foo.guard_band), 0, NOFLAG, NULL},
    /* params.clarity: the loop on the optimization's strength (render/gl/clarity.c) */
    {"params", "clarity", "clarity", T_NUM, 0, 1, 0, OFF(render.foo.clarity), 0, NOFLAG, NULL},
    /* params.autoSubset: P1's stride from P0's measured density (render/gl/fourier.c) */
    {"params", "autoSubset", "autoSubset", T_INT, 1, 64, 0, OFF(render.foo.auto_subset), 0, NOFLAG, NULL},
    /* params.progressive: a still in batches added to kept sums (render/gl/progressive.c) */
    {"params", "progressive", "progressive", T_INT, 1, 256, 0, OFF(render.foo.progressive), 0, NOFLAG, NULL},
    /* params.excludeSelf: no self-occlusion in the exact sums (render/gl/shaders/exact_opacity.comp.glsl) */
    {"params", "excludeSelf", "excludeSelf", T_BOOL, 0, 0, 0, OFF(render.foo.exclude_self), 0, NOFLAG, NULL},

    {"importance", "attribute", "importance", T_STR, 0, 0, 0, OFF(render.importance.attribute), LC_NAME_LEN, NOFLAG,
     NULL},
    {"importance", "range", "importanceRange", T_RANGE, 0, 0, 0, OFF(render.importance.range), 0,
     (long)OFF(render.importance.has_range), NULL},
    {"importance", "exponent", "importanceExponent", T_NUM, 0, 1000, LO_OPEN, OFF(render.importance.exponent), 0,
     NOFLAG, NULL},
    {"importance", "terms", "importanceTerms", T_TERMS, 0, LC_MAX_IMPORTANCE_TERMS, 0, OFF(render.importance), 0,
     NOFLAG, NULL},
    {"importance", "curve", "importanceCurve", T_CURVE, 0, LC_MAX_CURVE_POINTS, 0, OFF(render.importance.curve), 0,
     NOFLAG, NULL},
    {"importance", "invert", "importanceInvert", T_BOOL, 0, 0, 0, OFF(render.importance.invert), 0, NOFLAG, NULL},

    {"color", "attribute", "color", T_STR, 0, 0, 0, OFF(render.color.attribute), LC_NAME_LEN, NOFLAG, NULL},
    {"color", "colormap", "colormap", T_NAME, 0, 0, 0, OFF(render.color.colormap), LC_NAME_LEN, NOFLAG, colormap_names},
    {"color", "range", "colorRange", T_RANGE, 0, 0, 0, OFF(render.color.range), 0, (long)OFF(render.color.has_range),
     NULL},
    {"color", "curve", "colorCurve", T_CURVE, 0, LC_MAX_CURVE_POINTS, 0, OFF(render.color.curve), 0, NOFLAG, NULL},
    {"color", "equalize", "equalize", T_BOOL, 0, 0, 0, OFF(render.color.equalize), 0, NOFLAG, NULL},
    {"color", "fixed", "colorFixed", T_RANGES, 0, LC_MAX_COLOR_FIXED, 0, OFF(render.color), 0, NOFLAG, NULL},
    {"color", "fadeHalfLife", "colorFadeHalfLife", T_NUM, 0, 60, 0, OFF(render.color.fade_half_life), 0, NOFLAG, NULL},

    {"style", "background", "background", T_COLOR, 0, 0, 0, OFF(render.style.background), 0, NOFLAG, NULL},
    {"style", "lineWidth", "lineWidth", T_NUM, 0, LINE_WIDTH_MAX, 0, OFF(render.style.line_width), 0, NOFLAG, NULL},
    {"style", "minLinePixels", "minLinePixels", T_NUM, 0, 64, 0, OFF(render.style.min_line_pixels), 0, NOFLAG, NULL},
    {"style", "pointSize", "pointSize", T_NUM, 0, 256, LO_OPEN, OFF(render.style.point_size), 0, NOFLAG, NULL},
    {"style", "shading", "shading", T_ENUM, 0, 0, 0, OFF(render.style.shading), 0, NOFLAG, shading_names},
    {"style", "silhouetteExponent", "silhouetteExponent", T_NUM, 1, 100, 0, OFF(render.style.silhouette_exponent), 0,
     NOFLAG, NULL},
    {"style", "haloWidth", "haloWidth", T_NUM, 0, 64, 0, OFF(render.style.halo_width), 0, NOFLAG, NULL},
    {"style", "haloDepth", "haloDepth", T_NUM, 0, 1, 0, OFF(render.style.halo_depth), 0, NOFLAG, NULL},
    {"style", "haloStrength", "haloStrength", T_NUM, 0, 1, 0, OFF(render.style.halo_strength), 0, NOFLAG, NULL},
    {"style", "antialias", "antialias", T_INT, 1, LC_MAX_ANTIALIAS, 0, OFF(render.style.antialias), 0, NOFLAG, NULL},
    {"style", "shadow", "shadow", T_NUM, 0, 1, 0, OFF(render.style.shadow), 0, NOFLAG, NULL},
    {"style", "shadowLight", "shadowLight", T_VEC3, 0, 0, 0, OFF(render.style.shadow_light), 0, NOFLAG, NULL},
    {"style", "shadowColored", "shadowColored", T_BOOL, 0, 0, 0, OFF(render.style.shadow_colored), 0, NOFLAG, NULL},
    {"style", "ground", "ground", T_ENUM, 0, 0, 0, OFF(render.style.ground), 0, NOFLAG, ground_names},
    {"style", "groundColor", "groundColor", T_COLOR, 0, 0, 0, OFF(render.style.ground_color), 0, NOFLAG, NULL},
    {"style", "groundOffset", "groundOffset", T_NUM, 0, 1, 0, OFF(render.style.ground_offset), 0, NOFLAG, NULL},
    {"style", "smartTransparency", "smartTransparency", T_NUM, 0, 1, 0, OFF(render.style.smart), 0, NOFLAG, NULL},
    {"style", "smartIterations", "smartIterations", T_INT, 0, LC_MAX_SMART_ITERATIONS, 0,
     OFF(render.style.smart_iterations), 0, NOFLAG, NULL},

    {NULL, "filter", "filter", T_FILTERS, 0, LC_MAX_FILTERS, 0, OFF(render), 0, NOFLAG, NULL},

    {"lines", "clusters", "clusters", T_INT, 0, 1000000, 0, OFF(render.clusters.count), 0, NOFLAG, NULL},
    {"lines", "representative", "representative", T_ENUM, 0, 0, 0, OFF(render.clusters.representative), 0, NOFLAG,
     representative_names},
    {"lines", "linkage", "linkage", T_ENUM, 0, 0, 0, OFF(render.clusters.linkage), 0, NOFLAG, linkage_names},
    {"lines", "liftImportance", "liftImportance", T_NUM, 0, 1000, 0, OFF(render.clusters.lift_importance), 0, NOFLAG,
     NULL},
    {"lines", "liftColor", "liftColor", T_NUM, 0, 1000, 0, OFF(render.clusters.lift_color), 0, NOFLAG, NULL},

    {NULL, "layers", "layers", T_LAYERS, 0, LC_MAX_LAYERS, 0, OFF(layers), 0, NOFLAG, NULL},

    {"time", "window", "timeWindow", T_RANGE, 0, 0, 0, OFF(render.time.window), 0, (long)OFF(render.time.has_window),
     NULL},
    {"time", "attribute", "timeAttribute", T_STR, 0, 0, 0, OFF(render.time.attribute), LC_NAME_LEN, NOFLAG, NULL},
    {"time", "markers", "timeMarkers", T_BOOL, 0, 0, 0, OFF(render.time.markers), 0, NOFLAG, NULL},

    /* surface: method "surface-layers" (a field's integral surface) */
    {"surface", "field", "surfaceField", T_STR, 0, 0, 0, OFF(surface.field), sizeof(((lc_request *)0)->surface.field),
     NOFLAG, NULL},
    {"surface", "seed", "surfaceSeed", T_SEED, 2, LC_SURFACE_SEED_MAX, 0, OFF(surface.seed_count), OFF(surface.seed),
     NOFLAG, NULL},
    {"surface", "particles", "surfaceParticles", T_INT, 1, 100000, 0, OFF(surface.particles), 0, NOFLAG, NULL},
    {"surface", "step", "surfaceStep", T_NUM, 0, BIG, 0, OFF(surface.step), 0, NOFLAG, NULL},
    {"surface", "length", "surfaceLength", T_NUM, 0, BIG, 0, OFF(surface.length), 0, NOFLAG, NULL},
    {"surface", "direction", "surfaceDirection", T_ENUM, 0, 0, 0, OFF(surface.direction), 0, NOFLAG, direction_names},
    {"surface", "epsilon", "surfaceEpsilon", T_NUM, 0, 1, 0, OFF(surface.epsilon), 0, NOFLAG, NULL},
    {"surface", "opacity", "surfaceOpacity", T_NUM, 0, 1, LO_OPEN, OFF(surface.opacity), 0, NOFLAG, NULL},
    {"surface", "maxLayers", "surfaceMaxLayers", T_INT, 1, 64, 0, OFF(surface.max_layers), 0, NOFLAG, NULL},
    {"surface", "composite", "surfaceComposite", T_ENUM, 0, 0, 0, OFF(surface.composite), 0, NOFLAG, composite_names},
    {"surface", "color", "surfaceColor", T_COLOR, 0, 0, 0, OFF(surface.color), 0, NOFLAG, NULL},
    {"surface", "curvesPerFrame", "surfaceCurvesPerFrame", T_INT, 1, 100000, 0, OFF(surface.curves_per_frame), 0,
     NOFLAG, NULL},

    /* streamlines: a dataset that names a vector field, traced as a streamline set (docs/ALGORITHM.md §22) */
    {"streamlines", "seeding", "streamlinesSeeding", T_ENUM, 0, 0, 0, OFF(streamlines.seeding), 0, NOFLAG,
     seeding_names},
    {"streamlines", "seeds", "streamlinesSeeds", T_SEED, 1, LC_STREAMLINES_SEEDS_MAX, 0, OFF(streamlines.seed_count),
     OFF(streamlines.seeds), NOFLAG, NULL},
    {"streamlines", "count", "streamlinesCount", T_INT, 1, 100000, 0, OFF(streamlines.count), 0,
     (long)OFF(streamlines.has_count), NULL},
    {"streamlines", "step", "streamlinesStep", T_NUM, 0, BIG, 0, OFF(streamlines.step), 0, NOFLAG, NULL},
    {"streamlines", "length", "streamlinesLength", T_NUM, 0, BIG, 0, OFF(streamlines.length), 0, NOFLAG, NULL},
    {"streamlines", "direction", "streamlinesDirection", T_ENUM, 0, 0, 0, OFF(streamlines.direction), 0, NOFLAG,
     direction_names},
    {"streamlines", "separation", "streamlinesSeparation", T_NUM, 0, BIG, 0, OFF(streamlines.separation), 0, NOFLAG,
     NULL},
};
const size_t lc_request_nfields = sizeof lc_request_fields / sizeof lc_request_fields[0];

const char *const lc_request_sections[] = {"camera", "params", "importance", "color",      "style",
                                           "lines",  "time",   "surface",    "streamlines"};
const size_t lc_request_nsections = sizeof lc_request_sections / sizeof lc_request_sections[0];
