/* `lucent schema`: prints the render request schema (protocol/'s field table)
 * as JSON, the one source: the page's table is generated from the same function
 * at build time (protocol/gen/schema_js.c), and tests/tools/check_schema.py
 * checks the page and the OpenAPI file against this output. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

int lc_cli_schema(int argc, char **argv)
{
    if (argc > 1) {
        FILE *f = strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 ? stdout : stderr;
        fprintf(f, "usage: lucent schema\nPrints the render request fields (types, ranges, names) as JSON.\n");
        return f == stdout ? 0 : 2;
    }
    json_t *schema = lc_proto_schema(NULL);
    char *text = schema ? json_dumps(schema, JSON_INDENT(1) | JSON_REAL_PRECISION(15)) : NULL;
    json_decref(schema);
    if (!text) {
        fprintf(stderr, "lucent schema: out of memory\n");
        return 1;
    }
    puts(text);
    free(text);
    return 0;
}
