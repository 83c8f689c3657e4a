/* import.c: any assimp format into the triangle soup: meshes under their node transforms,
   materials, embedded and external textures. */
#define _POSIX_C_SOURCE 200809L
#include "gltf_guard.h"
#include "gltf_shim.h"
#include "image_shim.h"
#include "scene.h"

#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static float srgb_to_linear(float c)
{
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

/*
 * Base-colour textures are sRGB (glTF 2.0 spec 3.9.2); alpha stays linear.
 * Values are clamped to [0, 1] first: float images can hold anything.
 */
static void texture_to_linear(vdbgi_texture *t)
{
    for (size_t i = 0; i < (size_t)t->width * (size_t)t->height; i++)
        for (int k = 0; k < 3; k++) {
            const float c = t->rgba[4 * i + k];
            t->rgba[4 * i + k] = srgb_to_linear(c >= 0.0f ? fminf(c, 1.0f) : 0.0f);
        }
}

/* Decode an embedded assimp texture: compressed bytes, or raw BGRA8 texels. */
static vdbgi_result load_embedded(vdbgi_context *ctx, const struct aiTexture *at,
                                  vdbgi_texture *out)
{
    if (at->mHeight == 0)
        return vdbgi_image_decode(ctx, NULL, at->pcData, at->mWidth, at->achFormatHint, out);
    const size_t n = (size_t)at->mWidth * at->mHeight;
    out->rgba = vdbgi_calloc(ctx, n, 4 * sizeof(float));
    if (!out->rgba)
        return VDBGI_ERR_OUT_OF_MEMORY;
    out->width = (int)at->mWidth;
    out->height = (int)at->mHeight;
    for (size_t i = 0; i < n; i++) {
        const struct aiTexel *const px = &at->pcData[i];
        out->rgba[4 * i + 0] = px->r / 255.0f;
        out->rgba[4 * i + 1] = px->g / 255.0f;
        out->rgba[4 * i + 2] = px->b / 255.0f;
        out->rgba[4 * i + 3] = px->a / 255.0f;
    }
    return VDBGI_OK;
}

/*
 * Find a material's texture of the first of types (two) it has and decode it
 * into texture slot `slot`; returns the slot, or -1 when it has none or it
 * does not load. An image an earlier slot holds (sources[i], by the name the
 * scene gives it) is that slot, decoded once however many materials share
 * it (24 materials on one 4096^2 image took 3.4 GB).
 */
static int load_material_texture(vdbgi_scene *s, const struct aiScene *as,
                                 const struct aiMaterial *am, const char *dir,
                                 const enum aiTextureType types[2], size_t slot, char **sources)
{
    vdbgi_context *const ctx = s->ctx;
    struct aiString tex_path;
    if (aiGetMaterialTexture(am, types[0], 0, &tex_path, NULL, NULL, NULL, NULL, NULL, NULL) !=
            aiReturn_SUCCESS &&
        aiGetMaterialTexture(am, types[1], 0, &tex_path, NULL, NULL, NULL, NULL, NULL, NULL) !=
            aiReturn_SUCCESS)
        return -1;
    const char *const p = tex_path.data;
    for (size_t i = 0; i < s->texture_count; i++)
        if (sources[i] && strcmp(sources[i], p) == 0)
            return s->textures[i].width ? (int)i : -1;
    sources[slot] = vdbgi_strdup(ctx, p); /* NULL: only no sharing */
    const struct aiTexture *embedded = NULL;
    if (p[0] == '*') {
        const long i = strtol(p + 1, NULL, 10);
        if (i >= 0 && (unsigned long)i < as->mNumTextures)
            embedded = as->mTextures[i];
    } else {
        for (unsigned i = 0; i < as->mNumTextures; i++)
            if (strcmp(as->mTextures[i]->mFilename.data, p) == 0)
                embedded = as->mTextures[i];
    }
    vdbgi_texture *const tex = &s->textures[slot];
    char error_copy[sizeof(ctx->error)];
    memcpy(error_copy, ctx->error, sizeof(error_copy));
    vdbgi_result r;
    if (embedded) {
        r = load_embedded(ctx, embedded, tex);
    } else {
        /* Relative texture paths are relative to the scene file. */
        const size_t dir_len = p[0] == '/' ? 0 : strlen(dir);
        char *const full = vdbgi_alloc(ctx, dir_len + strlen(p) + 1);
        if (!full)
            return -1; /* the scene allocation that follows will fail the same way */
        memcpy(full, dir, dir_len);
        strcpy(full + dir_len, p);
        r = vdbgi_input_check(ctx, full);
        if (r == VDBGI_OK)
            r = vdbgi_image_decode(ctx, full, NULL, 0, NULL, tex);
        vdbgi_free(ctx, full);
    }
    if (r != VDBGI_OK) {
        /* A missing texture should not sink a bake: warn, keep the base colour. */
        vdbgi_log(ctx, VDBGI_LOG_WARNING, "%s: texture '%s' ignored: %s", s->name, p, ctx->error);
        memcpy(ctx->error, error_copy, sizeof(error_copy));
        return -1;
    }
    texture_to_linear(tex);
    return (int)slot;
}

static float clamp01(float c)
{
    return isfinite(c) ? fminf(fmaxf(c, 0.0f), 1.0f) : 0.0f;
}

/* Whether any glTF material has a strength other than 1 (else there is nothing to find). */
static bool info_has_strength(const vdbgi_gltf_material_info *info, size_t count)
{
    for (size_t g = 0; g < count; g++)
        if (info[g].strength != 1.0f)
            return true;
    return false;
}

static bool same3(const float a[3], const float b[3])
{
    return fabsf(a[0] - b[0]) < 1e-6f && fabsf(a[1] - b[1]) < 1e-6f && fabsf(a[2] - b[2]) < 1e-6f;
}

/* Emission above VDBGI_MAX_EMISSION is capped there (docs/lightmap.md), with one warning. */
static void cap_emission(vdbgi_scene *s, const char *material, float e[3])
{
    const float most = fmaxf(e[0], fmaxf(e[1], e[2]));
    if (!(most > VDBGI_MAX_EMISSION))
        return;
    vdbgi_log(s->ctx, VDBGI_LOG_WARNING, "%s: material '%s': emission %g capped at %g", s->name,
              material, (double)most, (double)VDBGI_MAX_EMISSION);
    for (int k = 0; k < 3; k++)
        e[k] = fminf(e[k], VDBGI_MAX_EMISSION);
}

/*
 * The result of reading from a glTF what assimp drops (the shim leaves none
 * on a failure): out of memory stops the import; a file tinygltf cannot read
 * only loses what, with a warning.
 */
static vdbgi_result what_assimp_drops(vdbgi_scene *s, vdbgi_result read, const char *what)
{
    if (read == VDBGI_OK || read == VDBGI_ERR_OUT_OF_MEMORY)
        return read;
    vdbgi_log(s->ctx, VDBGI_LOG_WARNING, "%s: %s ignored: %s", s->name, what, s->ctx->error);
    s->ctx->error[0] = '\0'; /* a warning, not the import's failure */
    return VDBGI_OK;
}

/*
 * glTF's KHR_materials_emissive_strength, which Debian's assimp 5.2 drops:
 * each emitting material takes the strength of the glTF material it came
 * from. Assimp orders materials as meshes first use them and drops unused
 * ones, so a material is found by its name where that is unique in the
 * file, else by its factors (emissive and base colour) where every glTF
 * material with those factors has the same strength; else it keeps 1, with
 * a warning.
 */
static vdbgi_result apply_emissive_strength(vdbgi_scene *s, const struct aiScene *as,
                                            const char *path)
{
    vdbgi_gltf_material_info *info = NULL;
    size_t count = 0;
    VDBGI_TRY(what_assimp_drops(s, vdbgi_gltf_materials(s->ctx, path, &info, &count),
                                "emissive strength"));
    vdbgi_result r = VDBGI_OK;
    for (size_t m = 0; m < as->mNumMaterials && count; m++) {
        vdbgi_material *const mat = &s->materials[m];
        if (!(mat->emissive[0] > 0.0f || mat->emissive[1] > 0.0f || mat->emissive[2] > 0.0f))
            continue;
        struct aiString name;
        const bool named =
            aiGetMaterialString(as->mMaterials[m], AI_MATKEY_NAME, &name) == aiReturn_SUCCESS &&
            name.length > 0;
        size_t by_name = 0, by_factors = 0, hit = 0;
        bool agree = true;
        for (size_t g = 0; g < count; g++)
            if (named && strcmp(info[g].name, name.data) == 0)
                by_name++, hit = g;
        if (by_name != 1)
            for (size_t g = 0; g < count; g++)
                if (same3(info[g].emissive, mat->emissive) && same3(info[g].base, mat->base)) {
                    agree = agree && (by_factors == 0 || info[g].strength == info[hit].strength);
                    by_factors++, hit = by_factors == 1 ? g : hit;
                }
        if (by_name == 1 || (by_factors > 0 && agree)) {
            const float strength = info[hit].strength;
            if (!(strength >= 0.0f) || !isfinite(strength)) {
                r = vdbgi_fail(s->ctx, VDBGI_ERR_FORMAT,
                               "%s: material '%s': emissive strength %g is not a number >= 0", path,
                               info[hit].name, (double)strength);
                break;
            }
            for (int k = 0; k < 3; k++)
                mat->emissive[k] *= strength;
            cap_emission(s, info[hit].name, mat->emissive);
        } else if (info_has_strength(info, count)) {
            vdbgi_log(s->ctx, VDBGI_LOG_WARNING,
                      "%s: cannot tell which glTF material '%s' is: its emissive strength is taken "
                      "as 1",
                      s->name, named ? name.data : "(unnamed)");
        }
    }
    vdbgi_free(s->ctx, info);
    return r;
}

/*
 * Base colour, sidedness, emission and their textures. Texture slot m holds
 * material m's base colour, slot material_count + m its emission. Emission
 * is glTF's emissiveFactor times KHR_materials_emissive_strength (which
 * Debian's assimp 5.2 does not read: the glTF shim does), or OBJ's Ke.
 */
static vdbgi_result load_materials(vdbgi_scene *s, const struct aiScene *as, const char *path,
                                   const char *dir)
{
    static const enum aiTextureType base_types[2] = {aiTextureType_BASE_COLOR,
                                                     aiTextureType_DIFFUSE};
    static const enum aiTextureType emissive_types[2] = {aiTextureType_EMISSIVE,
                                                         aiTextureType_EMISSION_COLOR};
    bool emits = false;
    char **const sources =
        vdbgi_calloc(s->ctx, s->texture_count ? s->texture_count : 1, sizeof(char *));
    if (!sources)
        return VDBGI_ERR_OUT_OF_MEMORY;
    vdbgi_result r = VDBGI_OK;
    for (size_t m = 0; m < as->mNumMaterials && r == VDBGI_OK; m++) {
        const struct aiMaterial *const am = as->mMaterials[m];
        vdbgi_material *const mat = &s->materials[m];
        struct aiColor4D c;
        if (aiGetMaterialColor(am, AI_MATKEY_BASE_COLOR, &c) != aiReturn_SUCCESS &&
            aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) != aiReturn_SUCCESS)
            c.r = c.g = c.b = 1.0f; /* glTF's default base colour */
        mat->base[0] = clamp01(c.r), mat->base[1] = clamp01(c.g), mat->base[2] = clamp01(c.b);
        int two_sided = 0;
        unsigned int max = 1;
        if (aiGetMaterialIntegerArray(am, AI_MATKEY_TWOSIDED, &two_sided, &max) == aiReturn_SUCCESS)
            mat->double_sided = two_sided != 0;
        mat->texture = load_material_texture(s, as, am, dir, base_types, m, sources);
        if (aiGetMaterialColor(am, AI_MATKEY_COLOR_EMISSIVE, &c) == aiReturn_SUCCESS) {
            /* OBJ's Ke may pass 1 to carry a strength. A negative or NaN one is no light. */
            const float e[3] = {c.r, c.g, c.b};
            struct aiString name;
            const char *const called =
                aiGetMaterialString(am, AI_MATKEY_NAME, &name) == aiReturn_SUCCESS ? name.data
                                                                                   : "(unnamed)";
            if (!(e[0] >= 0.0f && e[1] >= 0.0f && e[2] >= 0.0f)) {
                r = vdbgi_fail(s->ctx, VDBGI_ERR_FORMAT,
                               "%s: material '%s': emissive colour %g,%g,%g is not >= 0", path,
                               called, (double)e[0], (double)e[1], (double)e[2]);
                break;
            }
            memcpy(mat->emissive, e, sizeof(e));
            cap_emission(s, called, mat->emissive);
        }
        if (mat->emissive[0] > 0.0f || mat->emissive[1] > 0.0f || mat->emissive[2] > 0.0f) {
            emits = true;
            mat->emissive_texture = load_material_texture(s, as, am, dir, emissive_types,
                                                          s->material_count + m, sources);
        }
    }
    for (size_t i = 0; i < s->texture_count; i++)
        vdbgi_free(s->ctx, sources[i]);
    vdbgi_free(s->ctx, sources);
    return r == VDBGI_OK && emits ? apply_emissive_strength(s, as, path) : r;
}

