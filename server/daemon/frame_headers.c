/* Response headers of an HTTP render from its frame statistics. */
#include "frame_headers.h"

#include <stdio.h>

#include "session.h"

void lc_frame_headers_add(struct MHD_Response *r, const lc_render_job *job)
{
    const lc_frame_info *info = &job->info;
    /* X-Lucent-Timings: pass=ms pairs (openapi.yaml); Server-Timing shows the
     * same in browser dev tools. */
    char timings[768], server_timing[1024];
    size_t tn = 0, sn = 0;
    timings[0] = server_timing[0] = '\0';
    for (int p = 0; p < LC_PASS_COUNT; p++) {
        if (info->pass_ms[p] < 0)
            continue;
        tn += (size_t)snprintf(timings + tn, sizeof timings - tn, "%s%s=%.3f", tn ? "," : "", lc_pass_name(p),
                               info->pass_ms[p]);
        sn += (size_t)snprintf(server_timing + sn, sizeof server_timing - sn, "%s%s;dur=%.3f", sn ? ", " : "",
                               lc_pass_name(p), info->pass_ms[p]);
        if (tn >= sizeof timings || sn >= sizeof server_timing)
            break;
    }
    if (tn < sizeof timings)
        snprintf(timings + tn, sizeof timings - tn, "%sgpu=%.3f,wall=%.3f,encode=%.3f,queue=%.3f", tn ? "," : "",
                 info->gpu_ms, info->wall_ms, job->encode_ms, job->queue_ms);
    if (sn < sizeof server_timing)
        snprintf(server_timing + sn, sizeof server_timing - sn, "%sencode;dur=%.3f, queue;dur=%.3f", sn ? ", " : "",
                 job->encode_ms, job->queue_ms);
    MHD_add_response_header(r, "X-Lucent-Timings", timings);
    MHD_add_response_header(r, "Server-Timing", server_timing);
    char buf[64];
    snprintf(buf, sizeof buf, "%s", info->converged ? "true" : "false");
    MHD_add_response_header(r, "X-Lucent-Converged", buf);
    snprintf(buf, sizeof buf, "%.6g", info->max_alpha_change);
    MHD_add_response_header(r, "X-Lucent-Max-Alpha-Change", buf);
    snprintf(buf, sizeof buf, "%u", info->element_count);
    MHD_add_response_header(r, "X-Lucent-Elements", buf);
    if (info->has_visibility) {
        char vis[192];
        snprintf(vis, sizeof vis, "topDecileAlpha=%.4f,bottomHalfAlpha=%.4f,coveredFraction=%.4f,occluderAlpha=%.4f",
                 info->top_decile_alpha, info->bottom_half_alpha, info->covered_fraction, info->occluder_alpha);
        MHD_add_response_header(r, "X-Lucent-Visibility", vis);
    }
    snprintf(buf, sizeof buf, "%.4g", job->cost); /* the estimate --max-cost is compared with */
    MHD_add_response_header(r, "X-Lucent-Cost", buf);
    if (job->session) {
        snprintf(buf, sizeof buf, "%llu", (unsigned long long)job->session->http_frames);
        MHD_add_response_header(r, "X-Lucent-Frame", buf);
    }
}
