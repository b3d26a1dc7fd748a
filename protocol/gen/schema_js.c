/* Build-time generator of the page's schema module (web/js/schema_fields.js in
 * the build tree): the field table that `lucent schema` prints, as an ES module,
 * so the page checks fields against the table the daemon parses with instead of
 * a hand-kept mirror. Usage: lucent_schema_js OUT.js */
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>

#include "request.h"

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: lucent_schema_js OUT.js\n");
        return 2;
    }
    json_t *schema = lc_proto_schema(NULL);
    if (!schema) {
        fprintf(stderr, "lucent_schema_js: out of memory\n");
        return 1;
    }
    FILE *f = fopen(argv[1], "w");
    if (!f) {
        perror(argv[1]);
        json_decref(schema);
        return 1;
    }
    fputs("// Generated at build time by protocol/gen/schema_js.c from protocol/'s field table (the\n"
          "// fields `lucent schema` prints, in its order); do not edit. web/js/schema.js reads it.\n"
          "export const SCHEMA = Object.freeze([\n",
          f);
    int rc = 0;
    size_t i;
    json_t *field;
    json_array_foreach(schema, i, field)
    {
        char *text = json_dumps(field, JSON_COMPACT | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(15));
        if (!text) {
            rc = 1;
            break;
        }
        fprintf(f, "  %s,\n", text);
        free(text);
    }
    fputs("]);\n", f);
    json_decref(schema);
    if (fclose(f) != 0 || rc) {
        fprintf(stderr, "lucent_schema_js: could not write %s\n", argv[1]);
        remove(argv[1]);
        return 1;
    }
    return 0;
}
