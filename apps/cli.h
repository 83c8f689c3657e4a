/* cli.h: what every vdbgi program shares: messages, number parsing, progress. */
#ifndef VDBGI_CLI_H
#define VDBGI_CLI_H

#include "vdbgi.h"

#include <stdbool.h>
#include <stdio.h>

#if defined(__GNUC__)
#define CLI_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define CLI_PRINTF(f, a)
#endif

/* Exit codes of every app. */
enum { CLI_OK = 0, CLI_FAILED = 1, CLI_USAGE = 2 };

/* zstd's levels: 0 quiet, 1 errors, 2 warnings (default), 3 info, 4 debug. */
extern int cli_verbosity;
extern const char *cli_prog;

void cli_init(const char *prog);

/* "prog: message" on stderr (level >= 1). */
void cli_error(const char *fmt, ...) CLI_PRINTF(1, 2);
/* "prog: message" and "try 'prog --help'" on stderr; returns CLI_USAGE. */
int cli_usage_error(const char *fmt, ...) CLI_PRINTF(1, 2);
/* Report a failed library call: "prog: <context error>"; returns CLI_FAILED. */
int cli_fail(const vdbgi_context *ctx, vdbgi_result r);
/* The same about a call that saw no file: "prog: NAME: <context error>". */
int cli_fail_about(const vdbgi_context *ctx, const char *name);

/*
 * The end of every app's argument parsing: c is getopt_long's ':' (missing
 * value) or '?' (unknown option); returns CLI_USAGE after saying which.
 */
int cli_bad_option(int c, char **argv);

/*
 * The options every program takes, last in its getopt_long table (with
 * "qvh" among its short options where it takes -q and -v), and the `default:`
 * of its switch: -q, -v, -h (usage() on stdout), --version, and getopt's
 * errors. Returns -2 when c was -q or -v (go on), else the exit code.
 */
enum { CLI_OPT_VERSION = 999 };
#define CLI_COMMON_LONG_OPTIONS                                                                    \
    {"quiet", no_argument, NULL, 'q'}, {"verbose", no_argument, NULL, 'v'},                        \
        {"help", no_argument, NULL, 'h'}, {"version", no_argument, NULL, CLI_OPT_VERSION},         \
    {                                                                                              \
        NULL, 0, NULL, 0                                                                           \
    }
int cli_common_option(int c, char **argv, void (*usage)(void));

/*
 * Take the one positional argument left after options into *out: returns -1
 * when there is exactly one, else a usage error ("no scene given").
 */
int cli_one_input(int argc, char **argv, const char *what, const char **out);
/* A context that logs through cli_log, or NULL after saying why. */
vdbgi_context *cli_context(void);

/*
 * --memory-limit SIZE (gi-merge and vdb-to-gi, the steps that hold a whole world):
 * bytes, or with K, M, G or T (powers of 1024). Sets cli_memory_limit, which
 * cli_context gives every context; returns -2, or the exit code of a usage
 * error.
 */
enum { CLI_OPT_MEMORY_LIMIT = 998 };
extern size_t cli_memory_limit;
int cli_memory_limit_option(const char *arg);
/*
 * --max-bytes SIZE (the apps that read a .gi): what a volume may unpack to,
 * as vdbgi_context_desc.volume_budget (0, the default: VDBGI_VOLUME_BUDGET).
 * The same sizes as --memory-limit; returns -2 or a usage error's exit code.
 */
extern size_t cli_volume_budget;
int cli_volume_budget_option(const char *arg);

/* Log callback for vdbgi_context_desc: prints by cli_verbosity. */
void cli_log(void *user, vdbgi_log_level level, const char *message);

/*
 * The light model's options, shared by gi-bake and gi-lightmap: put
 * CLI_LIGHT_LONG_OPTIONS in the getopt_long table and hand every option to
 * cli_light_option first. Returns -1 when c is none of them, -2 when it was
 * one and is set in *b, else the exit code of a usage error.
 */
enum {
    CLI_OPT_RAY_DIST = 1000,
    CLI_OPT_AMBIENT,
    CLI_OPT_SUN,
    CLI_OPT_SUN_COLOR,
    CLI_OPT_FALLOFF,
    CLI_OPT_SKY,
    CLI_OPT_SAMPLING,
    CLI_OPT_SEED,
    CLI_OPT_THREADS,
    CLI_OPT_INVALID,
    CLI_OPT_LIGHTS,
    CLI_OPT_MODEL,
    CLI_OPT_SKY_MAP,
    CLI_OPT_SKY_INTENSITY,
    CLI_OPT_SKY_ROTATION,
    CLI_OPT_NOISE,
    CLI_OPT_MAX_RAYS
};
#define CLI_LIGHT_LONG_OPTIONS                                                                     \
    {"ray-dist", required_argument, NULL, CLI_OPT_RAY_DIST},                                       \
        {"ambient", required_argument, NULL, CLI_OPT_AMBIENT},                                     \
        {"sun", required_argument, NULL, CLI_OPT_SUN},                                             \
        {"sun-color", required_argument, NULL, CLI_OPT_SUN_COLOR},                                 \
        {"falloff", required_argument, NULL, CLI_OPT_FALLOFF},                                     \
        {"sky", required_argument, NULL, CLI_OPT_SKY},                                             \
        {"sampling", required_argument, NULL, CLI_OPT_SAMPLING},                                   \
        {"seed", required_argument, NULL, CLI_OPT_SEED},                                           \
        {"threads", required_argument, NULL, CLI_OPT_THREADS},                                     \
        {"invalid-threshold", required_argument, NULL, CLI_OPT_INVALID},                           \
        {"lights", required_argument, NULL, CLI_OPT_LIGHTS},                                       \
        {"model", required_argument, NULL, CLI_OPT_MODEL},                                         \
        {"sky-map", required_argument, NULL, CLI_OPT_SKY_MAP},                                     \
        {"sky-intensity", required_argument, NULL, CLI_OPT_SKY_INTENSITY},                         \
        {"noise", required_argument, NULL, CLI_OPT_NOISE},                                         \
        {"max-rays", required_argument, NULL, CLI_OPT_MAX_RAYS},                                   \
    {                                                                                              \
        "sky-rotation", required_argument, NULL, CLI_OPT_SKY_ROTATION                              \
    }
