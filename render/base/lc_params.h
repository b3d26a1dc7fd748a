/* Plain-data parameter types of a render: camera, FOO parameters, mapping and
 * style. No GL here: protocol/ includes this header to parse requests into it. */
#ifndef LC_PARAMS_H
#define LC_PARAMS_H

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LC_NAME_LEN 64
#define LC_MAX_BANDS 8
#define LC_MIN_BANDS 1
#define LC_AUTO_SUBSET_DEFAULT 1 /* params.autoSubset: P1's largest automatic stride (1 = off) */

/* What a dataset is made of. */
typedef enum { LC_PRIM_POINTS = 0, LC_PRIM_LINES = 1, LC_PRIM_TRIANGLES = 2 } lc_prim_type;

typedef enum {
    LC_METHOD_FOURIER = 0, /* FOO, passes P1..P6 */
    LC_METHOD_EXACT,       /* per-pixel linked lists (DOO reference) */
    LC_METHOD_OPAQUE,      /* depth-tested opaque geometry */
    LC_METHOD_DIRECT,      /* alpha = g^k, order-independent weighted blend */
    LC_METHOD_WBOIT,       /* McGuire & Bavoil 2013 with the FOO opacities */
    /* A vector field's integral surface (the request's surface object,
     * render/gl/surface_render.c), not a dataset's elements: lc_render_frame refuses it. */
    LC_METHOD_SURFACE_LAYERS,
    LC_METHOD_WEIGHTED_AVERAGE, /* Bavoil & Myers 2008 with the FOO opacities */
    LC_METHOD_BINNING,          /* tau(d) in 11 depth bins (FOO §5.3) with the FOO opacities */
    /* alpha = g^k times Kanzler's occlusion penalty on the view-dependent
     * per-pixel maps (render/gl/kanzler.c; docs/ALGORITHM.md §28) */
    LC_METHOD_KANZLER,
    LC_METHOD_COUNT
} lc_method;

typedef enum { LC_ESTIMATOR_FOO = 0, LC_ESTIMATOR_MIDPOINT = 1 } lc_estimator;

/* Depth normalization (docs/ALGORITHM.md "Depth normalization"): the view-space
 * depth range of the data bounds this frame; each pixel's own min/max fragment
 * depth (one extra geometry pass at each resolution); or the data bounds'
 * range warped per pixel around the mean and spread of its importance mass
 * (one extra geometry pass at the optimization resolution; the Fourier and
 * binning methods). Auto (the default) is moments with density normalization and the
 * bounds with the paper's formula (normalize "off"), so "off" stays the paper's. */
typedef enum {
    LC_DEPTH_RANGE_GLOBAL = 0,
    LC_DEPTH_RANGE_PIXEL = 1,
    LC_DEPTH_RANGE_MOMENTS = 2,
    LC_DEPTH_RANGE_AUTO = 3
} lc_depth_range;
/* The direct method's fragment opacity (params.alphaSource; docs/ALGORITHM.md
 * §12): importance g^k, or the local transparency baselines of OOS §2.1. */
typedef enum {
    LC_ALPHA_IMPORTANCE = 0,      /* g^k, params.directExponent */
    LC_ALPHA_CONSTANT = 1,        /* params.alphaConstant */
    LC_ALPHA_ANGLE = 2,           /* (2/pi) arccos |<n, v>| */
    LC_ALPHA_NORMAL_VARIATION = 3 /* ((d n_z/du)^2 + (d n_z/dv)^2)^(gamma/2), per pixel */
} lc_alpha_source;
/* Density-aware opacity (docs/ALGORITHM.md "Density normalization"): auto
 * scales a pixel's front and behind sums down where its importance mass
 * exceeds a reference, raises the emphasis there, and maps importance from the
 * attribute's auto range (min/max without outliers) when the request gives no
 * range; off is the paper's formula with min/max. */
typedef enum { LC_NORMALIZE_AUTO = 0, LC_NORMALIZE_OFF = 1 } lc_normalize;

