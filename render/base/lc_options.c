/* Command-line option tables: strict parsing, usage and a listing for tests. */
#include "lc_options.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#define USAGE_COLUMN 25

int lc_opt_parse_int(const char *s, long long lo, long long hi, long long *out)
{
    /* strtoll would skip leading blanks and take "+"; a flag's value is the digits alone. */
    if (!(isdigit((unsigned char)s[0]) || (s[0] == '-' && isdigit((unsigned char)s[1]))))
        return -1;
    char *end;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (errno || *end || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

int lc_opt_parse_real(const char *s, double lo, double hi, double *out)
{
    if (!s[0] || isspace((unsigned char)s[0]))
        return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    /* 1e999 overflows to inf (ERANGE); underflow to a tiny number is harmless. */
    if (*end || !isfinite(v) || (errno == ERANGE && fabs(v) > 1.0) || !(v >= lo && v <= hi))
        return -1;
    *out = v;
    return 0;
}

static void store_int(void *field, size_t size, long long v)
{
    if (size == sizeof(int)) {
        int i = (int)v;
        memcpy(field, &i, sizeof i);
    } else if (size == sizeof(long long)) {
        memcpy(field, &v, sizeof v);
    } else if (size == sizeof(short)) {
        short h = (short)v;
        memcpy(field, &h, sizeof h);
    } else {
        unsigned char c = (unsigned char)v;
        memcpy(field, &c, 1);
    }
}

static const lc_option *find(const lc_opt_set *sets, int nsets, const char *name, size_t len, void **target)
{
    for (int s = 0; s < nsets; s++)
        for (const lc_option *o = sets[s].opts; o->name; o++)
            if (strlen(o->name) == len && strncmp(o->name, name, len) == 0) {
                *target = sets[s].target;
                return o;
            }
    return NULL;
}

/* The range as usage and messages write it: integers without a decimal point. */
static void format_range(const lc_option *o, char *buf, size_t n)
{
    if (o->type == LC_OPT_INT)
        snprintf(buf, n, "an integer in [%.0f, %.0f]", o->lo, o->hi);
    else
        snprintf(buf, n, "a number in [%.15g, %.15g]", o->lo, o->hi);
}

static int apply(const char *cmd, const lc_option *o, void *target, const char *arg)
{
    char *field = (char *)target + o->offset;
    char why[256] = "";
    switch (o->type) {
    case LC_OPT_BOOL: store_int(field, o->size, 1); return 0;
    case LC_OPT_TEXT: memcpy(field, &arg, sizeof arg); return 0;
    case LC_OPT_INT: {
        long long v;
        if (lc_opt_parse_int(arg, (long long)o->lo, (long long)o->hi, &v) != 0)
            break;
        if (o->scale != 0) {
            double d = (double)v * o->scale;
            memcpy(field, &d, sizeof d);
        } else {
            store_int(field, o->size, v);
        }
        return 0;
    }
    case LC_OPT_REAL: {
        double d;
        if (lc_opt_parse_real(arg, o->lo, o->hi, &d) != 0)
            break;
        memcpy(field, &d, sizeof d);
        return 0;
    }
    case LC_OPT_CALL:
        if (o->call(target, o, arg, why, sizeof why) == 0)
            return 0;
        fprintf(stderr, "lucent %s: %s: %s\n", cmd, o->name, why[0] ? why : "invalid value");
        return -1;
    }
    format_range(o, why, sizeof why);
    fprintf(stderr, "lucent %s: %s: \"%s\" is not %s\n", cmd, o->name, arg, why);
    return -1;
}

int lc_opt_parse(const char *cmd, const lc_opt_set *sets, int nsets, int argc, char **argv, const char **positional,
                 int max_positional, int *npositional)
{
    int npos = 0, flags_done = 0;
    if (npositional)
        *npositional = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (flags_done || a[0] != '-' || a[1] == '\0') {
            if (!positional || npos >= max_positional) {
                fprintf(stderr, "lucent %s: unexpected argument \"%s\"\n", cmd, a);
                return -1;
            }
            positional[npos++] = a;
            if (npositional)
                *npositional = npos;
            continue;
        }
        if (strcmp(a, "--") == 0) {
            flags_done = 1;
            continue;
        }
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
            return 1;
        if (strcmp(a, "--list-flags") == 0) {
            lc_opt_list(stdout, sets, nsets);
            return 1;
        }
        const char *eq = strncmp(a, "--", 2) == 0 ? strchr(a, '=') : NULL;
        size_t len = eq ? (size_t)(eq - a) : strlen(a);
        void *target = NULL;
        const lc_option *o = find(sets, nsets, a, len, &target);
        if (!o) {
            fprintf(stderr, "lucent %s: unknown option %.*s (lucent %s --help lists them)\n", cmd, (int)len, a, cmd);
            return -1;
        }
        const char *value = NULL;
        if (o->type == LC_OPT_BOOL) {
            if (eq) {
                fprintf(stderr, "lucent %s: %s takes no value\n", cmd, o->name);
                return -1;
            }
        } else if (eq) {
            value = eq + 1;
        } else if (i + 1 < argc) {
            value = argv[++i];
        } else {
            fprintf(stderr, "lucent %s: %s needs a value (%s)\n", cmd, o->name, o->meta ? o->meta : "");
            return -1;
        }
        if (apply(cmd, o, target, value) != 0)
            return -1;
    }
    return 0;
}

/* Prints a help text's lines after the first, indented to the column. */
static void print_help(FILE *f, const char *help)
{
    for (const char *p = help; *p;) {
        const char *nl = strchr(p, '\n');
        size_t n = nl ? (size_t)(nl - p) : strlen(p);
        fprintf(f, "%.*s\n", (int)n, p);
        if (!nl || !nl[1])
            break;
        p = nl + 1;
        fprintf(f, "%*s", USAGE_COLUMN, "");
    }
}

void lc_opt_usage(FILE *f, const lc_opt_set *sets, int nsets)
{
    char names[256] = "";
    for (int s = 0; s < nsets; s++)
        for (const lc_option *o = sets[s].opts; o->name; o++) {
            if (!o->help)
                continue;
            size_t used = strlen(names);
            snprintf(names + used, sizeof names - used, "%s%s%s%s", used ? ", " : "", o->name, o->meta ? " " : "",
                     o->meta ? o->meta : "");
            if (!o->help[0])
                continue;
            if ((int)strlen(names) + 4 <= USAGE_COLUMN)
                fprintf(f, "  %-*s", USAGE_COLUMN - 2, names);
            else /* long names: the help on the next line */
                fprintf(f, "  %s\n%*s", names, USAGE_COLUMN, "");
            print_help(f, o->help);
            names[0] = '\0';
        }
}

void lc_opt_list(FILE *f, const lc_opt_set *sets, int nsets)
{
    static const char *const type_names[] = {"bool", "int", "real", "text", "call"};
    for (int s = 0; s < nsets; s++)
        for (const lc_option *o = sets[s].opts; o->name; o++) {
            const char *type = o->type == LC_OPT_CALL && o->numeric ? "number" : type_names[o->type];
            if (o->type == LC_OPT_INT || o->type == LC_OPT_REAL)
                fprintf(f, "%s %s %.17g %.17g -\n", o->name, type, o->lo, o->hi);
            else
                fprintf(f, "%s %s - - %s\n", o->name, type, o->key ? o->key : "-");
        }
}