int cli_light_option(int c, const char *arg, vdbgi_bake_desc *b);
/* --rays N|auto into *b, N in 1..most: -2 when set, else the exit code of a usage error. */
int cli_rays_option(const char *arg, int most, vdbgi_bake_desc *b);

/*
 * The apps bake as a path tracer counts light, with rays by each probe's or
 * texel's spread to VDBGI_NOISE, unless told (the library's zero is the
 * seed's model and its 128 fixed rays): call before parsing. cli_light_check
 * after parsing refuses the seed model's stand-ins under the physical model,
 * and auto's settings beside a fixed --rays N, with a hint; -1 to go on, else
 * the exit code of a usage error.
 */
void cli_light_defaults(vdbgi_bake_desc *b);
int cli_light_check(const vdbgi_bake_desc *b);

/*
 * What the light options leave for later: the sky map to load (path NULL for
 * none) and whether --sun scene asked for the scene's own sun.
 */
typedef struct cli_light_extra {
    const char *sky_map;
    float sky_intensity, sky_rotation;
    bool sun_scene;
} cli_light_extra;
extern cli_light_extra cli_light;

/*
 * After the scene is loaded: the sky map into *sky (the caller destroys it)
 * and b->sky_map, and the check --sun scene makes. -1 to go on, else the
 * exit code of an error it printed.
 */
int cli_light_prepare(vdbgi_context *ctx, const vdbgi_scene *scene, vdbgi_bake_desc *b,
                      vdbgi_sky **sky);

/* Whole-string parses; false on junk, overflow or an empty string. */
bool cli_parse_int(const char *s, long long *out);
bool cli_parse_double(const char *s, double *out); /* accepts "inf" */
bool cli_parse_vec3(const char *s, float out[3]);  /* "x,y,z" */
/* "a,b,..." of exactly n finite numbers. */
bool cli_parse_doubles(const char *s, double *out, int n);

/*
 * A one-line "\r" progress meter on stderr, shown only when stderr is a
 * terminal, verbosity >= 2, and the work has run for more than a second.
 */
typedef struct cli_progress {
    const char *what; /* "baking" */
    const char *unit; /* "probes" */
    double total;     /* units in the whole job */
    double start;     /* cli_now() when the job began */
    bool shown;
} cli_progress;

/*
 * The files a run reads and writes. An output may not be an input or another
 * output (by path or by inode, so through links), and an existing output is
 * replaced only by a file of its own kind: one whose first bytes are magic
 * (an empty file is fine). One line and CLI_FAILED on the first conflict,
 * else -1.
 */
typedef struct cli_file {
    const char *path; /* NULL: not used this run */
    const char *kind; /* "VDB", "KTX2", ...: for the message */
    const char *magic;
    size_t magic_size;
} cli_file;
int cli_check_files(const char *const *inputs, int input_count, const cli_file *outputs,
                    int output_count);

/*
 * Check the run's files (cli_check_files), make the context and hold its
 * outputs until vdbgi_context_commit_outputs (all of a run's outputs, or
 * none). Returns -1 with *ctx set to go on, else the exit code.
 */
int cli_start(const char *const *inputs, int input_count, const cli_file *outputs, int output_count,
              vdbgi_context **ctx);

double cli_now(void);
void cli_progress_begin(cli_progress *p, const char *what, const char *unit, double total);
int cli_progress_update(void *user, float done); /* fits vdbgi's progress callback */
void cli_progress_end(cli_progress *p);

/* Human sizes: "12.3 MB". Returns buf. */
const char *cli_bytes(double bytes, char *buf, size_t cap);
/* The "runtime" line of gi-inspect and vdb-to-gi: what vdbgi's shaders upload. */
void cli_print_runtime(FILE *f, const vdbgi_volume_info *vi);
/* A volume's L2 term bytes a texel, sh_size over the atlas's texels: 14 (.gi version 8, the
   second band in luminance), 24 (6 and 7, all in colour), or 0 (no terms). */
size_t cli_term_bytes(const vdbgi_volume_info *vi);
/* Whether its terms are version 8's: the second band in luminance. */
bool cli_terms_luma2(const vdbgi_volume_info *vi);
/* How its L2 terms are held: "14 bytes a texel: the second band in luminance" or "24 bytes
   a texel: all in colour". */
const char *cli_term_form(const vdbgi_volume_info *vi);
/* s as a JSON string: quoted, quotes, backslashes and control characters escaped. */
void cli_json_string(FILE *f, const char *s);
/*
 * Write what print(f, arg) prints to path, composed in memory and written as
 * the library writes its files (held with the context's other outputs).
 */
vdbgi_result cli_write_printed(vdbgi_context *ctx, const char *path,
                               void (*print)(FILE *f, const void *arg), const void *arg);

#endif /* VDBGI_CLI_H */
