/* Scratch buffers sized by a frame (fragment lists and chains, compute sums,
 * the exact pool, surface layers), and their discard.
 *
 * On llvmpipe a deleted buffer's storage lives as long as a binned scene
 * refers to it, and a scene lets go of its references only when llvmpipe
 * reuses it: it takes the first idle scene of its list, so the scenes that
 * were in flight beside it during a large frame keep that frame's buffers
 * until as many scenes are in flight again, which small frames may never
 * bring. Which scenes hold what is a matter of timing (a loaded host keeps
 * more in flight), so a large still's 256 MB fragment list stayed resident
 * now and then. The discard gives the pages back to the system before the
 * delete: the buffer is mapped unsynchronized once nothing runs (llvmpipe maps
 * a buffer's own storage) and the whole pages in it are dropped. A scene that
 * keeps the storage never runs again, so nothing reads the zero pages. */
#include <stdatomic.h>
#include <stdint.h>
#include <sys/mman.h>
#include <unistd.h>

#include "gl_context.h"
#include "renderer_internal.h"

/* Below this a buffer is deleted as it is: its pages are not worth a map. */
#define DISCARD_PAGES_MIN (1u << 20)

static atomic_int drop_pages; /* lc_scratch_configure: on software rasterizers */

void lc_scratch_configure(const char *gl_renderer)
{
    atomic_store(&drop_pages, lc_gl_renderer_is_software(gl_renderer));
}

GLuint lc_scratch_buffer(uint64_t bytes, GLbitfield flags)
{
    GLuint b;
    glCreateBuffers(1, &b);
    /* The map of the discard needs a map bit; GPUs keep their storage flags. */
    glNamedBufferStorage(b, (GLsizeiptr)bytes, NULL, flags | (atomic_load(&drop_pages) ? GL_MAP_WRITE_BIT : 0));
    return b;
}

/* Drops the whole pages of [p, p + n): they read as zeros if touched again.
 * The allocator's own words lie outside the range (before p), so a later free
 * of the storage finds them intact. */
static void drop_range(void *p, size_t n)
{
    long page = sysconf(_SC_PAGESIZE);
    if (page <= 0)
        return;
    uintptr_t a = ((uintptr_t)p + (uintptr_t)page - 1) & ~((uintptr_t)page - 1);
    uintptr_t b = ((uintptr_t)p + n) & ~((uintptr_t)page - 1);
    if (b > a)
        madvise((void *)a, b - a, MADV_DONTNEED);
}

void lc_scratch_discard(GLuint *buf)
{
    if (!*buf)
        return;
    GLint64 size = 0;
    GLint mappable = 0;
    if (atomic_load(&drop_pages)) {
        glGetNamedBufferParameteri64v(*buf, GL_BUFFER_SIZE, &size);
        glGetNamedBufferParameteriv(*buf, GL_BUFFER_STORAGE_FLAGS, &mappable);
        mappable &= GL_MAP_WRITE_BIT;
    }
    if (mappable && size >= (GLint64)DISCARD_PAGES_MIN) {
        glFinish(); /* every draw that writes it has run */
        void *p = glMapNamedBufferRange(*buf, 0, (GLsizeiptr)size, GL_MAP_WRITE_BIT | GL_MAP_UNSYNCHRONIZED_BIT);
        if (p) {
            drop_range(p, (size_t)size);
            glUnmapNamedBuffer(*buf);
        }
    }
    glDeleteBuffers(1, buf);
    *buf = 0;
}
