/*
 * image_shim.cpp: OpenImageIO behind a C interface; translates, decides
 * nothing. Built as its own shared module (libvdbgi_image.so), which
 * image.c opens the first time an image is read or written: Debian's
 * OpenImageIO brings some 260 libraries, which no bake of an untextured
 * scene and no --help should pay for. It reaches the library only through
 * the host table it is given.
 */
#include "image_shim.h"

static const vdbgi_image_host *host;
#define VDBGI_SHIM_FAIL host->fail
#include "shim.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

using namespace OIIO;

extern "C" VDBGI_MODULE_API void vdbgi_image_module_init(const vdbgi_image_host *h)
{
    host = h;
}

extern "C" VDBGI_MODULE_API vdbgi_result
vdbgi_image_module_decode(vdbgi_context *ctx, const char *path, const void *data, size_t data_size,
                          const char *format_hint, vdbgi_image *out)
{
    VDBGI_SHIM_BEGIN
    out->width = out->height = 0;
    out->rgba = nullptr;
    std::unique_ptr<Filesystem::IOMemReader> mem;
    std::string name;
    if (data) {
        // The plugin is chosen by extension, so give the memory a fake name.
        name = std::string("embedded.") + (format_hint && *format_hint ? format_hint : "png");
        mem.reset(new Filesystem::IOMemReader(const_cast<void *>(data), data_size));
    } else {
        name = path;
    }
    // Keep RGB as stored: by default OIIO would premultiply it by a PNG's alpha.
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    if (mem) {
        // With a config, OIIO 2.4 takes the proxy from it rather than from the argument.
        void *proxy = mem.get();
        config.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy);
    }
    auto in = ImageInput::open(name, &config, mem.get());
    if (!in) {
        const std::string err = OIIO::geterror();
        return host->fail(ctx, VDBGI_ERR_FORMAT, "%s: cannot read image: %s",
                          data ? "embedded texture" : path, err.c_str());
    }
    const ImageSpec &spec = in->spec();
    const int w = spec.width, h = spec.height, nc = spec.nchannels;
    if (w <= 0 || h <= 0 || nc <= 0 || nc > 64 || w > 65536 || h > 65536) {
        return host->fail(ctx, VDBGI_ERR_FORMAT, "%s: unusable image size %dx%dx%d",
                          data ? "embedded texture" : path, w, h, nc);
    }
    // The size comes from the file's header: a few bytes may claim gigabytes of pixels.
    if ((size_t)w * (size_t)h > VDBGI_IMAGE_MAX_PIXELS) {
        return host->fail(ctx, VDBGI_ERR_FORMAT,
                          "%s: %dx%d image is over the %d-megapixel texture limit",
                          data ? "embedded texture" : path, w, h, VDBGI_IMAGE_MAX_PIXELS >> 20);
    }
    std::vector<float> pixels((size_t)w * h * nc);
    if (!in->read_image(0, 0, 0, nc, TypeDesc::FLOAT, pixels.data())) {
        const std::string err = in->geterror();
        return host->fail(ctx, VDBGI_ERR_FORMAT, "%s: cannot decode image: %s",
                          data ? "embedded texture" : path, err.c_str());
    }
    in->close();
    float *const rgba = (float *)host->calloc(ctx, (size_t)w * h, 4 * sizeof(float));
    if (!rgba)
        return VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        const float *const s = &pixels[i * nc];
        float *const d = &rgba[i * 4];
        if (nc >= 3) {
            d[0] = s[0], d[1] = s[1], d[2] = s[2];
            d[3] = nc >= 4 ? s[3] : 1.0f;
        } else {
            d[0] = d[1] = d[2] = s[0];
            d[3] = nc == 2 ? s[1] : 1.0f;
        }
    }
    out->width = w;
    out->height = h;
    out->rgba = rgba;
    return VDBGI_OK;
    VDBGI_SHIM_END(ctx, "openimageio")
}

extern "C" VDBGI_MODULE_API vdbgi_result vdbgi_image_module_encode(
    vdbgi_context *ctx, const char *path, const char *ext, int width, int height, int channels,
    const float *pixels, bool data, uint8_t **bytes, size_t *size)
{
    VDBGI_SHIM_BEGIN
    *bytes = nullptr;
    *size = 0;
    const bool exr = std::strcmp(ext, "exr") == 0;
    auto out = ImageOutput::create(ext);
    if (!out)
        return host->fail(ctx, VDBGI_ERR_BACKEND, "openimageio: no %s writer: %s", ext,
                          OIIO::geterror().c_str());
    if (!out->supports("ioproxy"))
        return host->fail(ctx, VDBGI_ERR_BACKEND,
                          "openimageio: the %s writer cannot write to memory", ext);
    // Half floats hold up to 65504: a map with brighter texels (emission near its cap)
    // is written as 32-bit floats, every texel finite, rather than as Inf.
    bool beyond_half = false;
    const size_t n = size_t(width) * size_t(height) * size_t(channels);
    for (size_t i = 0; exr && i < n && !beyond_half; i++)
        beyond_half = std::fabs(pixels[i]) > 65504.0f;
    ImageSpec spec(width, height, channels,
                   exr ? (beyond_half ? TypeDesc::FLOAT : TypeDesc::HALF) : TypeDesc::UINT8);
    if (exr) {
        spec.attribute("compression", "zip");
        // The same pixels give the same bytes: no time of writing in the header.
        spec.attribute("DateTime", "");
    }
    if (data)
        spec.attribute("oiio:ColorSpace", "Linear");
    // Our alpha is data, not coverage: write RGB as given, never divided by it.
    spec.attribute("oiio:UnassociatedAlpha", 1);
    // Into memory: the library writes the bytes itself and checks every write, which a
    // plugin writing to a full disk may not.
    std::vector<unsigned char> buffer;
    Filesystem::IOVecOutput proxy(buffer);
    if (!(out->set_ioproxy(&proxy) && out->open(std::string("memory.") + ext, spec) &&
          out->write_image(TypeDesc::FLOAT, pixels) && out->close()))
        return host->fail(ctx, VDBGI_ERR_IO, "%s: cannot encode image: %s", path,
                          out->geterror().c_str());
    uint8_t *const b = (uint8_t *)host->calloc(ctx, buffer.size() ? buffer.size() : 1, 1);
    if (!b)
        return VDBGI_ERR_OUT_OF_MEMORY;
    std::memcpy(b, buffer.data(), buffer.size());
    *bytes = b;
    *size = buffer.size();
    return VDBGI_OK;
    VDBGI_SHIM_END(ctx, "openimageio")
}
