/* gifile.h: the .gi container (docs/format.md) around a volume's two textures. */
#ifndef VDBGI_GIFILE_H
#define VDBGI_GIFILE_H

#include "volume.h"

#define VDBGI_GI_HEADER_SIZE 112
/* The newest version read: 1 is the seed layout, 2 adds the layout field (docs/format.md). */
#define VDBGI_GI_VERSION 2

/* Allocate v->raw for v->info's texture sizes and point indirection and atlas into it. */
vdbgi_result vdbgi_gifile_alloc(vdbgi_volume *v);
/* Write the header into v->raw and gzip the whole into v->file. */
vdbgi_result vdbgi_gifile_encode(vdbgi_volume *v);

#endif /* VDBGI_GIFILE_H */
