/*
 * image.c: images in and out through the OpenImageIO module, opened the
 * first time one is needed. Found as $VDBGI_IMAGE_MODULE, else in
 * ../lib/vdbgi/ beside the running program (the build tree and an
 * installed prefix both have it there), else in VDBGI_MODULE_DIR.
 */
#define _GNU_SOURCE
#include "image_shim.h"

#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef VDBGI_MODULE_DIR
#define VDBGI_MODULE_DIR "/usr/local/lib/vdbgi"
#endif

static struct {
    pthread_once_t once;
    vdbgi_image_module_decode_fn *decode;
    vdbgi_image_module_encode_fn *encode;
    char error[512];
} module = {PTHREAD_ONCE_INIT, NULL, NULL, ""};

static const vdbgi_image_host host = {vdbgi_fail, vdbgi_calloc};

static void *open_candidate(const char *path)
{
    void *const h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h && !module.error[0]) {
        const char *const why = dlerror();
        snprintf(module.error, sizeof(module.error), "%s", why ? why : path);
    }
    return h;
}

static void open_module(void)
{
    void *h = NULL;
    const char *const env = getenv("VDBGI_IMAGE_MODULE");
    if (env && *env) {
        h = open_candidate(env);
    } else {
        char exe[PATH_MAX], path[PATH_MAX + 64];
        const ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
        if (n > 0) {
            exe[n] = '\0';
            char *const slash = strrchr(exe, '/');
            if (slash) {
                *slash = '\0';
                snprintf(path, sizeof(path), "%s/../lib/vdbgi/%s", exe, VDBGI_IMAGE_MODULE_NAME);
                h = open_candidate(path);
            }
        }
        if (!h) {
            module.error[0] = '\0';
            h = open_candidate(VDBGI_MODULE_DIR "/" VDBGI_IMAGE_MODULE_NAME);
        }
    }
    if (!h)
        return;
    vdbgi_image_module_init_fn *const init =
        (vdbgi_image_module_init_fn *)dlsym(h, "vdbgi_image_module_init");
    module.decode = (vdbgi_image_module_decode_fn *)dlsym(h, "vdbgi_image_module_decode");
    module.encode = (vdbgi_image_module_encode_fn *)dlsym(h, "vdbgi_image_module_encode");
    if (!init || !module.decode || !module.encode) {
        module.decode = NULL;
        module.encode = NULL;
        snprintf(module.error, sizeof(module.error), "%s lacks its entry points",
                 VDBGI_IMAGE_MODULE_NAME);
        return;
    }
    init(&host);
}

static vdbgi_result ready(vdbgi_context *ctx)
{
    pthread_once(&module.once, open_module);
    VDBGI_FAIL_IF(ctx, !module.decode, VDBGI_ERR_BACKEND,
                  "image support unavailable (set VDBGI_IMAGE_MODULE?): %s", module.error);
    return VDBGI_OK;
}

vdbgi_result vdbgi_image_decode(vdbgi_context *ctx, const char *path, const void *data,
                                size_t data_size, const char *format_hint, vdbgi_image *out)
{
    out->width = out->height = 0;
    out->rgba = NULL;
    VDBGI_TRY(ready(ctx));
    return module.decode(ctx, path, data, data_size, format_hint, out);
}

vdbgi_result vdbgi_image_encode(vdbgi_context *ctx, const char *name, const char *ext, int width,
                                int height, int channels, const float *pixels, bool data,
                                uint8_t **bytes, size_t *size)
{
    *bytes = NULL;
    *size = 0;
    VDBGI_TRY(ready(ctx));
    return module.encode(ctx, name, ext, width, height, channels, pixels, data, bytes, size);
}

vdbgi_result vdbgi_image_write(vdbgi_context *ctx, const char *path, int width, int height,
                               int channels, const float *pixels, bool data)
{
    const char *const dot = strrchr(path, '.');
    const char *const ext = dot ? dot + 1 : "";
    VDBGI_FAIL_IF(ctx, strcmp(ext, "exr") != 0 && strcmp(ext, "png") != 0, VDBGI_ERR_INVALID_ARG,
                  "%s: images are .png or .exr", path);
    VDBGI_TRY(ready(ctx));
    uint8_t *bytes = NULL;
    size_t size = 0;
    vdbgi_result r =
        module.encode(ctx, path, ext, width, height, channels, pixels, data, &bytes, &size);
    if (r == VDBGI_OK)
        r = vdbgi_write_bytes_atomic(ctx, path, bytes, size);
    vdbgi_free(ctx, bytes);
    return r;
}