/* Neighbour weights of the smoothing (P3): the plain mean (the papers' FOO and
 * DOO), or d^-2 of the element centres' distance normalized over the
 * neighbours (OOS §4.3; docs/ALGORITHM.md "Perception aids"). */
typedef enum { LC_SMOOTHING_UNIFORM = 0, LC_SMOOTHING_DISTANCE = 1 } lc_smoothing_weights;

/* Margin used with the per-pixel range instead of depth_margin (gl/pipeline.c). */
#define LC_PIXEL_DEPTH_MARGIN 0.25

/* The colormaps a request may name, in the one order every layer uses
 * (image/colormap.c has a table for each; the web client's schema and
 * protocol/openapi.yaml list them in this order, which a test checks). */
#define LC_COLORMAP_LIST(X) X(viridis) X(coolwarm) X(grayscale) X(inferno) X(plasma) X(turbo)
#define LC_COLORMAP_NAME_ENTRY(n) #n,
enum { LC_COLORMAP_COUNT = sizeof((const char *[]){LC_COLORMAP_LIST(LC_COLORMAP_NAME_ENTRY)}) / sizeof(const char *) };
/* LC_COLORMAP_COUNT names and a NULL. */
extern const char *const lc_colormap_names[];

typedef enum { LC_SHADING_PHONG = 0, LC_SHADING_NONE = 1 } lc_shading;

typedef enum { LC_FORMAT_PNG = 0, LC_FORMAT_JPEG = 1 } lc_image_format;

/* ParaView/VTK camera names. viewAngle in degrees (vertical field of view). */
typedef struct lc_camera {
    double position[3];
    double focal_point[3];
    double view_up[3];
    double view_angle;
    bool parallel_projection;
    double parallel_scale; /* half the view height in world units (VTK) */
} lc_camera;

/* Fourier opacity optimization parameters (docs/ALGORITHM.md). */
typedef struct lc_foo_params {
    double q;                /* weight of importance behind a fragment */
    double r;                /* weight of importance in front of a fragment */
    double lambda;           /* importance emphasis exponent */
    int bands;               /* m, 1..8 */
    int smoothing;           /* s, Laplacian iterations */
    double smoothing_weight; /* omega */
    double fade_half_life;   /* seconds; 0 = no fading */
    double resolution_scale; /* P1/P2 resolution relative to output, (0,1] */
    int subset;              /* P1/P4 use every n-th primitive, weights x n */
    double depth_margin;     /* delta (the bounds' depth range and the moments) */
    lc_estimator estimator;
    lc_depth_range depth_range;   /* as requested; lc_foo_depth_range resolves auto */
    double direct_exponent;       /* k of the "direct" baseline, alpha = g^k (and of "kanzler") */
    lc_alpha_source alpha_source; /* the direct baseline's opacity; importance = g^k */
    double alpha_constant;        /* alpha of alphaSource constant */
    double gamma;                 /* exponent of alphaSource normalVariation */
    /* Method "kanzler" (M3D Eq. 3.2-3.3): rho = 1/(1 + (1 - g^lambda) P),
     * P = m M + c C + v V + d less(i, D) on the per-pixel maps. */
    double kanzler_importance; /* m: weight of the maximum importance M */
    double kanzler_coverage;   /* c: weight of the coverage C (fragments in the pixel) */
    double kanzler_variance;   /* v: weight of the directional variance V */
    double kanzler_depth;      /* d: weight of less(i, D), the fragment in front of M's depth */
    double kanzler_lambda;     /* lambda: how little the penalty touches important fragments */
    lc_normalize normalize;
    /* Perception aids (docs/ALGORITHM.md "Perception aids"): */
    double target_opacity; /* t of OOS Eq. 7, alpha = t / (1 + ...); (0, 1], 0 = 1 (lc_foo_target_opacity) */
    lc_smoothing_weights smoothing_weights;
    double guard_band; /* P0 moments-P2 see this fraction of the view more on each side; 0 = none */
    /* params.clarity (docs/ALGORITHM.md §25): the top decile's target opacity
     * of the loop on the emphasis; 0 = off. It acts only while q, r and λ are
     * the defaults, not given by the request (strength_given). */
    double clarity;
    /* params.autoSubset (docs/ALGORITHM.md §10): the largest stride P1 may
     * draw with where P0 measured dense data; 1 = P1 draws what params.subset says. */
    int auto_subset;
    /* params.excludeSelf (OOS §4.3, exact method only): a fragment's sums of
     * Eq. 10 leave out its own element's fragments. */
    bool exclude_self;
    /* params.progressive (docs/ALGORITHM.md §34, render/gl/progressive.c):
     * a still drawn in this many batches of the primitives, one a frame, each
     * added to the sums kept from the batches before; 0 or 1 = one frame. */
    int progressive;
    /* Set by the caller per frame, never parsed: the batch this frame adds
     * (1 .. progressive), 0 = every batch in one call (the image is the last
     * batch's); with batch_prefix, a one-shot frame of batches 1 .. batch
     * alone (the reference the progressive frames are measured against). */
    int batch;
    bool batch_prefix;
    bool strength_given;
    /* Set by the clarity loop only (render/gl/clarity.c), never parsed: lines
     * take their elements' mean importance in the emphasis, as patches do. */
    bool element_emphasis;
} lc_foo_params;

