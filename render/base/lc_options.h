/* Command-line option tables: each flag written once as {name, field, type,
 * range, help}, parsed strictly and printed as usage from the same entry. */
#ifndef LC_OPTIONS_H
#define LC_OPTIONS_H

#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    LC_OPT_BOOL, /* no value: the field (bool or int) becomes 1 */
    LC_OPT_INT,  /* a decimal integer in [lo, hi]: into an int or 8-byte integer field,
                  * or, when scale != 0, into a double field as value * scale */
    LC_OPT_REAL, /* a finite number in [lo, hi] into a double field */
    LC_OPT_TEXT, /* the argument itself (borrowed from argv) into a const char * field */
    LC_OPT_CALL  /* call(): names, lists and compound values (WxH, ADDR:PORT, 20G) */
} lc_opt_type;

typedef struct lc_option lc_option;
/* Parses arg for o into target; returns 0, or -1 with a reason in why (the
 * flag and the argument are named by the caller). */
typedef int (*lc_opt_call)(void *target, const lc_option *o, const char *arg, char *why, size_t why_len);

struct lc_option {
    const char *name; /* "--frames"; "-o" style aliases are entries with help NULL */
    const char *meta; /* the value in usage ("N", "WxH"); NULL for LC_OPT_BOOL */
    lc_opt_type type;
    size_t offset;    /* of the field in the table's target (LC_OPT_AT) */
    size_t size;      /* of the field */
    double lo, hi;    /* LC_OPT_INT, LC_OPT_REAL: the accepted range, inclusive */
    double scale;     /* LC_OPT_INT into a double field (e.g. 0.001: ms given, seconds kept) */
    lc_opt_call call; /* LC_OPT_CALL */
    const char *key;  /* LC_OPT_CALL: passed along (e.g. the request field a flag sets) */
    int numeric;      /* LC_OPT_CALL: the value is a number or made of numbers (listed as such) */
    /* Usage text; "" joins the flag to the next entry's line ("--q X, --r X  help");
     * NULL hides the entry (aliases, --list-flags). Lines after '\n' are indented. */
    const char *help;
};

/* offset and size of a member, for an lc_option's field. */
#define LC_OPT_AT(type, member) offsetof(type, member), sizeof(((type *)0)->member)

/* A table and the struct its offsets point into; tables end with a NULL name. */
typedef struct lc_opt_set {
    const lc_option *opts;
    void *target;
} lc_opt_set;

/* Parses argv[1..argc-1] against the sets (first match wins). "--name VALUE"
 * and "--name=VALUE" both work. Arguments that do not start with '-' go to
 * positional (at most max_positional; NULL = none allowed), "--" ends the
 * flags. "--help"/"-h" print nothing and return 1; the hidden "--list-flags"
 * prints lc_opt_list() to stdout and returns 1. On a bad flag or value prints
 * "lucent CMD: --flag: reason" to stderr and returns -1 (exit status 2). */
int lc_opt_parse(const char *cmd, const lc_opt_set *sets, int nsets, int argc, char **argv, const char **positional,
                 int max_positional, int *npositional);

/* Writes the usage lines of the sets' visible entries. */
void lc_opt_usage(FILE *f, const lc_opt_set *sets, int nsets);

/* One line per entry, for tests: "NAME TYPE LO HI KEY" with TYPE bool, int,
 * real, text, number (a numeric LC_OPT_CALL) or call; KEY is the entry's key or "-". */
void lc_opt_list(FILE *f, const lc_opt_set *sets, int nsets);

/* Strict numbers, as the tables parse them: the whole of s, finite, in [lo, hi].
 * Return 0 or -1. */
int lc_opt_parse_int(const char *s, long long lo, long long hi, long long *out);
int lc_opt_parse_real(const char *s, double lo, double hi, double *out);

#ifdef __cplusplus
}
#endif

#endif
