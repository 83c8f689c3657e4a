/* zlib's names that lib/format/gifile.c uses, for the WebAssembly reader (see libdeflate.h). */
#ifndef STUB_ZLIB_H
#define STUB_ZLIB_H
typedef unsigned char Bytef;
typedef unsigned int uInt;
#define Z_OK 0
#define Z_SYNC_FLUSH 2
#define MAX_WBITS 15
typedef struct z_stream_s {
    Bytef *next_in;
    uInt avail_in;
    Bytef *next_out;
    uInt avail_out;
} z_stream;
int inflateInit2(z_stream *s, int bits);
int inflate(z_stream *s, int flush);
int inflateEnd(z_stream *s);
#endif