/* One weighted criterion of the importance (docs/ALGORITHM.md "Importance
 * terms", Met.3D's importance section): t = clamp((v - min)/(max - min)),
 * 1 - t when inverted, weighted in [-1, 1]. */
#define LC_MAX_IMPORTANCE_TERMS 4
typedef struct lc_importance_term {
    char attribute[LC_NAME_LEN];
    double range[2];
    bool has_range; /* false: the attribute's range as the single form picks it */
    double weight;  /* [-1, 1] */
    bool invert;
} lc_importance_term;

/* Transfer-function curves: piecewise linear through up to LC_MAX_CURVE_POINTS
 * (x, y) points with increasing x in [0, 1]; no points = identity. */
#define LC_MAX_CURVE_POINTS 64
typedef struct lc_curve {
    int count;
    double points[LC_MAX_CURVE_POINTS][2];
} lc_curve;

/* Importance g from an attribute: g = clamp((v - min)/(max - min))^exponent.
 * min > max inverts. With terms, the terms replace the attribute and range. */
typedef struct lc_importance_map {
    char attribute[LC_NAME_LEN]; /* "" = dataset default */
    double range[2];
    bool has_range; /* false = the attribute's own min/max */
    double exponent;
    int term_count; /* 0: the single form above */
    lc_importance_term terms[LC_MAX_IMPORTANCE_TERMS];
    lc_curve curve; /* transfer function of clamp(t) before the exponent; no points = identity */
    bool invert;    /* g of 1 - the mapped value: smaller values matter more (the range stays as given) */
} lc_importance_map;

/* Hard filters (docs/ALGORITHM.md "Filters"): a line (or, for points, a point)
 * draws only where every filter holds. A line filter tests a statistic of the
 * attribute over the line's vertices. */
#define LC_MAX_FILTERS 8
typedef enum {
    LC_FILTER_VERTEX = 0, /* points: the point's own value */
    LC_FILTER_MIN,
    LC_FILTER_MAX,
    LC_FILTER_MEAN,
    LC_FILTER_FIRST,
    LC_FILTER_LAST,
    LC_FILTER_CHANGE, /* last - first */
    LC_FILTER_OVER_COUNT
} lc_filter_over;
typedef struct lc_filter {
    char attribute[LC_NAME_LEN];
    lc_filter_over over;
    double lo, hi;         /* the value must lie in [lo, hi] ... */
    bool lo_open, hi_open; /* ... or (lo, ...) / (..., hi) */
} lc_filter;

/* Time windows (docs/ALGORITHM.md "Time windows"): on lines whose vertices
 * carry a time, only the segments whose two vertices lie in [t0, t1] draw and
 * count; a vertex-level filter on the time attribute. */
