/* meta.c: the settings a bake records beside its grids, as typed name/value pairs. */
#include "meta.h"

#include <stdio.h>
#include <string.h>

static vdbgi_meta *meta_slot(vdbgi_meta_store *p, const char *name, vdbgi_meta_type type)
{
    vdbgi_meta *m = NULL;
    for (size_t i = 0; i < p->count && !m; i++)
        if (strcmp(p->items[i].name, name) == 0)
            m = &p->items[i];
    if (!m) {
        if (p->count == VDBGI_META_CAPACITY)
            return NULL; /* ours fit; a foreign file's extras are dropped */
        m = &p->items[p->count++];
        memset(m, 0, sizeof(*m));
        snprintf(m->name, sizeof(m->name), "%s", name);
    }
    m->type = type;
    return m;
}

void vdbgi_meta_set_string(vdbgi_meta_store *p, const char *name, const char *value)
{
    vdbgi_meta *const m = meta_slot(p, name, VDBGI_META_STRING);
    if (m) {
        snprintf(m->text, sizeof(m->text), "%s", value);
        snprintf(m->line, sizeof(m->line), "%s=%s", m->name, m->text);
    }
}

void vdbgi_meta_set_int(vdbgi_meta_store *p, const char *name, int64_t value)
{
    vdbgi_meta *const m = meta_slot(p, name, VDBGI_META_INT);
    if (m) {
        m->i = value;
        snprintf(m->line, sizeof(m->line), "%s=%lld", m->name, (long long)value);
    }
}

void vdbgi_meta_set_double(vdbgi_meta_store *p, const char *name, double value)
{
    vdbgi_meta *const m = meta_slot(p, name, VDBGI_META_DOUBLE);
    if (m) {
        m->d = value;
        snprintf(m->line, sizeof(m->line), "%s=%.9g", m->name, value);
    }
}

void vdbgi_meta_set_vec3(vdbgi_meta_store *p, const char *name, const float value[3])
{
    vdbgi_meta *const m = meta_slot(p, name, VDBGI_META_VEC3);
    if (m) {
        memcpy(m->v, value, sizeof(m->v));
        snprintf(m->line, sizeof(m->line), "%s=%.9g,%.9g,%.9g", m->name, (double)value[0],
                 (double)value[1], (double)value[2]);
    }
}

const vdbgi_meta *vdbgi_meta_find(const vdbgi_meta_store *p, const char *name)
{
    for (size_t i = 0; i < p->count; i++)
        if (strcmp(p->items[i].name, name) == 0)
            return &p->items[i];
    return NULL;
}
