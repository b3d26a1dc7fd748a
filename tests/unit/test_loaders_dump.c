/* LAMMPS dump reader (render/io/dump_read.c) on small dumps written here:
 * scaled, wrapped with and without image flags, unwrapped and triclinic
 * positions, each checked against positions computed by hand; atoms listed in
 * another order every frame; atoms that vanish and come back; speed and
 * displacement; every other column an attribute; bad input named by line;
 * every prefix and random edits of a sample. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lc_test.h"
#include "loader_test_util.h"
#include "loaders.h"

#define DATA LUCENT_TEST_DATA "/loaders/dump/"

static lc_scene *load_text(const char *text, lc_error *err)
{
    lc_scene *s = NULL;
    memset(err, 0, sizeof *err);
    int rc = lc_load_dump_memory(text, strlen(text), "t.dump", &s, err);
    CHECK(rc == 0 ? s != NULL : s == NULL && err->msg[0], "contract: rc %d", rc);
    return s;
}

static const float *attr(const lc_scene *s, const char *name)
{
    int i = lc_scene_find_attribute(s, name);
    CHECK(i >= 0, "attribute %s", name);
    return i >= 0 ? s->attributes[i].values : NULL;
}

static void check_point(const lc_scene *s, uint32_t v, double x, double y, double z, const char *what)
{
    CHECK(v < s->vertex_count, "%s: vertex %u of %u", what, v, s->vertex_count);
    if (v >= s->vertex_count)
        return;
    const float *p = s->positions + 3 * (size_t)v;
    CHECK(fabs(p[0] - x) < 1e-5 && fabs(p[1] - y) < 1e-5 && fabs(p[2] - z) < 1e-5,
          "%s: vertex %u at (%g %g %g), expected (%g %g %g)", what, v, p[0], p[1], p[2], x, y, z);
}

/* Box [0,10]^3 periodic; atom 1 moves +x by 1 per frame and crosses x = 10
 * between frames 1 and 2 (wrapped 9.5 -> 0.5 with image flag 0 -> 1); atom 2
 * sits still at 5; atom 3 moves -y by 2 per frame from y = 1 (wrapped to 9). */