typedef struct lc_time_window {
    bool has_window;             /* false: no window, every segment */
    double window[2];            /* [t0, t1], inclusive */
    char attribute[LC_NAME_LEN]; /* "": time, t, frame or timestep */
    bool markers;                /* a splat at each line's position at t1 (docs/ALGORITHM.md §26) */
} lc_time_window;

#define LC_MAX_COLOR_FIXED 4
typedef struct lc_color_map {
    char attribute[LC_NAME_LEN]; /* "importance", "rgb", an attribute, "" = default */
    char colormap[LC_NAME_LEN];  /* "viridis", "coolwarm", "grayscale", ... */
    double range[2];
    bool has_range;
    lc_curve curve; /* transfer function of the colormap coordinate; no points = identity */
    /* View-dependent colour equalization (docs/ALGORITHM.md §19): */
    bool equalize;   /* the colormap follows the visible colour values' CDF */
    int fixed_count; /* ranges kept as the identity, data units */
    double fixed[LC_MAX_COLOR_FIXED][2];
    double fade_half_life; /* seconds: sessions' CDF approaches the frame's (DLS Eq. 10) */
} lc_color_map;

typedef enum { LC_GROUND_AUTO = 0, LC_GROUND_ON, LC_GROUND_OFF } lc_ground;

typedef struct lc_style {
    double background[3];
    double line_width;      /* world units */
    double min_line_pixels; /* ribbons never thinner than this many pixels */
    double point_size;      /* pixels at output resolution */
    lc_shading shading;
    /* Perception aids (docs/ALGORITHM.md "Perception aids"); 0 = off: */
    double silhouette_exponent; /* eta of OOS Eq. 8 on surfaces; <= 1 = off */
    double halo_width;          /* depth-dependent halos beside line ribbons, output pixels */
    double halo_depth;          /* their depth offset at the ribbon's edge, fraction of the data's diagonal */
    double halo_strength;       /* their opacity, [0, 1] */
    int antialias;              /* still frames: K jittered compositing samples averaged; <= 1 = one */
    /* Ground shadows (docs/ALGORITHM.md §29): the context receives the
     * transmittance of the transparent layers from a directional light. */
    double shadow;          /* the shadow's opacity s in [0, 1]; 0 = off */
    double shadow_light[3]; /* toward the light (the ground faces it); 0: the suggested view's up, else +Y */
    bool shadow_colored;    /* tinted by the occluders' colour instead of grey */
    lc_ground ground;       /* the ground plane: LC_GROUND_AUTO draws it for shadows without a context layer */
    double ground_color[3]; /* its (unlit) colour */
    double ground_offset;   /* its distance beyond the data along the light, fraction of the data's diagonal */
    /* Smart transparency (docs/ALGORITHM.md §29, after Carnecky et al.): */
    double smart;         /* strength of the silhouettes and halos in [0, 1]; 0 = off */
    int smart_iterations; /* diffusion steps (each spreads them one pixel) */
} lc_style;
#define LC_MAX_SMART_ITERATIONS 32
#define LC_MAX_ANTIALIAS 16

/* Level of detail and the shortcuts of interactive frames (docs/ALGORITHM.md
 * "Level of detail"). Only lod_pixels is a request field; a session sets the
 * others on the frames it renders while the camera moves. */
#define LC_DEFAULT_LOD_PIXELS 0.2
/* params.clarity by default: the most important tenth at least half opaque
 * (chosen on the corpus, docs/EVALUATION.md "Density normalization"). */
