/* The request's streamlines section turned into the streamline-set spec that
 * load-time sets use (render/io/streamlines.h), so that a set asked for by a
 * request is parsed, checked and traced by the one code path. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <jansson.h>

#include "request.h"

/* Appends to out at *at; false once it no longer fits. */
static int put(char *out, size_t n, size_t *at, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = *at < n ? vsnprintf(out + *at, n - *at, fmt, ap) : -1;
    va_end(ap);
    if (k < 0 || *at + (size_t)k >= n)
        return 0;
    *at += (size_t)k;
    return 1;
}

int lc_proto_streamlines_spec(const lc_request *r, const char *field_name, char *out, size_t n)
{
    static const char *const kinds[] = {"points", "rake", "box", "density"};
    static const char *const dirs[] = {"forward", "backward", "both"};
    const lc_streamlines_request *s = &r->streamlines;
    size_t at = 0;
    int ok = put(out, n, &at, "streamlines:%s?seeding=%s&direction=%s", field_name, kinds[s->seeding & 3],
                 dirs[s->direction >= 0 && s->direction < 3 ? s->direction : 0]);
    for (int i = 0; ok && i < s->seed_count; i++) /* %.17g: the doubles the request holds, exactly */
        ok = put(out, n, &at, "%s%.17g,%.17g,%.17g", i ? ";" : "&seeds=", s->seeds[i][0], s->seeds[i][1],
                 s->seeds[i][2]);
    if (ok && s->has_count)
        ok = put(out, n, &at, "&count=%d", s->count);
    if (ok && s->step != 0)
        ok = put(out, n, &at, "&step=%.17g", s->step);
    if (ok && s->length != 0)
        ok = put(out, n, &at, "&length=%.17g", s->length);
    if (ok && s->separation != 0)
        ok = put(out, n, &at, "&separation=%.17g", s->separation);
    return ok ? (int)at : -1;
}

void lc_proto_streamlines_replace(const json_t *update, lc_request *r)
{
    if (!json_is_object(json_object_get(update, "streamlines")))
        return;
    memset(&r->streamlines, 0, sizeof r->streamlines);
    r->streamlines.seeding = 3, r->streamlines.count = 64; /* lc_request_default's */
}