static void test_positions(void)
{
    static const char *const kinds[] = {"scaled", "wrapped+flags", "wrapped", "unwrapped"};
    for (int kind = 0; kind < 4; kind++) {
        char text[4096];
        size_t n = 0;
        static const double x1[4] = {8.5, 9.5, 10.5, 11.5}, y3[4] = {1, -1, -3, -5};
        for (int f = 0; f < 4; f++) {
            n += (size_t)snprintf(text + n, sizeof text - n,
                                  "ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS pp pp pp\n"
                                  "0 10\n0.0 1e1\n0 10\nITEM: ATOMS %s\n",
                                  100 * f,
                                  kind == 0   ? "id type xs ys zs"
                                  : kind == 1 ? "type x y z ix iy iz id"
                                  : kind == 2 ? "x id y type z"
                                              : "id xu yu zu type");
            for (int k = 0; k < 3; k++) {
                int id = (f + k) % 3 + 1; /* another order in every frame */
                double p[3] = {id == 1 ? x1[f] : 5, id == 3 ? y3[f] : 5, 5}, w[3];
                int img[3];
                for (int j = 0; j < 3; j++) {
                    img[j] = (int)floor(p[j] / 10);
                    w[j] = p[j] - 10 * img[j];
                }
                int type = 10 * id;
                if (kind == 0)
                    n += (size_t)snprintf(text + n, sizeof text - n, "%d %d %.6f %.6f %.6f\n", id, type, w[0] / 10,
                                          w[1] / 10, w[2] / 10);
                else if (kind == 1)
                    n += (size_t)snprintf(text + n, sizeof text - n, "%d %g %g %g %d %d %d %d\n", type, w[0], w[1],
                                          w[2], img[0], img[1], img[2], id);
                else if (kind == 2)
                    n += (size_t)snprintf(text + n, sizeof text - n, "%g %d %g %d %g\n", w[0], id, w[1], type, w[2]);
                else
                    n += (size_t)snprintf(text + n, sizeof text - n, "%d %g %g %g %d\n", id, p[0], p[1], p[2], type);
            }
        }
        lc_error err;
        lc_scene *s = load_text(text, &err);
        CHECK(s != NULL, "%s: %s", kinds[kind], err.msg);
        if (!s)
            continue;
        CHECK(s->type == LC_PRIM_LINES && s->line_count == 3 && s->vertex_count == 12, "%s: %u lines, %u vertices",
              kinds[kind], s->line_count, s->vertex_count);
        /* The unwrapped positions: the same for every kind (the wrapped kind
         * starts from the first frame's wrapped position, which is unwrapped here). */
        for (int f = 0; f < 4; f++) {
            check_point(s, (uint32_t)f, x1[f], 5, 5, kinds[kind]);
            check_point(s, 4 + (uint32_t)f, 5, 5, 5, kinds[kind]);
            check_point(s, 8 + (uint32_t)f, 5, y3[f], 5, kinds[kind]);
        }
        const float *type = attr(s, "type"), *speed = attr(s, "speed"), *disp = attr(s, "displacement");
        if (type && speed && disp) {
            CHECK(type[0] == 10 && type[4] == 20 && type[11] == 30, "%s: type follows its atom", kinds[kind]);
            CHECK(fabsf(speed[0] - 1) < 1e-5f && fabsf(speed[3] - 1) < 1e-5f && speed[5] == 0 &&
                      fabsf(speed[8] - 2) < 1e-5f,
                  "%s: speed %g %g %g %g", kinds[kind], speed[0], speed[3], speed[5], speed[8]);
            CHECK(disp[0] == 0 && fabsf(disp[3] - 3) < 1e-5f && fabsf(disp[11] - 6) < 1e-5f,
                  "%s: displacement %g %g %g", kinds[kind], disp[0], disp[3], disp[11]);
        }
        CHECK(lc_scene_find_attribute(s, "id") < 0 && lc_scene_find_attribute(s, "x") < 0 &&
                  lc_scene_find_attribute(s, "ix") < 0 && s->attribute_count == 4,
              "%s: id, positions and image flags are no attributes (%d attributes)", kinds[kind], s->attribute_count);
        const float *step = attr(s, "timestep"); /* the frame's TIMESTEP, 100 f, per vertex */
        CHECK(step && step[0] == 0 && step[3] == 300 && step[4] == 0 && step[9] == 100, "%s: timestep per vertex",
              kinds[kind]);
        CHECK(strcmp(s->default_importance, "speed") == 0, "%s: default importance %s", kinds[kind],
              s->default_importance);
        lc_error ferr = {0};
        CHECK(lc_scene_finalize(s, NULL, &ferr) == 0, "%s: finalize (%s)", kinds[kind], ferr.msg);
        lc_scene_destroy(s);
    }
}

/* A triclinic box (xy = 2): scaled (0.5, 0.5, 0.5) is lo + H s. */
static void test_triclinic(void)
{
    const char *text = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS xy xz yz pp pp pp\n"
                       "0 12 2\n0 10 0\n0 10 0\nITEM: ATOMS id xs ys zs\n1 0.5 0.5 0.5\n"
                       "ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS xy xz yz pp pp pp\n"
                       "0 12 2\n0 10 0\n0 10 0\nITEM: ATOMS id xs ys zs\n1 0.95 0.5 0.5\n";
    lc_error err;
    lc_scene *s = load_text(text, &err);
    CHECK(s != NULL, "triclinic: %s", err.msg);
    if (!s)
        return;
    check_point(s, 0, 0 + 10 * 0.5 + 2 * 0.5, 5, 5, "triclinic");
    check_point(s, 1, 10 * 0.95 + 2 * 0.5, 5, 5, "triclinic");
    lc_scene_destroy(s);
}

/* Atom 2 misses frame 2 and comes back for 3 and 4: two lines; atom 3 is in
 * frame 0 only: no line; atom 4 appears in frame 3: one line; ids sort the lines. */
