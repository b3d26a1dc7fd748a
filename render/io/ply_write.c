/* Binary little-endian PLY writer. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_util.h"
#include "ply.h"

/* ---- writer */

static void put_u32le(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v;
    p[1] = (unsigned char)(v >> 8);
    p[2] = (unsigned char)(v >> 16);
    p[3] = (unsigned char)(v >> 24);
}

static void put_f32le(unsigned char *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put_u32le(p, u);
}

int lc_save_ply(const lc_scene *s, const char *path, lc_error *err)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return lc_err(err, LC_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
    setvbuf(f, NULL, _IOFBF, 1 << 20);
    fprintf(f,
            "ply\nformat binary_little_endian 1.0\ncomment written by Lucent\nelement vertex %u\n"
            "property float x\nproperty float y\nproperty float z\n",
            s->vertex_count);
    for (int a = 0; a < s->attribute_count; a++) {
        char name[LC_NAME_LEN];
        lc_io_header_name(s->attributes[a].name, name, sizeof name);
        fprintf(f, "property float %s\n", name);
    }
    if (s->rgb)
        fprintf(f, "property uchar red\nproperty uchar green\nproperty uchar blue\n");
    if (s->type == LC_PRIM_TRIANGLES)
        fprintf(f, "element face %u\nproperty list uchar int vertex_indices\n", s->triangle_count);
    else if (s->type == LC_PRIM_LINES)
        fprintf(f, "element line %u\nproperty list uint uint vertex_indices\n", s->line_count);
    fprintf(f, "end_header\n");

    unsigned char rec[4 * (3 + LC_MAX_ATTRIBUTES) + 3];
    for (uint32_t i = 0; i < s->vertex_count; i++) {
        unsigned char *p = rec;
        for (int k = 0; k < 3; k++, p += 4)
            put_f32le(p, s->positions[3 * (size_t)i + k]);
        for (int a = 0; a < s->attribute_count; a++, p += 4)
            put_f32le(p, s->attributes[a].values[i]);
        if (s->rgb)
            for (int k = 0; k < 3; k++) {
                float c = s->rgb[3 * (size_t)i + k];
                *p++ = (unsigned char)(c > 0 ? (c < 1 ? c * 255.0f + 0.5f : 255) : 0);
            }
        fwrite(rec, 1, (size_t)(p - rec), f);
    }
    if (s->type == LC_PRIM_TRIANGLES) {
        for (uint32_t t = 0; t < s->triangle_count; t++) {
            unsigned char tri[13];
            tri[0] = 3;
            for (int k = 0; k < 3; k++)
                put_u32le(tri + 1 + 4 * k, s->triangles[3 * (size_t)t + k]);
            fwrite(tri, 1, sizeof tri, f);
        }
    } else if (s->type == LC_PRIM_LINES) {
        for (uint32_t l = 0; l < s->line_count; l++) {
            unsigned char b[4];
            uint32_t first = s->line_offsets[l], last = s->line_offsets[l + 1];
            put_u32le(b, last - first);
            fwrite(b, 1, 4, f);
            for (uint32_t v = first; v < last; v++) {
                put_u32le(b, v);
                fwrite(b, 1, 4, f);
            }
        }
    }
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        remove(path);
        return lc_err(err, LC_ERR_IO, "%s: write failed", path);
    }
    return 0;
}
