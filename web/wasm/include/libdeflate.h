/* libdeflate's names that lib/format/gifile.c uses, for the WebAssembly reader (web/wasm):
   the browser inflates with DecompressionStream, so only inflated .gi bytes reach it, and
   no-gzip.c's stand-ins, which always fail, are never called. */
#ifndef STUB_LIBDEFLATE_H
#define STUB_LIBDEFLATE_H
#include <stddef.h>
enum libdeflate_result {
    LIBDEFLATE_SUCCESS = 0,
    LIBDEFLATE_BAD_DATA = 1,
    LIBDEFLATE_SHORT_OUTPUT = 2,
    LIBDEFLATE_INSUFFICIENT_SPACE = 3
};
struct libdeflate_compressor;
struct libdeflate_decompressor;
struct libdeflate_compressor *libdeflate_alloc_compressor(int level);
size_t libdeflate_gzip_compress_bound(struct libdeflate_compressor *c, size_t n);
size_t libdeflate_gzip_compress(struct libdeflate_compressor *c, const void *in, size_t n,
                                void *out, size_t cap);
void libdeflate_free_compressor(struct libdeflate_compressor *c);
struct libdeflate_decompressor *libdeflate_alloc_decompressor(void);
enum libdeflate_result libdeflate_gzip_decompress_ex(struct libdeflate_decompressor *d,
                                                     const void *in, size_t in_n, void *out,
                                                     size_t out_n, size_t *in_used,
                                                     size_t *out_got);
void libdeflate_free_decompressor(struct libdeflate_decompressor *d);
#endif
