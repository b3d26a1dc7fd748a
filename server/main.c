/* lucent: command-line entry (render, info, gen, bench, compare, serve). */
#include <stdio.h>

int main(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "usage: lucent render|info|gen|bench|serve ...\n");
    return 2;
}
