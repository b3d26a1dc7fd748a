/* Internals of the VTK legacy reader shared by its tokenizer (vtk_lex.c) and
 * its section parser (vtk_read.c). Not part of the io API. */
#ifndef LC_IO_VTK_INTERNAL_H
#define LC_IO_VTK_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "io_util.h"

#include "lc_base.h"
#include "scene.h"

#define MAX_WORD 256

typedef enum { VT_NONE = 0, VT_I8, VT_U8, VT_I16, VT_U16, VT_I32, VT_U32, VT_I64, VT_U64, VT_F32, VT_F64 } vtype;

/* Where attribute arrays go: POINT_DATA feeds the scene, CELL_DATA and
 * dataset FIELD data are parsed and dropped. */
typedef enum { SEC_NONE = 0, SEC_POINT, SEC_CELL, SEC_FIELD } section;

typedef struct vtk_load {
    const unsigned char *data;
    size_t size, pos;
    int binary;
    size_t line;    /* 1-based line of pos (meaningful in ASCII files) */
    size_t kw_line; /* line of the last keyword: where count errors are reported */
    size_t kw_pos;  /* its byte offset */
    const char *file;
    lc_error *err;
    int version_major;

    lc_scene *s;
    uint32_t npoints; /* 0 until POINTS */
    section sec;
    uint64_t cell_count; /* cells read so far: what CELL_DATA must match */
    lc_io_u32vec cell;   /* one cell's point ids */
    lc_io_u32vec line_idx, line_off, triangles;
    uint64_t skipped_attrs;
    lc_io_part *part; /* NULL or inactive: the whole file; else keep this process's lines */
} vtk_load;

/* Error at the current keyword: line for ASCII, byte offset for binary. */
int vtk_fail_at(vtk_load *L, int code, size_t line, size_t pos, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
#define fail_kw(L, code, ...) vtk_fail_at((L), (code), (L)->kw_line, (L)->kw_pos, __VA_ARGS__)
#define fail_here(L, code, ...) vtk_fail_at((L), (code), (L)->line, (L)->pos, __VA_ARGS__)

extern const int vtk_type_size[];
vtype vtk_type_from_name(const char *s);
int vtk_is_integer_type(vtype t);
int vtk_is_space(unsigned char c);
void vtk_skip_ws(vtk_load *L);
int vtk_next_word(vtk_load *L, char *w, int *got);
int vtk_need_word(vtk_load *L, char *w, const char *what);
int vtk_parse_count(const char *s, uint64_t *out);
int vtk_need_count(vtk_load *L, const char *what, uint64_t *out);
int vtk_need_type(vtk_load *L, const char *what, vtype *out);
int vtk_end_keyword_line(vtk_load *L);
/* After the SCALARS keyword: "name type [ncomp]" to the end of the line and
 * the LOOKUP_TABLE line that may follow (VTK requires it; some writers omit
 * it). name holds MAX_WORD bytes; ncomp is 1 when the line does not say. */
int vtk_scalars_header(vtk_load *L, char *name, vtype *t, uint64_t *ncomp);
/* One array of a FIELD block: "name ncomp ntuples type" to the end of its
 * line, the keyword position set to it for errors; *null = 1 for a
 * NULL_ARRAY, which has nothing after its name. name holds MAX_WORD bytes. */
int vtk_field_array_header(vtk_load *L, char *name, uint64_t *ncomp, uint64_t *ntuples, vtype *t, int *null);
void vtk_skip_line(vtk_load *L);
int vtk_at_keyword(const vtk_load *L, const char *kw, int after_data);
void vtk_skip_metadata_block(vtk_load *L);
void vtk_skip_metadata(vtk_load *L);
void vtk_decode_name(const char *in, char *out, size_t n);
int vtk_check_room(vtk_load *L, uint64_t count, vtype t, const char *what, uint64_t shown);
uint64_t vtk_get_be(const unsigned char *p, int n);
int vtk_read_value(vtk_load *L, vtype t, double *out, const char *what);
int vtk_read_floats(vtk_load *L, vtype t, uint64_t count, float *out, size_t stride, const char *what);
int vtk_read_index(vtk_load *L, vtype t, uint32_t *out, const char *what);
/* "# vtk DataFile Version x.y", a title line, ASCII|BINARY (sets binary). */
int vtk_read_preamble(vtk_load *L);

#endif