#define LC_DEFAULT_CLARITY 0.5
#define LC_LINE_SUBSET_FLOOR 4096
#define LC_LINE_SUBSET_PIXELS 8
#define LC_POINT_SUBSET_FLOOR 4096
#define LC_POINT_SUBSET_PIXELS 8
typedef struct lc_detail {
    double lod_pixels;    /* lines: largest screen error of the simplified polylines, output pixels; 0 = full */
    int point_stride;     /* points: one point in n in every pass, weighted n in P0/P1/P4 (a frame drawn smaller
                             than its view spreads the splats instead, lc_point_splat); <= 1 = all. Halved
                             until the frame keeps a point per LC_POINT_SUBSET_PIXELS pixels and at least
                             LC_POINT_SUBSET_FLOOR points: small clouds are not thinned. */
    bool uniform_points;  /* with a stride: thin the important points too (default: keep them, point_subset.c) */
    int line_stride;      /* lines, frames with a frame state's opacities: one in n of the lines beside the most
                             important in full, weighted n in P1/P4 (line_subset.c); <= 1 = all. Halved until
                             the frame keeps a segment per LC_LINE_SUBSET_PIXELS pixels and at least
                             LC_LINE_SUBSET_FLOOR segments: sparse lines are not thinned. */
    bool reuse_opacities; /* skip P1-P3: draw with the frame state's opacities when it has them */
    bool still;           /* a session's still: optimized as a one-shot render of its request is (the clarity
                             loop from the paper's strength, targets taken whole), whatever frames came before */
    double pixel_scale;   /* a frame drawn at a fraction of its view's size (a moving frame): that fraction, so
                             that sizes given in the view's pixels (time markers, point splats) keep their size;
                             0 = 1 */
} lc_detail;

/* Line clustering (docs/ALGORITHM.md "Line clustering"): count 0 = off;
 * representative and linkage take the values of lc_representative and
 * lc_linkage (render/scene/cluster.h). */
typedef struct lc_line_cluster_params {
    int count;
    int representative; /* 0 most important, 1 mean line, 2 least total distance */
    int linkage;        /* 0 complete, 1 single, 2 average */
    double lift_importance, lift_color;
} lc_line_cluster_params;

/* Everything a renderer needs for one frame besides the data and the state. */
typedef struct lc_render_params {
    int width, height;
    lc_method method;
    bool has_camera; /* false: fit the data */
    lc_camera camera;
    lc_foo_params foo;
    lc_importance_map importance;
    lc_color_map color;
    lc_style style;
    lc_detail detail;
    int filter_count;
    lc_filter filters[LC_MAX_FILTERS];
    lc_line_cluster_params clusters;
    lc_time_window time;
} lc_render_params;

/* Layers (docs/ALGORITHM.md "Layers"): a scene of several datasets in one
 * view. Each transparent layer adds its fragments into the frame's one
 * optimization (one G(d), one tau(d)) with its own mapping and style; its
 * element ids follow those of the layers before it, and smoothing stays
 * inside a layer. The frame's lc_render_params give everything else (size,
 * camera, FOO parameters, background, perception aids). */
#define LC_MAX_LAYERS 8
typedef enum {
    LC_LAYER_TRANSPARENT = 0, /* in the optimization */
    LC_LAYER_CONTEXT          /* opaque, shaded, depth-tested against by the transparent layers (lines, surfaces) */
} lc_layer_role;
typedef struct lc_layer_params {
    lc_layer_role role;
    bool visible; /* false: the layer draws nothing and its elements get no fragments */
    lc_importance_map importance;
    lc_color_map color;
    lc_style style;   /* line_width, min_line_pixels, point_size and shading are the layer's */
    int filter_count; /* the layer's filters and time window, as a frame of its dataset alone has them */
    lc_filter filters[LC_MAX_FILTERS];
    lc_time_window time;
    lc_line_cluster_params clusters; /* lines: the layer's own clustering (count 0 = off) */
} lc_layer_params;
/* The defaults of a layer: visible, transparent, lc_render_params_default's mapping and style. */
void lc_layer_params_default(lc_layer_params *l);

/* Fills with the paper-default values (m = 5, s = 15, q = 60, r = 500, ...). */
void lc_foo_params_default(lc_foo_params *p);
void lc_style_default(lc_style *s);
void lc_render_params_default(lc_render_params *p);

const char *lc_method_name(lc_method m);
int lc_method_from_name(const char *name); /* -1 if unknown */
const char *lc_estimator_name(lc_estimator e);

#ifdef __cplusplus
}
#endif
#endif