typedef struct walk_state {
    vdbgi_scene *s;
    const struct aiScene *as;
    size_t vertex_count, triangle_count, nonfinite;
    bool fill;
} walk_state;

/* A node whose name begins so marks a space what moves uses, not geometry. */
#define KEEP_PREFIX "vdbgi_keep"

static bool is_keep_node(const struct aiNode *node)
{
    const size_t n = sizeof(KEEP_PREFIX) - 1;
    return node->mName.length >= n && memcmp(node->mName.data, KEEP_PREFIX, n) == 0;
}

/* The world bounds of every vertex under node (its meshes and its children's) into box. */
static void bound_nodes(const struct aiScene *as, const struct aiNode *node,
                        const struct aiMatrix4x4 *parent, double box[6])
{
    struct aiMatrix4x4 xf = *parent;
    aiMultiplyMatrix4(&xf, &node->mTransformation);
    for (unsigned n = 0; n < node->mNumMeshes; n++) {
        const struct aiMesh *const mesh = as->mMeshes[node->mMeshes[n]];
        for (unsigned v = 0; v < mesh->mNumVertices; v++) {
            struct aiVector3D p = mesh->mVertices[v];
            aiTransformVecByMatrix4(&p, &xf);
            const double c[3] = {p.x, p.y, p.z};
            for (int k = 0; k < 3; k++)
                if (isfinite(c[k])) {
                    box[k] = fmin(box[k], c[k]);
                    box[3 + k] = fmax(box[3 + k], c[k]);
                }
        }
    }
    for (unsigned c = 0; c < node->mNumChildren; c++)
        bound_nodes(as, node->mChildren[c], &xf, box);
}

