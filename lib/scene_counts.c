/*
 * scene_counts.c: the element counts an OFF or PLY header declares, held to
 * the file's bytes, and an OBJ's faces counted, before assimp reads them. assimp reserves what a header
 * says: assimp's own test file invalid/OutOfMemory.off, 309 bytes declaring
 * 3.5 x 10^11 vertices, took 4.6 GB and climbing.
 */
#define _POSIX_C_SOURCE 200809L
#include "context.h"
#include "gltf_shim.h"
#include "util.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

/* The next unsigned decimal number in text at *at (skipping blanks and # comments), or -1. */
static double next_count(const char *text, size_t *at)
{
    size_t i = *at;
    for (;;) {
        while (text[i] && isspace((unsigned char)text[i]))
            i++;
        if (text[i] != '#')
            break;
        while (text[i] && text[i] != '\n')
            i++;
    }
    if (!isdigit((unsigned char)text[i]))
        return -1.0;
    double n = 0.0;
    for (; isdigit((unsigned char)text[i]); i++)
        n = n * 10.0 + (text[i] - '0');
    *at = i;
    return n;
}

/*
 * OFF: a keyword ending in OFF (COFF, NOFF, STOFF...), then the vertex and
 * face counts. A vertex is at least "0 0 0\n" (6 bytes), a face at least
 * "1 0\n" (4).
 */
static double off_least_bytes(const char *text)
{
    size_t i = 0;
    while (isalpha((unsigned char)text[i]))
        i++;
    if (i < 3 || strncmp(&text[i - 3], "OFF", 3) != 0)
        return -1.0;
    const double vertices = next_count(text, &i), faces = next_count(text, &i);
    return vertices < 0.0 || faces < 0.0 ? -1.0 : 6.0 * vertices + 4.0 * faces;
}

/* PLY: every "element NAME COUNT" before end_header; an element is at least one byte. */
static double ply_least_bytes(const char *text)
{
    if (strncmp(text, "ply", 3) != 0 || (text[3] != '\n' && text[3] != '\r'))
        return -1.0;
    double least = 0.0;
    for (const char *line = text; line && strncmp(line, "end_header", 10) != 0;) {
        if (strncmp(line, "element ", 8) == 0) {
            size_t i = 8;
            while (line[i] == ' ')
                i++;
            while (line[i] && !isspace((unsigned char)line[i]))
                i++; /* the element's name */
            const double n = next_count(line, &i);
            least += n > 0.0 ? n : 0.0;
        }
        line = strchr(line, '\n');
        line = line ? line + 1 : NULL;
    }
    return least;
}

/* Does path end in ext (".obj"), in any case? */
static bool has_extension(const char *path, const char *ext)
{
    const size_t n = strlen(path), e = strlen(ext);
    return n >= e && strcasecmp(path + n - e, ext) == 0;
}

/* Reads of faces that repeat a vertex, past which most of a file being so is refused. */
#define OBJ_DEGENERATE_FACES 1000000

/*
 * OBJ has no header: its faces are counted line by line before assimp reads
 * it, which holds about 230 bytes a face whatever the face is (ten million
 * "f 1 1 1", 80 MB of one vertex repeated, took 2.3 GB for no area at all).
 * The triangles its faces make are held to the limit every scene has, and a
 * file whose faces mostly repeat a vertex (past a million) is refused.
 */
static vdbgi_result obj_counts(vdbgi_context *ctx, const char *path, FILE *f)
{
    char *line = NULL;
    size_t capacity = 0;
    uint64_t faces = 0, triangles = 0, degenerate = 0;
    while (getline(&line, &capacity, f) != -1) {
        const char *p = line;
        while (*p == ' ' || *p == '\t')
            p++;
        if (p[0] != 'f' || (p[1] != ' ' && p[1] != '\t'))
            continue;
        p++;
        /* Each corner is "v", "v/vt", "v//vn" or "v/vt/vn": its vertex is what counts. */
        long v[3] = {0, 0, 0};
        uint64_t corners = 0;
        for (;;) {
            while (*p == ' ' || *p == '\t')
                p++;
            if (!*p || *p == '\n' || *p == '\r' || *p == '#')
                break;
            if (corners < 3)
                v[corners] = strtol(p, NULL, 10);
            corners++;
            while (*p && !isspace((unsigned char)*p))
                p++;
        }
        faces++;
        triangles += corners > 2 ? corners - 2 : 0;
        degenerate += corners == 3 && (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]);
    }
    free(line); /* getline's */
    VDBGI_FAIL_IF(ctx, triangles > VDBGI_GLTF_MAX_TRIANGLES, VDBGI_ERR_FORMAT,
                  "%s: its faces make %llu triangles, more than %llu (about 4 GB to trace)", path,
                  (unsigned long long)triangles, VDBGI_GLTF_MAX_TRIANGLES);
    VDBGI_FAIL_IF(ctx, degenerate > OBJ_DEGENERATE_FACES && 2 * degenerate > faces,
                  VDBGI_ERR_FORMAT,
                  "%s: %llu of its %llu faces repeat a vertex (no area), which the importer "
                  "would hold at about 230 bytes each",
                  path, (unsigned long long)degenerate, (unsigned long long)faces);
    return VDBGI_OK;
}

vdbgi_result vdbgi_scene_counts_check(vdbgi_context *ctx, const char *path)
{
    FILE *const f = fopen(path, "rb");
    if (!f)
        return VDBGI_OK; /* the importer names what is wrong */
    if (has_extension(path, ".obj")) {
        const vdbgi_result r = obj_counts(ctx, path, f);
        fclose(f);
        return r;
    }
    char head[4097];
    const size_t got = fread(head, 1, sizeof(head) - 1, f);
    struct stat st;
    const bool sized = fstat(fileno(f), &st) == 0;
    fclose(f);
    head[got] = '\0';
    if (!sized)
        return VDBGI_OK;
    const double off = off_least_bytes(head), ply = ply_least_bytes(head);
    const double least = off >= 0.0 ? off : ply;
    VDBGI_FAIL_IF(ctx, least > (double)st.st_size, VDBGI_ERR_FORMAT,
                  "%s: its %s header declares counts that need at least %.0f bytes; the file has "
                  "%lld",
                  path, off >= 0.0 ? "OFF" : "PLY", least, (long long)st.st_size);
    return VDBGI_OK;
}
