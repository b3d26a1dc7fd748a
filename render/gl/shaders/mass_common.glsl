// Histogram of the per-pixel importance mass sum(g^2) over covered pixels, in
// MASS_BINS_PER_OCTAVE bins per power of two from 2^MASS_LOG2_MIN on: the
// renderer reads its median and 95th percentile back for the frame statistics
// (docs/ALGORITHM.md "Visibility report"). The constants come from the renderer.
layout(std430, binding = BIND_MASS_HISTOGRAM) buffer MassHistogram { uint mass_histogram[MASS_BINS]; };

void mass_count(float m)
{
    if (!(m > 0.0))
        return;
    int k = int(floor((log2(m) - float(MASS_LOG2_MIN)) * float(MASS_BINS_PER_OCTAVE)));
    atomicAdd(mass_histogram[clamp(k, 0, MASS_BINS - 1)], 1u);
}
