/* Binary VTK legacy POLYDATA writer. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_util.h"
#include "vtk.h"

/* ---- writer */

static void put_be32(FILE *f, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)(v >> 24), (unsigned char)(v >> 16), (unsigned char)(v >> 8),
                          (unsigned char)v};
    fwrite(b, 1, 4, f);
}

static void put_f32(FILE *f, float x)
{
    uint32_t u;
    memcpy(&u, &x, 4);
    put_be32(f, u);
}

int lc_save_vtk(const lc_scene *s, const char *path, lc_error *err)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return lc_err(err, LC_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
    setvbuf(f, NULL, _IOFBF, 1 << 20);
    fprintf(f, "# vtk DataFile Version 3.0\n%s (written by Lucent)\nBINARY\nDATASET POLYDATA\nPOINTS %u float\n",
            s->name[0] ? s->name : "scene", s->vertex_count);
    for (size_t i = 0; i < 3 * (size_t)s->vertex_count; i++)
        put_f32(f, s->positions[i]);
    fprintf(f, "\n");
    if (s->type == LC_PRIM_LINES) {
        fprintf(f, "LINES %u %llu\n", s->line_count, (unsigned long long)s->line_count + s->vertex_count);
        for (uint32_t l = 0; l < s->line_count; l++) {
            put_be32(f, s->line_offsets[l + 1] - s->line_offsets[l]);
            for (uint32_t v = s->line_offsets[l]; v < s->line_offsets[l + 1]; v++)
                put_be32(f, v);
        }
        fprintf(f, "\n");
    } else if (s->type == LC_PRIM_TRIANGLES) {
        fprintf(f, "POLYGONS %u %llu\n", s->triangle_count, 4ull * s->triangle_count);
        for (size_t t = 0; t < s->triangle_count; t++) {
            put_be32(f, 3);
            for (int k = 0; k < 3; k++)
                put_be32(f, s->triangles[3 * t + k]);
        }
        fprintf(f, "\n");
    } else {
        /* One VERTICES cell with every point, so that VTK tools show them. */
        fprintf(f, "VERTICES 1 %llu\n", (unsigned long long)s->vertex_count + 1);
        put_be32(f, s->vertex_count);
        for (uint32_t v = 0; v < s->vertex_count; v++)
            put_be32(f, v);
        fprintf(f, "\n");
    }
    if (s->attribute_count || s->rgb)
        fprintf(f, "POINT_DATA %u\n", s->vertex_count);
    for (int a = 0; a < s->attribute_count; a++) {
        char name[LC_NAME_LEN];
        lc_io_header_name(s->attributes[a].name, name, sizeof name);
        fprintf(f, "SCALARS %s float 1\nLOOKUP_TABLE default\n", name);
        for (uint32_t i = 0; i < s->vertex_count; i++)
            put_f32(f, s->attributes[a].values[i]);
        fprintf(f, "\n");
    }
    if (s->rgb) {
        fprintf(f, "COLOR_SCALARS rgb 3\n");
        for (size_t i = 0; i < 3 * (size_t)s->vertex_count; i++) {
            float c = s->rgb[i];
            fputc((unsigned char)(c > 0 ? (c < 1 ? c * 255.0f + 0.5f : 255) : 0), f);
        }
        fprintf(f, "\n");
    }
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        remove(path);
        return lc_err(err, LC_ERR_IO, "%s: write failed", path);
    }
    return 0;
}
