/* Corpus replay without libFuzzer: feeds every file under the given files or
 * folders to LLVMFuzzerTestOneInput, so ctest runs each harness on its corpus
 * and on tests/data/loaders with any compiler (and under ASan when built so). */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int replay_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "%s: cannot open\n", path);
        return -1;
    }
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    /* Exactly n bytes (malloc(1) for empty files), so ASan sees any read past
     * the end of the input. */
    uint8_t *buf = malloc(n > 0 ? (size_t)n : 1);
    int ok = buf && (n <= 0 || fread(buf, 1, (size_t)n, f) == (size_t)n);
    fclose(f);
    if (!ok) {
        free(buf);
        fprintf(stderr, "%s: cannot read\n", path);
        return -1;
    }
    LLVMFuzzerTestOneInput(buf, n > 0 ? (size_t)n : 0);
    free(buf);
    return 1;
}

/* Returns the number of files replayed, or -1 on an unreadable path. */
static long replay(const char *path, int depth)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        fprintf(stderr, "%s: not found\n", path);
        return -1;
    }
    if (!S_ISDIR(st.st_mode))
        return replay_file(path);
    if (depth > 8)
        return 0;
    DIR *d = opendir(path);
    if (!d)
        return -1;
    long count = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        char child[4096];
        snprintf(child, sizeof child, "%s/%s", path, e->d_name);
        long n = replay(child, depth + 1);
        if (n < 0) {
            count = -1;
            break;
        }
        count += n;
    }
    closedir(d);
    return count;
}

int main(int argc, char **argv)
{
    long total = 0;
    for (int i = 1; i < argc; i++) {
        long n = replay(argv[i], 0);
        if (n < 0)
            return 1;
        total += n;
    }
    printf("replayed %ld inputs\n", total);
    return total > 0 ? 0 : 1; /* an empty run means the paths are wrong */
}
