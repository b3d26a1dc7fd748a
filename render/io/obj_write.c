/* Wavefront OBJ writer: v, f or l, and the default importance in vt. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_util.h"
#include "obj.h"

/* ---- writer */

int lc_save_obj(const lc_scene *s, const char *path, lc_error *err)
{
    int a = s->default_importance[0] ? lc_scene_find_attribute(s, s->default_importance) : -1;
    const float *vt = a >= 0 ? s->attributes[a].values : NULL;
    FILE *f = fopen(path, "w");
    if (!f)
        return lc_err(err, LC_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
    setvbuf(f, NULL, _IOFBF, 1 << 20);
    fprintf(f, "# written by Lucent: %s, %u vertices%s%s\n", lc_prim_type_name(s->type), s->vertex_count,
            vt ? ", vt = " : "", vt ? s->attributes[a].name : "");
    /* %.9g: every float survives the text round trip exactly. */
    for (uint32_t i = 0; i < s->vertex_count; i++) {
        const float *p = s->positions + 3 * (size_t)i;
        if (s->rgb) {
            const float *c = s->rgb + 3 * (size_t)i;
            fprintf(f, "v %.9g %.9g %.9g %.9g %.9g %.9g\n", p[0], p[1], p[2], c[0], c[1], c[2]);
        } else {
            fprintf(f, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
        }
    }
    if (vt)
        for (uint32_t i = 0; i < s->vertex_count; i++)
            fprintf(f, "vt %.9g\n", vt[i]);
    if (s->type == LC_PRIM_TRIANGLES) {
        for (uint32_t t = 0; t < s->triangle_count; t++) {
            const uint32_t *v = s->triangles + 3 * (size_t)t;
            if (vt)
                fprintf(f, "f %u/%u %u/%u %u/%u\n", v[0] + 1, v[0] + 1, v[1] + 1, v[1] + 1, v[2] + 1, v[2] + 1);
            else
                fprintf(f, "f %u %u %u\n", v[0] + 1, v[1] + 1, v[2] + 1);
        }
    } else if (s->type == LC_PRIM_LINES) {
        for (uint32_t l = 0; l < s->line_count; l++) {
            fputc('l', f);
            for (uint32_t v = s->line_offsets[l]; v < s->line_offsets[l + 1]; v++) {
                if (vt)
                    fprintf(f, " %u/%u", v + 1, v + 1);
                else
                    fprintf(f, " %u", v + 1);
            }
            fputc('\n', f);
        }
    }
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        remove(path);
        return lc_err(err, LC_ERR_IO, "%s: write failed", path);
    }
    return 0;
}