static void test_vanishing(void)
{
    static const int present[4][5] = {{1, 1, 1, 0, 1}, {1, 1, 0, 1, 1}, {1, 0, 0, 0, 0}, {0, 0, 0, 1, 1}};
    static const int ids[4] = {7, 2, 30, 4};
    char text[4096];
    size_t n = 0;
    for (int f = 0; f < 5; f++) {
        int count = 0;
        for (int a = 0; a < 4; a++)
            count += present[a][f];
        n += (size_t)snprintf(text + n, sizeof text - n,
                              "ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n%d\nITEM: BOX BOUNDS ff ff ff\n0 100\n0 100\n"
                              "0 100\nITEM: ATOMS id x y z\n",
                              f, count);
        for (int a = 3; a >= 0; a--)
            if (present[a][f])
                n += (size_t)snprintf(text + n, sizeof text - n, "%d %d %d %d\n", ids[a], ids[a], f, 0);
    }
    lc_error err;
    lc_scene *s = load_text(text, &err);
    CHECK(s != NULL, "vanishing: %s", err.msg);
    if (!s)
        return;
    /* Lines by id: 2 (frames 0-1), 2 (3-4), 4 (3-4), 7 (0-2, the atom at frame 4 alone is dropped). */
    static const uint32_t offsets[5] = {0, 2, 4, 6, 9};
    CHECK(s->line_count == 4 && s->vertex_count == 9, "vanishing: %u lines, %u vertices", s->line_count,
          s->vertex_count);
    for (uint32_t l = 0; s->line_count == 4 && l <= 4; l++)
        CHECK(s->line_offsets[l] == offsets[l], "vanishing: line offset %u is %u", l, s->line_offsets[l]);
    if (s->vertex_count == 9) {
        check_point(s, 0, 2, 0, 0, "atom 2, frame 0");
        check_point(s, 2, 2, 3, 0, "atom 2 back, frame 3");
        check_point(s, 4, 4, 3, 0, "atom 4, frame 3");
        check_point(s, 8, 7, 2, 0, "atom 7, frame 2");
        const float *disp = attr(s, "displacement");
        CHECK(disp && disp[2] == 0 && disp[3] == 1, "a new line measures displacement from its own start");
        const float *step = attr(s, "timestep"); /* a run's first vertex has its own frame's TIMESTEP */
        CHECK(step && step[0] == 0 && step[1] == 1 && step[2] == 3 && step[3] == 4 && step[6] == 0 && step[8] == 2,
              "timestep follows the frames of each run");
    }
    lc_scene_destroy(s);
}

/* A text column (element names) is skipped; the numeric ones stay. */
static void test_text_column(void)
{
    const char *text = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 10\n0 10\n0 10\n"
                       "ITEM: ATOMS id element xu yu zu q\n1 C 1 2 3 0.5\n"
                       "ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 10\n0 10\n0 10\n"
                       "ITEM: ATOMS id element xu yu zu q\n1 C 1 2 4 0.25\n";
    lc_error err;
    lc_scene *s = load_text(text, &err);
    CHECK(s != NULL, "text column: %s", err.msg);
    if (!s)
        return;
    const float *q = attr(s, "q");
    CHECK(lc_scene_find_attribute(s, "element") < 0 && s->attribute_count == 4 && q && q[0] == 0.5f && q[1] == 0.25f,
          "element skipped, q kept (%d attributes)", s->attribute_count);
    lc_scene_destroy(s);
}

/* Minimum-image unwrapping needs the periodic axes: a jump along a fixed
 * (ff) axis stays a jump. */
static void test_fixed_axis(void)
{
    const char *text = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp ff pp\n0 10\n0 10\n0 10\n"
                       "ITEM: ATOMS id x y z\n1 9.5 9.5 9.5\n"
                       "ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp ff pp\n0 10\n0 10\n0 10\n"
                       "ITEM: ATOMS id x y z\n1 0.5 0.5 0.5\n";
    lc_error err;
    lc_scene *s = load_text(text, &err);
    CHECK(s != NULL, "fixed axis: %s", err.msg);
    if (s)
        check_point(s, 1, 10.5, 0.5, 10.5, "pp ff pp");
    lc_scene_destroy(s);
}

static void expect_error(const char *text, const char *part, const char *what)
{
    lc_error err;
    lc_scene *s = load_text(text, &err);
    CHECK(!s && strstr(err.msg, part), "%s: expected '%s' in '%s'", what, part, err.msg);
    lc_scene_destroy(s);
}

#define HEAD "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"

