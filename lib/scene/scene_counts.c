/*
 * scene_counts.c: the element counts an OFF or PLY header declares, held to
 * the file's bytes, and an OBJ's faces counted, before assimp reads them. assimp reserves what a header
 * says: assimp's own test file invalid/OutOfMemory.off, 309 bytes declaring
 * 3.5 x 10^11 vertices, took 4.6 GB and climbing.
 */
#define _POSIX_C_SOURCE 200809L
#include "context.h"
#include "gltf_guard.h"
#include "util.h"

#include <assimp/cimport.h>

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

/* Faces without area, past which most of a file being so is refused. */
#define OBJ_DEGENERATE_FACES 1000000

/*
 * OBJ has no header: its faces are counted before assimp reads it, which
 * holds about 230 bytes a face whatever the face is (ten million "f 1 1 1",
 * 80 MB of one vertex repeated, took 2.3 GB for no area at all). The scan
 * streams the bytes (a line may be the whole file) and splits lines where
 * assimp does: at \n, \r, \f and \0, a backslash before one continuing it.
 */
typedef struct obj_scan {
    enum { LINE_START, MAYBE_FACE, OTHER_LINE, FACE_BLANK, FACE_TOKEN, FACE_COMMENT } state;
    bool backslash, skip_lf;
    uint64_t faces, triangles, degenerate;
    /* The face being read: its corners, the first three vertices, whether all are one. */
    uint64_t corners;
    long long v[3], value;
    bool negative, slash, all_same;
} obj_scan;

static bool obj_blank(int c)
{
    return c == ' ' || c == '\t' || c == '\v';
}

/* A corner's vertex is the number before its first '/' ("v", "v/vt", "v//vn"). */
static void obj_token_end(obj_scan *s)
{
    const long long v = s->negative ? -s->value : s->value;
    if (s->corners < 3)
        s->v[s->corners] = v;
    s->all_same = s->all_same && (s->corners == 0 || v == s->v[0]);
    s->corners++;
}

static void obj_line_end(obj_scan *s)
{
    if (s->state == FACE_TOKEN)
        obj_token_end(s);
    if (s->state == FACE_BLANK || s->state == FACE_TOKEN || s->state == FACE_COMMENT) {
        const long long *const v = s->v;
        s->faces++;
        s->triangles += s->corners > 2 ? s->corners - 2 : 0;
        s->degenerate += s->corners < 3 || s->all_same ||
                         (s->corners == 3 && (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]));
    }
    s->state = LINE_START;
}

static void obj_byte(obj_scan *s, int c)
{
    const bool line_end = c == '\n' || c == '\r' || c == '\f' || c == '\0';
    if (s->skip_lf) {
        s->skip_lf = false;
        if (c == '\n')
            return;
    }
    if (s->backslash) {
        s->backslash = false;
        if (line_end) { /* the line goes on: the two are a blank */
            s->skip_lf = c == '\r';
            c = ' ';
        } else if (s->state == FACE_TOKEN) {
            obj_token_end(s);
            s->state = FACE_BLANK;
        }
    } else if (c == '\\') {
        s->backslash = true;
        return;
    } else if (line_end) {
        obj_line_end(s);
        return;
    }
    switch (s->state) {
    case LINE_START:
        if (!obj_blank(c))
            s->state = c == 'f' ? MAYBE_FACE : OTHER_LINE;
        break;
    case MAYBE_FACE:
        if (obj_blank(c)) {
            s->state = FACE_BLANK;
            s->corners = 0;
            s->all_same = true;
        } else {
            s->state = OTHER_LINE;
        }
        break;
    case FACE_TOKEN:
        if (obj_blank(c) || c == '#') {
            obj_token_end(s);
            s->state = c == '#' ? FACE_COMMENT : FACE_BLANK;
        } else if (c == '/') {
            s->slash = true;
        } else if (!s->slash && c == '-' && s->value == 0) {
            s->negative = true;
        } else if (!s->slash && c >= '0' && c <= '9' && s->value < 1000000000000000LL) {
            s->value = 10 * s->value + (c - '0');
        }
        break;
    case FACE_BLANK:
        if (c == '#') {
            s->state = FACE_COMMENT;
        } else if (!obj_blank(c)) {
            s->state = FACE_TOKEN;
            s->value = 0;
            s->negative = s->slash = false;
            obj_byte(s, c);
        }
        break;
    case OTHER_LINE:
    case FACE_COMMENT: break;
    }
}

/* The triangles its faces make against the limit every scene has; mostly faces without area. */
static vdbgi_result obj_counts(vdbgi_context *ctx, const char *path, FILE *f)
{
    obj_scan s = {0};
    unsigned char block[65536];
    size_t got;
    while ((got = fread(block, 1, sizeof(block), f)) > 0)
        for (size_t i = 0; i < got; i++)
            obj_byte(&s, block[i]);
    obj_line_end(&s);
    VDBGI_FAIL_IF(ctx, s.triangles > VDBGI_GLTF_MAX_TRIANGLES, VDBGI_ERR_FORMAT,
                  "%s: its faces make %llu triangles, more than %llu (about 4 GB to trace)", path,
                  (unsigned long long)s.triangles, VDBGI_GLTF_MAX_TRIANGLES);
    VDBGI_FAIL_IF(ctx, s.degenerate > OBJ_DEGENERATE_FACES && 2 * s.degenerate > s.faces,
                  VDBGI_ERR_FORMAT,
                  "%s: %llu of its %llu faces have no area (fewer than three vertices, or one "
                  "repeated), and the importer would hold about 230 bytes each",
                  path, (unsigned long long)s.degenerate, (unsigned long long)s.faces);
    return VDBGI_OK;
}

vdbgi_result vdbgi_scene_counts_check(vdbgi_context *ctx, const char *path)
{
    FILE *const f = fopen(path, "rb");
    if (!f)
        return VDBGI_OK; /* the importer names what is wrong */
    /* assimp reads a file whose extension it does not know by its content, OBJ included. */
    const char *const dot = strrchr(path, '.');
    if (!dot || strcasecmp(dot, ".obj") == 0 || !aiIsExtensionSupported(dot)) {
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
