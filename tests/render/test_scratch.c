/* Scratch buffers (render/gl/scratch.c): on a software rasterizer a discard
 * gives the buffer's pages back even while the driver keeps its storage. A
 * buffer texture stands for the binned scene that would keep it: an object
 * attached to another outlives its deletion until detached, as llvmpipe's
 * idle scenes keep a deleted buffer's storage until they are reused. Resident
 * memory is read around each step; without the page drop the 64 MB would stay
 * resident until the texture goes. On a GPU the discard is a plain delete and
 * only that is checked. */
#include "gl_context.h"
#include "memory.h"
#include "render_util.h"
#include "renderer_internal.h"

#define SCRATCH_BYTES (64ull << 20)
#define MB (1024.0 * 1024.0)

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    int software = lc_gl_renderer_is_software((const char *)glGetString(GL_RENDERER));

    /* A small buffer is deleted as it is (its pages are not worth a map). */
    GLuint small = lc_scratch_buffer(4096, GL_DYNAMIC_STORAGE_BIT);
    CHECK(small != 0, "a small scratch buffer");
    lc_scratch_discard(&small);
    CHECK(small == 0 && glGetError() == GL_NO_ERROR, "a small discard: buffer %u, GL error 0x%04x", small,
          glGetError());

    double before = lc_memory_resident_bytes() / MB;
    GLuint buf = lc_scratch_buffer(SCRATCH_BYTES, GL_DYNAMIC_STORAGE_BIT);
    const uint32_t fill = 0x5a5a5a5au;
    glClearNamedBufferData(buf, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &fill);
    GLuint tex;
    glCreateTextures(GL_TEXTURE_BUFFER, 1, &tex);
    glTextureBuffer(tex, GL_R32UI, buf);
    glFinish();
    double filled = lc_memory_resident_bytes() / MB;
    printf("resident: %.0f MB before, %.0f MB with the buffer filled\n", before, filled);
    if (software)
        CHECK(filled >= before + 48, "the filled buffer is resident: %.0f MB, %.0f MB before", filled, before);

    lc_scratch_discard(&buf);
    CHECK(buf == 0 && glGetError() == GL_NO_ERROR, "the discard: buffer %u, GL error 0x%04x", buf, glGetError());
    double discarded = lc_memory_resident_bytes() / MB;
    printf("resident: %.0f MB after the discard, the texture keeping the storage\n", discarded);
    if (software)
        CHECK(discarded <= before + 16,
              "the discarded buffer's pages went back while its storage is kept: %.0f MB "
              "resident, %.0f MB before it",
              discarded, before);

    glDeleteTextures(1, &tex); /* the storage goes now; nothing read the dropped pages */
    glFinish();
    double after = lc_memory_resident_bytes() / MB;
    printf("resident: %.0f MB after the texture\n", after);
    CHECK(after <= before + 16, "nothing stays: %.0f MB resident, %.0f MB before", after, before);
    CHECK(glGetError() == GL_NO_ERROR, "no GL error");

    test_gl_close(&t);
    return lc_test_finish();
}
