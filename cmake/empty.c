/* Keeps a library target valid while it has no other sources. */
typedef int lc_empty_translation_unit;
