/* Option tables (render/base/lc_options): what each type stores, strict
 * numbers, --flag=value, positionals, aliases, usage and the listing. */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "lc_options.h"
#include "lc_test.h"

typedef struct args {
    int n;
    unsigned u;
    long long big;
    unsigned long long ull;
    double ms_as_s, real;
    bool flag;
    int iflag;
    const char *text;
    char word[8];
} args;

static int set_word(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    args *a = target;
    if (strlen(arg) >= sizeof a->word) {
        snprintf(why, why_len, "at most %zu letters (%s)", sizeof a->word - 1, o->key);
        return -1;
    }
    snprintf(a->word, sizeof a->word, "%s", arg);
    return 0;
}

#define A(member) LC_OPT_AT(args, member)
static const lc_option table[] = {
    {"--n", "N", LC_OPT_INT, A(n), -5, 100, .help = "an int"},
    {"--u", "N", LC_OPT_INT, A(u), 0, 4e9, .help = ""},
    {"--big", "N", LC_OPT_INT, A(big), 0, 1e15, .help = "two joined"},
    {"--ull", "N", LC_OPT_INT, A(ull), 1, 1e12, .help = "unsigned long long"},
    {"--ms", "MS", LC_OPT_INT, A(ms_as_s), 0, 60000, 0.001, .help = "milliseconds kept as seconds"},
    {"--real", "X", LC_OPT_REAL, A(real), 0.5, 2, .help = "a number\nwith a second line"},
    {"--flag", NULL, LC_OPT_BOOL, A(flag), .help = "a bool"},
    {"--iflag", NULL, LC_OPT_BOOL, A(iflag), .help = "an int flag"},
    {"--text", "T", LC_OPT_TEXT, A(text), .help = "text"},
    {"-t", "T", LC_OPT_TEXT, A(text), .help = NULL},
    {"--word", "W", LC_OPT_CALL, .call = set_word, .key = "word", .help = "a call"},
    {NULL}};

static int parse(args *a, int argc, char **argv, const char **pos, int max_pos, int *npos)
{
    memset(a, 0, sizeof *a);
    lc_opt_set set = {table, a};
    return lc_opt_parse("test", &set, 1, argc, argv, pos, max_pos, npos);
}

int main(void)
{
    args a;
    const char *pos[4];
    int npos = -1;
    char *ok[] = {"x",      "--n",     "-5",    "--u", "4000000000", "--big=999999999999999",
                  "--ull",  "7",       "--ms",  "150", "--real",     "0.75",
                  "--flag", "--iflag", "file1", "-t",  "abc",        "--word=hey",
                  "--",     "--n",     NULL};
    CHECK(parse(&a, 20, ok, pos, 4, &npos) == 0, "a valid line parses");
    CHECK(a.n == -5, "int: %d", a.n);
    CHECK(a.u == 4000000000u, "unsigned: %u", a.u);
    CHECK(a.big == 999999999999999LL, "long long from --big=: %lld", a.big);
    CHECK(a.ull == 7, "unsigned long long: %llu", a.ull);
    CHECK_NEAR(a.ms_as_s, 0.150, 1e-15, "milliseconds scaled to seconds");
    CHECK_NEAR(a.real, 0.75, 0, "real");
    CHECK(a.flag && a.iflag == 1, "bools: %d %d", a.flag, a.iflag);
    CHECK(a.text && strcmp(a.text, "abc") == 0, "the alias -t sets --text's field");
    CHECK(strcmp(a.word, "hey") == 0, "call: %s", a.word);
    CHECK(npos == 2 && strcmp(pos[0], "file1") == 0 && strcmp(pos[1], "--n") == 0,
          "positionals, and everything after -- is one (%d)", npos);

    /* Every refusal: exit status 2 for the caller. */
    const char *bad[][2] = {{"--n", "abc"},
                            {"--n", "1e999"},
                            {"--n", "-6"},
                            {"--n", "101"},
                            {"--n", "5x"},
                            {"--n", " 5"},
                            {"--n", "+5"},
                            {"--n", ""},
                            {"--n", "1.5"},
                            {"--n", "99999999999999999999"},
                            {"--u", "-1"},
                            {"--ull", "0"},
                            {"--ms", "60001"},
                            {"--real", "abc"},
                            {"--real", "1e999"},
                            {"--real", "nan"},
                            {"--real", "inf"},
                            {"--real", "-1"},
                            {"--real", "2.0001"},
                            {"--real", "1x"},
                            {"--word", "toolongword"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char *argv[] = {"x", (char *)bad[i][0], (char *)bad[i][1], NULL};
        CHECK(parse(&a, 3, argv, NULL, 0, NULL) == -1, "%s '%s' is refused", bad[i][0], bad[i][1]);
    }
    char *missing[] = {"x", "--n", NULL}, *unknown[] = {"x", "--nope", NULL}, *stray[] = {"x", "file", NULL};
    char *valued_bool[] = {"x", "--flag=1", NULL}, *help[] = {"x", "--n", "3", "-h", NULL};
    CHECK(parse(&a, 2, missing, NULL, 0, NULL) == -1, "a flag without its value");
    CHECK(parse(&a, 2, unknown, NULL, 0, NULL) == -1, "an unknown flag");
    CHECK(parse(&a, 2, stray, NULL, 0, NULL) == -1, "a positional where none is taken");
    CHECK(parse(&a, 2, valued_bool, NULL, 0, NULL) == -1, "a bool given a value");
    CHECK(parse(&a, 4, help, NULL, 0, NULL) == 1 && a.n == 3, "-h: 1, after the flags before it");

    CHECK(lc_opt_parse_int("9223372036854775807", 0, 9223372036854775807LL, &a.big) == 0, "the largest long long");
    CHECK(lc_opt_parse_int("9223372036854775808", 0, 9223372036854775807LL, &a.big) == -1, "overflow");

    /* Usage: visible entries, joined names, continuation lines; the alias stays hidden. */
    char buf[4096] = "";
    FILE *f = fmemopen(buf, sizeof buf - 1, "w");
    lc_opt_set set = {table, &a};
    lc_opt_usage(f, &set, 1);
    fclose(f);
    CHECK(strstr(buf, "  --u N, --big N         two joined\n") != NULL, "joined names:\n%s", buf);
    CHECK(strstr(buf, "a number\n                         with a second line\n") != NULL, "continuation:\n%s", buf);
    CHECK(strstr(buf, "-t ") == NULL, "the alias is hidden:\n%s", buf);
    memset(buf, 0, sizeof buf);
    f = fmemopen(buf, sizeof buf - 1, "w");
    lc_opt_list(f, &set, 1);
    fclose(f);
    CHECK(strstr(buf, "--n int -5 100 -\n") && strstr(buf, "--word call - - word\n") &&
              strstr(buf, "--real real 0.5 2 -\n") && strstr(buf, "--flag bool - - -\n"),
          "listing:\n%s", buf);
    return lc_test_finish();
}