static void test_errors(void)
{
    expect_error("", "line 1: no frame", "empty");
    expect_error("hello\n", "line 1: expected an ITEM", "not a dump");
    expect_error(HEAD "ITEM: ATOMS type x y z\n1 0 0 0\n1 0 0 0\n", "line 9: ITEM: ATOMS has no 'id'", "no id");
    expect_error(HEAD "ITEM: ATOMS id type\n1 0\n2 0\n", "line 9: ITEM: ATOMS has no positions", "no positions");
    expect_error(HEAD "ITEM: ATOMS id x y z\n1 0 0 0\n2 0 0          \n", "line 11: 3 values, ITEM: ATOMS names 4",
                 "short");
    expect_error(HEAD "ITEM: ATOMS id x y z\n1 0 0 0\n2 0 zero 0\n", "line 11: position: 'zero'", "text");
    expect_error(HEAD "ITEM: ATOMS id x y z\n1.5 0 0 0\n2 0 0 0\n", "line 10: id: '1.5' is not an integer", "id");
    expect_error(HEAD "ITEM: ATOMS id x y z\n1 0 0 0\n1 0 0 0\n", "line 11: atom id 1 appears twice", "twice");
    expect_error(HEAD "ITEM: ATOMS id x y z\n1 0 0 0\n", "cannot fit", "truncated");
    expect_error("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n99999999999\n", "line 4: NUMBER OF ATOMS", "huge count");
    expect_error("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n-2\nITEM: ATOMS id x y z\n", "line 4", "negative");
    expect_error("ITEM: TIMESTEP\n0\nITEM: BOX BOUNDS pp pp pp\n0 1\n1 1\n0 1\n", "line 5: BOX BOUNDS: axis y is empty",
                 "empty box");
    expect_error("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS id xs ys zs\n1 0 0 0\n",
                 "line 5: ITEM: ATOMS before ITEM: BOX BOUNDS", "no box");
    expect_error(HEAD "ITEM: ATOMS id x y z q\n1 0 0 0 1\n2 0 0 0 1\n" HEAD "ITEM: ATOMS id x y z\n1 0 0 0\n2 0 0 0\n",
                 "line 20: ITEM: ATOMS: column 'q' of the first frame is missing", "columns change");
    expect_error(HEAD "ITEM: ATOMS id x y z\n1 0 0 0\n2 0 0 0\n" HEAD "ITEM: ATOMS id xu yu zu\n1 0 0 0\n2 0 0 0\n",
                 "line 20: ITEM: ATOMS: the positions are given other than", "positions change");
    expect_error(HEAD "ITEM: ATOMS id x y z\n1 0 0 0\n2 0 0 0\nITEM: TIMESTEP\n1\n", "the file ends before",
                 "frame cut");
    expect_error(HEAD "ITEM: ATOMS id x y z\n1 0 0 0\n2 0 0 0\n", "no atom appears in two consecutive frames",
                 "one frame");
    expect_error(HEAD "ITEM: FOO\n", "line 9: expected an ITEM: line of a LAMMPS dump, found 'ITEM: FOO'", "item");
}

static int load_memory(const char *path, const void *data, size_t size, lc_scene **s, lc_error *err)
{
    return lc_load_dump_memory(data, size, lc_io_basename(path), s, err);
}

int main(void)
{
    lc_log_set_level(LC_LOG_ERROR); /* the cases trigger expected warnings */
    (void)run_case_table;           /* the cases are written here, not in a table */
    test_positions();
    test_triclinic();
    test_vanishing();
    test_fixed_axis();
    test_text_column();
    test_errors();
    /* Through the dispatcher, by both extensions. */
    lc_scene *s = NULL;
    lc_error err = {0};
    CHECK(lc_scene_load_file(DATA "small.lammpstrj", &s, &err) == 0 && s && s->line_count == 5, "small.lammpstrj: %s",
          err.msg);
    lc_scene_destroy(s);
    CHECK(lc_scene_is_dataset_file("a.dump") && lc_scene_is_dataset_file("b.LAMMPSTRJ") &&
              lc_scene_can_read_part("a.dump"),
          "extensions");
    static const char *const files[] = {"small.lammpstrj"};
    check_prefixes_and_mutations(DATA, files, 1, "0123456789 \n.-eITEM:", 0x2545F4914F6CDD1Dull, load_memory);
    return lc_test_finish();
}
