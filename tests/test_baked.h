/* test_baked.h: a lightmap of a scene in memory, for the tests that hold it to closed forms. */
#ifndef VDBGI_TEST_BAKED_H
#define VDBGI_TEST_BAKED_H

#include "lightmap.h"
#include "scene.h"
#include "test_util.h"

typedef struct baked {
    vdbgi_scene *scene;
    vdbgi_unwrap un;
    vdbgi_texels tx;
    vdbgi_lightmap map;
} baked;

/* A lightmap of scene (taken over: unbake destroys it) with bd and lp, in 256-texel atlases. */
static inline bool bake_map(vdbgi_context *ctx, vdbgi_scene *scene, const vdbgi_bake_desc *bd,
                            float texel, const vdbgi_lightmap_params *lp, baked *b)
{
    memset(b, 0, sizeof(*b));
    b->scene = scene;
    vdbgi_bake_params bp;
    CHECK_RESULT(ctx, vdbgi_bake_params_resolve(ctx, bd, scene, &bp), VDBGI_OK);
    const vdbgi_unwrap_params up = {.texel = texel, .size = 256};
    CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, scene, &up, &b->un), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_texels_build(ctx, scene, &b->un, &b->tx), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_lightmap_bake(ctx, scene, &bp, &b->un, &b->tx, lp, &b->map), VDBGI_OK);
    return b->map.rgb != NULL;
}

static inline void unbake(baked *b)
{
    vdbgi_lightmap_free(&b->map);
    vdbgi_texels_free(&b->tx);
    vdbgi_unwrap_free(&b->un);
    vdbgi_scene_destroy(b->scene);
}

#endif /* VDBGI_TEST_BAKED_H */
