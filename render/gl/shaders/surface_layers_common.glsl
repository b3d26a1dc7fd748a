// Surface layers (PRT, surface_layers.c) shared declarations: one batch's
// fragment lists, the per-pixel words (counters, list heads, layer counts,
// packed output) and the persistent layers. Indices must match surface_layers.c.

#define SURFACE_END 0xFFFFFFFFu
#define SURFACE_COUNTER_NODES 0u     // fragments offered to the pool this batch
#define SURFACE_COUNTER_POOL_DROP 1u // ... that found the pool full
#define SURFACE_COUNTER_MERGED 2u    // ... averaged into an existing layer
#define SURFACE_COUNTER_OVERFLOW 3u  // ... dropped because the pixel had K layers
#define SURFACE_HEADS 16u            // then u_pixel_count heads, counts, outputs

struct SurfaceFragment {
    uint next;
    float depth;   // view depth (-z in view space)
    uint color;    // packUnorm4x8
    uint order;    // the segment's place in the batch (its last vertex): merges follow the drawing order
    vec4 normal;   // view space, xyz
};

// Running means over the fragments merged so far: (rgb, depth), (normal, count).
struct SurfaceLayer {
    vec4 color_depth;
    vec4 normal_count;
};

layout(std430, binding = BIND_SURFACE_NODES) coherent buffer SurfaceNodes { SurfaceFragment frags[]; };
layout(std430, binding = BIND_SURFACE_PIXELS) coherent buffer SurfacePixels { uint pixels[]; };

uniform uint u_pixel_count;  // width * height
uniform uint u_pool_capacity;

uint heads_at(uint pix) { return SURFACE_HEADS + pix; }
uint counts_at(uint pix) { return SURFACE_HEADS + u_pixel_count + pix; }
uint output_at(uint pix) { return SURFACE_HEADS + 2u * u_pixel_count + pix; }
