/* lucent: command-line entry; dispatches to the subcommands. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "lc_base.h"
#include "serve.h"

static const struct {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *help;
} commands[] = {
    {"render", lc_cli_render, "render one frame of a request to PNG/JPEG"},
    {"info", lc_cli_info, "print counts, bounds, attributes and elements of a dataset"},
    {"gen", lc_cli_gen, "write a demo dataset to a PLY or OBJ file"},
    {"bench", lc_cli_bench, "per-pass timings, frames per second and GPU memory on the demo datasets"},
    {"compare", lc_cli_compare, "compare a method against the exact reference (SSIM, RMSE, time, memory)"},
    {"schema", lc_cli_schema, "print the render request schema (fields, types, ranges) as JSON"},
    {"ssim", lc_cli_ssim, "SSIM and RMSE of two images of one size"},
    {"serve", lc_serve_main, "run the HTTP/WebSocket render daemon"},
    {"movie", lc_cli_movie, "render a movie request (camera path) to an H.264/MP4 or VP9/WebM file"},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: lucent COMMAND [options]   (lucent COMMAND --help for its options)\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(f, "  %-8s %s\n", commands[i].name, commands[i].help);
    fprintf(f, "\nenvironment: LUCENT_EGL_DEVICE (EGL device index), LUCENT_LOG_LEVEL (error|warn|info|debug)\n");
}

int main(int argc, char **argv)
{
    const char *level = getenv("LUCENT_LOG_LEVEL");
    if (level && lc_log_parse_level(level) >= 0)
        lc_log_set_level((lc_log_level)lc_log_parse_level(level));
    else if (argc > 1 && strcmp(argv[1], "serve") != 0)
        lc_log_set_level(LC_LOG_WARN); /* tools print results, not progress */
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "help") == 0) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (strcmp(argv[1], commands[i].name) == 0)
            return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "lucent: unknown command \"%s\"\n", argv[1]);
    usage(stderr);
    return 2;
}
