/*
 * image_shim.h: C interface to the only code that includes OpenImageIO.
 * vdbgi_image_decode and vdbgi_image_write (image.c) open the module
 * libvdbgi_image.so (image_shim.cpp) on first use and call into it.
 */
#ifndef VDBGI_IMAGE_SHIM_H
#define VDBGI_IMAGE_SHIM_H

#include "context.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest image decoded, in pixels (16 M, 256 MB as floats): 4096 x 4096 textures fit. */
#define VDBGI_IMAGE_MAX_PIXELS (16 << 20)

/* A decoded image: width x height pixels of 4 floats, row 0 at the top. */
typedef struct vdbgi_image {
    int width, height;
    float *rgba;
} vdbgi_image;

/*
 * Decode an image into out->rgba (4 floats per pixel, values as stored,
 * no colour conversion, row 0 at the top), allocated through ctx. Either
 * path names a file, or data/data_size hold an encoded file in memory whose
 * format is named by format_hint ("png", "jpg", ...). Grey images are
 * replicated to RGB; missing alpha is 1.
 */
vdbgi_result vdbgi_image_decode(vdbgi_context *ctx, const char *path, const void *data,
                                size_t data_size, const char *format_hint, vdbgi_image *out);

/*
 * Write a width x height image of `channels` floats per pixel (row 0 at the
 * top) to path, through a temporary file renamed when complete. The format
 * follows the extension: .png stores 8 bits per channel (values are clamped
 * to [0, 1]: encode them first), .exr stores half floats as given. With
 * data set, a PNG is tagged as linear values (gAMA 1.0), not sRGB colour.
 */
vdbgi_result vdbgi_image_write(vdbgi_context *ctx, const char *path, int width, int height,
                               int channels, const float *pixels, bool data);

/*
 * The same image encoded in memory ("png" or "exr") into *bytes, allocated
 * through ctx; name is only for messages.
 */
vdbgi_result vdbgi_image_encode(vdbgi_context *ctx, const char *name, const char *ext, int width,
                                int height, int channels, const float *pixels, bool data,
                                uint8_t **bytes, size_t *size);

/* What the module may call in the library: it links against none of it. */
typedef struct vdbgi_image_host {
    vdbgi_result (*fail)(vdbgi_context *ctx, vdbgi_result code, const char *fmt, ...)
        VDBGI_PRINTF(3, 4);
    void *(*calloc)(vdbgi_context *ctx, size_t count, size_t size);
} vdbgi_image_host;

#define VDBGI_MODULE_API __attribute__((visibility("default")))
#define VDBGI_IMAGE_MODULE_NAME "libvdbgi_image.so"

/* The module's entry points, looked up by these names. */
typedef void vdbgi_image_module_init_fn(const vdbgi_image_host *host);
typedef vdbgi_result vdbgi_image_module_decode_fn(vdbgi_context *ctx, const char *path,
                                                  const void *data, size_t data_size,
                                                  const char *format_hint, vdbgi_image *out);
/* Encode the image in the format ext ("png" or "exr") into *bytes (through host->calloc). */
typedef vdbgi_result vdbgi_image_module_encode_fn(vdbgi_context *ctx, const char *path,
                                                  const char *ext, int width, int height,
                                                  int channels, const float *pixels, bool data,
                                                  uint8_t **bytes, size_t *size);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_IMAGE_SHIM_H */
