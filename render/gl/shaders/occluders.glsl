// Occluder weights of the visibility report (docs/ALGORITHM.md §8): each
// element sums the importance mass behind its fragments (the sum that q
// weighs in Eq. 10) in 1/4096 units, saturating, so the report can weigh an
// unimportant element by how much it hides.
layout(std430, binding = BIND_ELEMENT_BEHIND) buffer ElementBehind { uint element_behind[]; };

uint behind_units(float behind) { return uint(clamp(behind, 0.0, 256.0) * 4096.0 + 0.5); }

void add_behind_units(uint element, uint add)
{
    if (add == 0u)
        return;
    uint old = atomicAdd(element_behind[element], add);
    if (old > 0xFFFFFFFFu - add) // wrapped: stay at the top
        atomicMax(element_behind[element], 0xFFFFFFFFu);
}

void add_behind(uint element, float behind) { add_behind_units(element, behind_units(behind)); }

// importantOccluded (docs/ALGORITHM.md §8): [0] fragments with g above
// LC_IMPORTANT_G, [1] those of them with at least LC_IMPORTANT_MASS (one
// important fragment's g^2) of mass in front, the sum r weighs in Eq. 10.
// Values as in renderer.h.
layout(std430, binding = BIND_IMPORTANT_OCCLUDED) buffer ImportantOccluded { uint important_occluded[2]; };

// Adds an important fragment and whether it is occluded to counts (.x, .y).
uvec2 important_counts(float g, float front) { return g <= 0.8 ? uvec2(0u) : uvec2(1u, front >= 0.64 ? 1u : 0u); }

void add_important(uvec2 n)
{
    if (n.x > 0u)
        atomicAdd(important_occluded[0], n.x);
    if (n.y > 0u)
        atomicAdd(important_occluded[1], n.y);
}

void count_important(float g, float front) { add_important(important_counts(g, front)); }

// Patches (docs/ALGORITHM.md §6): with u_element_emphasis the emphasis of Eq. 10
// reads the element's mean importance instead of the fragment's own, so that
// a patch's opacity is not set by its least important fragment.
layout(std430, binding = BIND_ELEMENT_G) readonly buffer ElementG { float element_g[]; };
uniform int u_element_emphasis;

float emphasis_importance(uint element, float g) { return u_element_emphasis != 0 ? element_g[element] : g; }
