/* Renders every case of tests/data/reference/cases.txt with the `lucent render`
 * binary and requires pixels identical to the committed reference PNGs: the
 * guard that refactoring leaves images bit for bit as they were. A change that
 * is meant to alter images regenerates them (scripts/render_references.sh). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image.h"
#include "lc_test.h"

#define REF_DIR LUCENT_SOURCE_DIR "/tests/data/reference"

static void check_case(const char *name, const char *args, const char *tmp)
{
    char out[1280], ref[1280], cmd[4096];
    snprintf(out, sizeof out, "%s/%s.png", tmp, name);
    snprintf(ref, sizeof ref, "%s/%s.png", REF_DIR, name);
    /* The float buffers reproduce the references bit for bit; the default
     * compact layout is held to SSIM >= 0.999 by render.compact_ssim. */
    snprintf(cmd, sizeof cmd, "'%s' render %s --exact-positions --out '%s' >/dev/null 2>'%s/%s.log'", LUCENT_BINARY,
             args, out, tmp, name);
    int rc = system(cmd);
    CHECK(rc == 0, "%s: lucent render %s exited with %d (log %s/%s.log)", name, args, rc, tmp, name);
    if (rc != 0)
        return;
    lc_image a = {0}, b = {0};
    lc_error err = {0};
    int ra = lc_image_read_file(out, &a, &err);
    CHECK(ra == 0, "%s: %s", name, err.msg);
    int rb = lc_image_read_file(ref, &b, &err);
    CHECK(rb == 0, "%s: %s", name, err.msg);
    if (ra == 0 && rb == 0) {
        CHECK(a.width == b.width && a.height == b.height, "%s: %dx%d vs reference %dx%d", name, a.width, a.height,
              b.width, b.height);
        if (a.width == b.width && a.height == b.height) {
            size_t n = (size_t)a.width * a.height * 4, differing = 0;
            int max_diff = 0;
            for (size_t i = 0; i < n; i++) {
                int d = abs((int)a.rgba[i] - (int)b.rgba[i]);
                differing += d != 0;
                if (d > max_diff)
                    max_diff = d;
            }
            CHECK(differing == 0, "%s: %zu of %zu channels differ (max %d/255, SSIM %.5f); see %s", name, differing, n,
                  max_diff, lc_image_ssim(a.rgba, b.rgba, a.width, a.height), out);
        }
    }
    lc_image_free(&a);
    lc_image_free(&b);
}

int main(void)
{
    char tmp[] = "/tmp/lucent-ref-XXXXXX";
    if (!mkdtemp(tmp)) {
        perror("mkdtemp");
        return 1;
    }
    /* No GL outside CI: skip, as the other render tests do (render_util.h). */
    const char *ci = getenv("CI");
    char probe[600];
    snprintf(probe, sizeof probe, "'%s' render --dataset demo:abc --size 16x16 --out '%s/probe.png' >/dev/null 2>&1",
             LUCENT_BINARY, tmp);
    if (!(ci && strcmp(ci, "true") == 0) && system(probe) != 0) {
        fprintf(stderr, "lucent render does not run here (no EGL/GL 4.5?): skipped\n");
        return LC_TEST_SKIP;
    }
    FILE *f = fopen(REF_DIR "/cases.txt", "r");
    CHECK(f != NULL, "cannot open %s/cases.txt", REF_DIR);
    if (!f)
        return lc_test_finish();
    char line[1024];
    int cases = 0;
    while (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\r\n")] = '\0';
        if (line[0] == '#' || line[0] == '\0')
            continue;
        char *args = strchr(line, ' ');
        if (!args)
            continue;
        *args++ = '\0';
        check_case(line, args, tmp);
        cases++;
    }
    fclose(f);
    CHECK(cases >= 10, "only %d reference cases", cases);
    if (lc_test_failed == 0) {
        char cmd[600];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
        if (system(cmd) != 0)
            fprintf(stderr, "could not remove %s\n", tmp);
    }
    return lc_test_finish();
}
