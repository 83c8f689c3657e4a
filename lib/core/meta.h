/* meta.h: typed name/value settings stored with the grids. */
#ifndef VDBGI_META_H
#define VDBGI_META_H

#include "context.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vdbgi_meta_type {
    VDBGI_META_STRING,
    VDBGI_META_INT,    /* int64 */
    VDBGI_META_DOUBLE, /* double, may be inf */
    VDBGI_META_VEC3    /* 3 floats */
} vdbgi_meta_type;

typedef struct vdbgi_meta {
    char name[48];
    vdbgi_meta_type type;
    char text[208]; /* VDBGI_META_STRING */
    int64_t i;
    double d;
    float v[3];
    char line[256]; /* "name=value", kept current by the setters */
} vdbgi_meta;

#define VDBGI_META_CAPACITY 64

typedef struct vdbgi_meta_store {
    vdbgi_meta items[VDBGI_META_CAPACITY];
    size_t count;
} vdbgi_meta_store;

/* Set name to a value of the setter's type, replacing one of that name; past the
   capacity, new names are dropped (ours fit, a foreign file's extras need not). */
void vdbgi_meta_set_string(vdbgi_meta_store *store, const char *name, const char *value);
void vdbgi_meta_set_int(vdbgi_meta_store *store, const char *name, int64_t value);
void vdbgi_meta_set_double(vdbgi_meta_store *store, const char *name, double value);
void vdbgi_meta_set_vec3(vdbgi_meta_store *store, const char *name, const float value[3]);
const vdbgi_meta *vdbgi_meta_find(const vdbgi_meta_store *store, const char *name);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_META_H */