/* A vdbgi_keep node: counted, and on the fill pass its box, when it has one and there is room. */
static void keep_node(walk_state *w, const struct aiNode *node, const struct aiMatrix4x4 *parent)
{
    if (!w->fill)
        return;
    vdbgi_scene *const s = w->s;
    s->keep_node_count++;
    double box[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
    bound_nodes(w->as, node, parent, box);
    if (s->keep_box_count < VDBGI_MAX_KEEP_BOXES && box[0] <= box[3] && box[1] <= box[4] &&
        box[2] <= box[5])
        memcpy(s->keep_boxes[s->keep_box_count++], box, sizeof(box));
}

/* Visit every mesh instance with its world transform; count, or fill when w->fill. */
static void walk_nodes(walk_state *w, const struct aiNode *node, const struct aiMatrix4x4 *parent)
{
    if (is_keep_node(node)) {
        keep_node(w, node, parent);
        return;
    }
    struct aiMatrix4x4 xf = *parent;
    aiMultiplyMatrix4(&xf, &node->mTransformation);
    for (unsigned n = 0; n < node->mNumMeshes; n++) {
        const struct aiMesh *const mesh = w->as->mMeshes[node->mMeshes[n]];
        if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
            continue;
        const size_t base = w->vertex_count;
        w->vertex_count += mesh->mNumVertices;
        if (!w->fill) {
            w->triangle_count += mesh->mNumFaces;
            continue;
        }
        vdbgi_scene *const s = w->s;
        for (unsigned v = 0; v < mesh->mNumVertices; v++) {
            struct aiVector3D p = mesh->mVertices[v];
            aiTransformVecByMatrix4(&p, &xf);
            float *const dst = &s->positions[3 * (base + v)];
            dst[0] = p.x, dst[1] = p.y, dst[2] = p.z;
            if (mesh->mTextureCoords[0]) {
                s->uvs[2 * (base + v) + 0] = mesh->mTextureCoords[0][v].x;
                s->uvs[2 * (base + v) + 1] = mesh->mTextureCoords[0][v].y;
            }
            if (mesh->mTextureCoords[1]) {
                s->uvs1[2 * (base + v) + 0] = mesh->mTextureCoords[1][v].x;
                s->uvs1[2 * (base + v) + 1] = mesh->mTextureCoords[1][v].y;
                s->uv1_count++;
            }
            if (mesh->mColors[0]) {
                const struct aiColor4D c = mesh->mColors[0][v];
                const float rgb[3] = {c.r, c.g, c.b};
                for (int k = 0; k < 3; k++)
                    s->colors[3 * (base + v) + k] =
                        isfinite(rgb[k]) ? fminf(fmaxf(rgb[k], 0.0f), 1.0f) : 0.0f;
            }
        }
        for (unsigned f = 0; f < mesh->mNumFaces; f++) {
            const struct aiFace *const face = &mesh->mFaces[f];
            if (face->mNumIndices != 3)
                continue; /* points and lines share meshes with triangles in some files */
            const vdbgi_tri_status st = vdbgi_scene_add_triangle(
                s, (uint32_t)base + face->mIndices[0], (uint32_t)base + face->mIndices[1],
                (uint32_t)base + face->mIndices[2], mesh->mMaterialIndex);
            w->nonfinite += st == VDBGI_TRI_NONFINITE;
            s->skipped_count += st != VDBGI_TRI_KEPT;
        }
    }
    for (unsigned c = 0; c < node->mNumChildren; c++)
        walk_nodes(w, node->mChildren[c], &xf);
}

/* The node named name under node, and its world transform into *xf; NULL if none. */
static const struct aiNode *find_node(const struct aiNode *node, const struct aiString *name,
                                      const struct aiMatrix4x4 *parent, struct aiMatrix4x4 *xf)
{
    struct aiMatrix4x4 m = *parent;
    aiMultiplyMatrix4(&m, &node->mTransformation);
    if (node->mName.length == name->length &&
        memcmp(node->mName.data, name->data, name->length) == 0) {
        *xf = m;
        return node;
    }
    for (unsigned c = 0; c < node->mNumChildren; c++) {
        const struct aiNode *const n = find_node(node->mChildren[c], name, &m, xf);
        if (n)
            return n;
    }
    return NULL;
}

/*
 * The scene's punctual lights: assimp's, placed by the node of the same
 * name (a light no node holds lights nothing), with glTF's range, which
 * assimp 5.2 drops, read from the file (lights keep the file's order).
 */
static vdbgi_result load_lights(vdbgi_scene *s, const struct aiScene *as, const char *path)
{
    if (!as->mNumLights)
        return VDBGI_OK;
    float *ranges = NULL;
    size_t range_count = 0;
    VDBGI_TRY(what_assimp_drops(s, vdbgi_gltf_light_ranges(s->ctx, path, &ranges, &range_count),
                                "light ranges"));
    if (range_count != as->mNumLights && ranges) {
        vdbgi_log(s->ctx, VDBGI_LOG_WARNING, "%s: %zu glTF lights but %u imported: ranges ignored",
                  s->name, range_count, as->mNumLights);
        range_count = 0;
    }
    vdbgi_light lights[VDBGI_MAX_LIGHTS];
    size_t n = 0;
    vdbgi_result r = VDBGI_OK;
    struct aiMatrix4x4 identity;
    aiIdentityMatrix4(&identity);
    for (unsigned i = 0; i < as->mNumLights && r == VDBGI_OK; i++) {
        const struct aiLight *const al = as->mLights[i];
        const vdbgi_light_type type = al->mType == aiLightSource_DIRECTIONAL
                                          ? VDBGI_LIGHT_DIRECTIONAL
                                      : al->mType == aiLightSource_POINT ? VDBGI_LIGHT_POINT
                                      : al->mType == aiLightSource_SPOT  ? VDBGI_LIGHT_SPOT
                                                                         : 0;
        struct aiMatrix4x4 xf;
        if (!type || !find_node(as->mRootNode, &al->mName, &identity, &xf))
            continue;
        if (n == VDBGI_MAX_LIGHTS) {
            r = vdbgi_fail(s->ctx, VDBGI_ERR_FORMAT, "%s: more than %d lights", path,
                           VDBGI_MAX_LIGHTS);
            break;
        }
        vdbgi_light *const l = &lights[n++];
        memset(l, 0, sizeof(*l));
        l->type = type;
        struct aiVector3D p = al->mPosition, d = al->mDirection;
        aiTransformVecByMatrix4(&p, &xf);
        struct aiMatrix3x3 rot;
        aiMatrix3FromMatrix4(&rot, &xf);
        aiTransformVecByMatrix3(&d, &rot);
        l->position[0] = p.x, l->position[1] = p.y, l->position[2] = p.z;
        l->direction[0] = d.x, l->direction[1] = d.y, l->direction[2] = d.z;
        l->color[0] = al->mColorDiffuse.r, l->color[1] = al->mColorDiffuse.g;
        l->color[2] = al->mColorDiffuse.b;
        l->range = i < range_count ? ranges[i] : 0.0f;
        if (type == VDBGI_LIGHT_SPOT)
            l->inner_cone = al->mAngleInnerCone, l->outer_cone = al->mAngleOuterCone;
        const size_t len =
            al->mName.length < sizeof(l->name) - 1 ? al->mName.length : sizeof(l->name) - 1;
        memcpy(l->name, al->mName.data, len); /* a longer name is cut: it is for messages */
    }
    vdbgi_free(s->ctx, ranges);
    if (r == VDBGI_OK && (r = vdbgi_scene_add_lights(s, lights, n)) != VDBGI_OK) {
        char why[512];
        snprintf(why, sizeof(why), "%s", vdbgi_context_error(s->ctx));
        r = vdbgi_fail(s->ctx, VDBGI_ERR_FORMAT, "%s: %s", path, why);
    }
    return r;
}

static const char *base_name(const char *path)
{
    const char *const slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

vdbgi_result vdbgi_scene_load(vdbgi_context *ctx, const char *path, vdbgi_scene **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_TRY(vdbgi_input_check(ctx, path));
    VDBGI_TRY(vdbgi_gltf_precheck(ctx, path));
    VDBGI_TRY(vdbgi_scene_counts_check(ctx, path));

    const struct aiScene *const as = aiImportFile(
        path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure);
    if (!as || !as->mRootNode) {
        const char *const why = aiGetErrorString();
        vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: cannot import scene: %s", path,
                   why && *why ? why : "unknown format");
        aiReleaseImport(as);
        return VDBGI_ERR_FORMAT;
    }
    struct aiMatrix4x4 identity;
    aiIdentityMatrix4(&identity);
    walk_state w = {.as = as};
    walk_nodes(&w, as->mRootNode, &identity);
    if (w.triangle_count == 0 || w.vertex_count > UINT32_MAX) {
        vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: %s", path,
                   w.triangle_count ? "too many vertices" : "no triangles to trace");
        aiReleaseImport(as);
        return VDBGI_ERR_FORMAT;
    }
    vdbgi_scene *s = NULL;
    vdbgi_result r = vdbgi_scene_alloc(ctx, base_name(path), w.vertex_count, w.triangle_count,
                                       as->mNumMaterials ? as->mNumMaterials : 1,
                                       2 * (as->mNumMaterials ? as->mNumMaterials : 1), &s);
    if (r != VDBGI_OK) {
        aiReleaseImport(as);
        return r;
    }
    const size_t dir_len = (size_t)(base_name(path) - path);
    char *const dir = vdbgi_alloc(ctx, dir_len + 1);
    if (!dir) {
        vdbgi_scene_destroy(s);
        aiReleaseImport(as);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    memcpy(dir, path, dir_len);
    dir[dir_len] = '\0';
    for (size_t m = 0; m < s->material_count; m++)
        s->materials[m].base[0] = s->materials[m].base[1] = s->materials[m].base[2] = 1.0f;
    r = load_materials(s, as, path, dir);
    vdbgi_free(ctx, dir);
    if (r != VDBGI_OK) {
        aiReleaseImport(as);
        vdbgi_scene_destroy(s);
        return r;
    }
    w = (walk_state){.s = s, .as = as, .fill = true};
    walk_nodes(&w, as->mRootNode, &identity);
    r = load_lights(s, as, path);
    aiReleaseImport(as);
    if (r != VDBGI_OK) {
        vdbgi_scene_destroy(s);
        return r;
    }
    r = vdbgi_scene_finish(s, w.nonfinite);
    if (r != VDBGI_OK) {
        vdbgi_scene_destroy(s);
        return r;
    }
    *out = s;
    return VDBGI_OK;
}
