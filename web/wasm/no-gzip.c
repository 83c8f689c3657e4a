/* Every gzip entry point fails: the WebAssembly reader reads inflated .gi bytes only. */
#include "libdeflate.h"
#include "zlib.h"
struct libdeflate_compressor *libdeflate_alloc_compressor(int level)
{
    (void)level;
    return 0;
}
size_t libdeflate_gzip_compress_bound(struct libdeflate_compressor *c, size_t n)
{
    (void)c;
    (void)n;
    return 0;
}
size_t libdeflate_gzip_compress(struct libdeflate_compressor *c, const void *in, size_t n,
                                void *out, size_t cap)
{
    (void)c;
    (void)in;
    (void)n;
    (void)out;
    (void)cap;
    return 0;
}
void libdeflate_free_compressor(struct libdeflate_compressor *c)
{
    (void)c;
}
struct libdeflate_decompressor *libdeflate_alloc_decompressor(void)
{
    return 0;
}
enum libdeflate_result libdeflate_gzip_decompress_ex(struct libdeflate_decompressor *d,
                                                     const void *in, size_t in_n, void *out,
                                                     size_t out_n, size_t *in_used, size_t *out_got)
{
    (void)d;
    (void)in;
    (void)in_n;
    (void)out;
    (void)out_n;
    (void)in_used;
    (void)out_got;
    return LIBDEFLATE_BAD_DATA;
}
void libdeflate_free_decompressor(struct libdeflate_decompressor *d)
{
    (void)d;
}
int inflateInit2(z_stream *s, int bits)
{
    (void)s;
    (void)bits;
    return -1;
}
int inflate(z_stream *s, int flush)
{
    (void)s;
    (void)flush;
    return -1;
}
int inflateEnd(z_stream *s)
{
    (void)s;
    return 0;
}
