/* The meshed reference of an integral surface (stream_mesh.h): Hultquist's
 * front refinement with the particles of trace.c.
 *
 * A particle is one curve of the tracer (its vertex k is its place on front
 * k, time t0 + k h). The particles are kept in seed order; wherever two
 * neighbours lie farther apart than `split` on some front they both reach, a
 * particle is inserted halfway between them on the seed and traced from there
 * (Hultquist interpolates the new particle on the front instead; tracing it
 * from the seed costs a whole curve but puts it exactly on the surface). The
 * fronts are joined by two triangles per neighbour pair and step, as far as
 * both particles go and no farther than the first front where they lie more
 * than split apart (a tear: neighbours closer than 1e-9 on the seed that still
 * part, at a separatrix, are not split further). */
#include "stream_mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_INITIAL 33
#define DEFAULT_MAX 20000u
#define MIN_GAP 1e-9 /* seed parameters closer than this are not split further */

typedef struct particle {
    double u;
    lc_trace_curve c;
    struct particle *next;
} particle;

static double dist2(const float *a, const float *b)
{
    double d = 0;
    for (int k = 0; k < 3; k++)
        d += ((double)a[k] - b[k]) * ((double)a[k] - b[k]);
    return d;
}

/* The fronts a and b share before they lie farther apart than split: the
 * strip between them ends there (a tear, where refinement cannot follow). */
static uint32_t joined(const particle *a, const particle *b, double split2)
{
    uint32_t n = a->c.n < b->c.n ? a->c.n : b->c.n;
    for (uint32_t k = 0; k < n; k++)
        if (dist2(a->c.xyz + 3 * k, b->c.xyz + 3 * k) > split2)
            return k;
    return n;
}

/* 1 when a and b lie farther apart than split on a front both reach. */
static int diverge(const particle *a, const particle *b, double split2)
{
    uint32_t n = a->c.n < b->c.n ? a->c.n : b->c.n;
    return joined(a, b, split2) < n;
}

static void free_list(particle *p)
{
    while (p) {
        particle *n = p->next;
        lc_trace_curves_free(&p->c, 1);
        free(p);
        p = n;
    }
}

static particle *new_particle(const lc_field *f, const lc_seed *seed, const lc_trace_desc *d, double u, lc_error *err)
{
    particle *p = calloc(1, sizeof *p);
    if (!p) {
        lc_err(err, LC_ERR_NOMEM, "out of memory");
        return NULL;
    }
    p->u = u;
    if (lc_trace_curve_at(f, seed, d, u, &p->c, err) != 0) {
        free(p);
        return NULL;
    }
    return p;
}

/* The particles, refined until no neighbours diverge; *count set. */
static particle *refine(const lc_field *f, const lc_seed *seed, const lc_stream_mesh_desc *desc, double split,
                        uint32_t *count, lc_error *err)
{
    int n0 = desc->initial > 1 ? desc->initial : DEFAULT_INITIAL;
    uint32_t max = desc->max_particles ? desc->max_particles : DEFAULT_MAX;
    particle *head = NULL, **tail = &head;
    *count = 0;
    for (int i = 0; i < n0; i++) {
        particle *p = new_particle(f, seed, &desc->trace, (double)i / (n0 - 1), err);
        if (!p) {
            free_list(head);
            return NULL;
        }
        *tail = p, tail = &p->next;
        ++*count;
    }
    /* One pass over the list inserts where needed; an inserted particle is
     * checked against both neighbours in the same pass (the loop stays on a). */
    for (particle *a = head; a && a->next;) {
        particle *b = a->next;
        if (b->u - a->u > MIN_GAP && diverge(a, b, split * split)) {
            if (*count >= max) {
                free_list(head);
                lc_err_field(err, LC_ERR_LIMIT, "split",
                             "the surface needs more than %u particles at split %g: raise split or shorten the curves",
                             max, split);
                return NULL;
            }
            particle *m = new_particle(f, seed, &desc->trace, 0.5 * (a->u + b->u), err);
            if (!m) {
                free_list(head);
                return NULL;
            }
            m->next = b, a->next = m;
            ++*count;
            continue;
        }
        a = b;
    }
    return head;
}

int lc_stream_mesh_build(const lc_field *field, const lc_seed *seed_in, const lc_stream_mesh_desc *desc,
                         lc_stream_mesh *out, lc_error *err)
{
    memset(out, 0, sizeof *out);
    lc_seed seed = *seed_in;
    int rc = lc_seed_check(&seed, field, err);
    if (rc)
        return rc;
    double split = desc->split;
    if (!(split > 0)) {
        double d2 = 0;
        for (int a = 0; a < 3; a++)
            d2 += (field->bounds[3 + a] - field->bounds[a]) * (field->bounds[3 + a] - field->bounds[a]);
        split = sqrt(d2) / 200.0;
    }
    uint32_t count = 0;
    particle *head = refine(field, &seed, desc, split, &count, err);
    if (!head)
        return err ? err->code : LC_ERR_INVALID;
    uint64_t vertices = 0, triangles = 0;
    for (particle *p = head; p; p = p->next) {
        vertices += p->c.n;
        if (p->next) {
            uint32_t n = joined(p, p->next, split * split);
            triangles += n > 1 ? 2ull * (n - 1) : 0;
        }
    }
    if (vertices > UINT32_MAX / 3 || triangles > UINT32_MAX / 3) {
        free_list(head);
        return lc_err_field(err, LC_ERR_LIMIT, "split", "%llu vertices: too many for one mesh",
                            (unsigned long long)vertices);
    }
    out->xyz = malloc((size_t)(vertices ? vertices : 1) * 3 * sizeof(float));
    out->normal = malloc((size_t)(vertices ? vertices : 1) * 3 * sizeof(float));
    out->triangles = malloc((size_t)(triangles ? triangles : 1) * 3 * sizeof(uint32_t));
    if (!out->xyz || !out->normal || !out->triangles) {
        free_list(head);
        lc_stream_mesh_free(out);
        return lc_err(err, LC_ERR_NOMEM, "out of memory for a mesh of %llu vertices", (unsigned long long)vertices);
    }
    uint32_t base = 0, t = 0;
    for (particle *p = head; p; p = p->next) {
        memcpy(out->xyz + 3 * (size_t)base, p->c.xyz, 3 * sizeof(float) * p->c.n);
        memcpy(out->normal + 3 * (size_t)base, p->c.normal, 3 * sizeof(float) * p->c.n);
        if (p->next) { /* the strip to the next particle: quads (a_k, b_k, b_k+1, a_k+1) */
            uint32_t nb = base + p->c.n, n = joined(p, p->next, split * split);
            for (uint32_t k = 0; k + 1 < n; k++) {
                uint32_t q[6] = {base + k, nb + k, nb + k + 1, base + k, nb + k + 1, base + k + 1};
                memcpy(out->triangles + 3 * (size_t)t, q, sizeof q);
                t += 2;
            }
        }
        base += p->c.n;
    }
    out->vertex_count = base;
    out->triangle_count = t;
    out->particles = count;
    free_list(head);
    return 0;
}

void lc_stream_mesh_free(lc_stream_mesh *m)
{
    if (!m)
        return;
    free(m->xyz);
    free(m->normal);
    free(m->triangles);
    memset(m, 0, sizeof *m);
}
