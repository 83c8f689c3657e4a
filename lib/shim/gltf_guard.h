/* gltf_guard.h: the checks a glTF passes before any importer parses it (gltf_guard.cpp). */
#ifndef VDBGI_GLTF_GUARD_H
#define VDBGI_GLTF_GUARD_H

#include "context.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What a glTF may ask of the importers (docs: README, "Limits and what is refused"). */
#define VDBGI_GLTF_MAX_NESTING 64            /* JSON arrays and objects inside each other */
#define VDBGI_GLTF_MAX_NODE_DEPTH 256        /* nodes under nodes */
#define VDBGI_GLTF_MAX_TRIANGLES 20000000ull /* every instance counted: about 4 GB to trace */
#define VDBGI_GLTF_MAX_BUFFER (1ull << 31)   /* bytes of one external buffer */

/*
 * Check a glTF (.glb by its magic, .gltf by its name) before any importer
 * parses it: a .glb's chunk sizes against the file, the JSON's nesting, the
 * node hierarchy (indices in range, a forest, its depth), the triangles its
 * instances add up to, and every external buffer and image a regular file
 * (not /proc, /sys or a device) of a sane size. Files of other kinds pass.
 * VDBGI_ERR_FORMAT with the reason, naming the file.
 */
vdbgi_result vdbgi_gltf_precheck(vdbgi_context *ctx, const char *path);

#ifdef __cplusplus
}

namespace tinygltf
{
class TinyGLTF;
}
/* C names (the library's symbols all start vdbgi_), for the two C++ shims alone. */
extern "C" {
/* The shims' tinygltf readers read files only through the guard: regular, of sane size. */
void vdbgi_gltf_guard_files(tinygltf::TinyGLTF &loader);
/* Whether path ends in ext, letter case aside. */
bool vdbgi_gltf_named(const char *path, const char *ext);
}
#endif

#endif /* VDBGI_GLTF_GUARD_H */
