/* The statistics of an HTTP render as response headers (protocol/openapi.yaml
 * "Image"): per-pass timings, convergence, elements, visibility, cost. */
#ifndef LC_SERVER_FRAME_HEADERS_H
#define LC_SERVER_FRAME_HEADERS_H

#include <microhttpd.h>

#include "workers.h"

/* Adds X-Lucent-Timings, Server-Timing, X-Lucent-Converged,
 * X-Lucent-Max-Alpha-Change, X-Lucent-Elements, X-Lucent-Visibility (methods
 * with element opacities), X-Lucent-Cost and X-Lucent-Frame (session renders)
 * for the finished job. */
void lc_frame_headers_add(struct MHD_Response *r, const lc_render_job *job);

#endif
