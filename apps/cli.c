/* cli.c: messages, parsing and progress shared by the vdbgi programs. */
#define _XOPEN_SOURCE 700
#include "cli.h"

#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

int cli_verbosity = 2;
const char *cli_prog = "vdbgi";

/* Interrupted or terminated: no temporary file is left, and the signal still ends us. */
static void on_signal(int sig)
{
    vdbgi_remove_temporaries();
    signal(sig, SIG_DFL);
    raise(sig);
}

void cli_init(const char *prog)
{
    cli_prog = prog;
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    signal(SIGHUP, on_signal);
}

static void vmessage(const char *fmt, va_list ap)
{
    fprintf(stderr, "%s: ", cli_prog);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
}

void cli_error(const char *fmt, ...)
{
    if (cli_verbosity < 1)
        return;
    va_list ap;
    va_start(ap, fmt);
    vmessage(fmt, ap);
    va_end(ap);
}

int cli_usage_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vmessage(fmt, ap);
    va_end(ap);
    fprintf(stderr, "try '%s --help'\n", cli_prog);
    return CLI_USAGE;
}

int cli_fail(const vdbgi_context *ctx, vdbgi_result r)
{
    const char *const msg = vdbgi_context_error(ctx);
    cli_error("%s", msg && *msg ? msg : vdbgi_result_string(r));
    return CLI_FAILED;
}

int cli_fail_about(const vdbgi_context *ctx, const char *name)
{
    /* An error from reading the file names it already. */
    const char *const why = vdbgi_context_error(ctx);
    const size_t n = strlen(name);
    if (strncmp(why, name, n) == 0 && why[n] == ':')
        cli_error("%s", why);
    else
        cli_error("%s: %s", name, why);
    return CLI_FAILED;
}

int cli_bad_option(int c, char **argv)
{
    return c == ':' ? cli_usage_error("option '%s' needs a value", argv[optind - 1])
                    : cli_usage_error("unknown option '%s'", argv[optind - 1]);
}

int cli_common_option(int c, char **argv, void (*usage)(void))
{
    switch (c) {
    case 'q': cli_verbosity = 1; return -2;
    case 'v': cli_verbosity++; return -2;
    case 'h': usage(); return CLI_OK;
    case CLI_OPT_VERSION: printf("%s %s\n", cli_prog, vdbgi_version_string()); return CLI_OK;
    default: return cli_bad_option(c, argv);
    }
}

int cli_start(const char *const *inputs, int input_count, const cli_file *outputs, int output_count,
              vdbgi_context **ctx)
{
    *ctx = NULL;
    const int clash = cli_check_files(inputs, input_count, outputs, output_count);
    if (clash >= 0)
        return clash;
    if (!(*ctx = cli_context()))
        return CLI_FAILED;
    vdbgi_context_hold_outputs(*ctx, 1);
    return -1;
}

cli_light_extra cli_light = {NULL, 1.0f, 0.0f, false};

int cli_light_prepare(vdbgi_context *ctx, const vdbgi_scene *scene, vdbgi_bake_desc *b,
                      vdbgi_sky **sky)
{
    *sky = NULL;
    if (cli_light.sun_scene) {
        const vdbgi_light *lights = NULL;
        const size_t n = b->lights == VDBGI_LIGHTS_OFF ? 0 : vdbgi_scene_get_lights(scene, &lights);
        bool found = false;
        for (size_t i = 0; i < n; i++)
            found = found || lights[i].type == VDBGI_LIGHT_DIRECTIONAL;
        if (!found) {
            vdbgi_scene_info si;
            vdbgi_scene_get_info(scene, &si);
            if (b->lights == VDBGI_LIGHTS_OFF)
                cli_error("--sun scene and --lights off leave no sun");
            else
                cli_error("--sun scene: %s has no directional light", si.name);
            return CLI_FAILED;
        }
    }
    if (!cli_light.sky_map)
        return -1;
    const vdbgi_result r = vdbgi_sky_load(ctx, cli_light.sky_map, cli_light.sky_intensity,
                                          cli_light.sky_rotation, sky);
    b->sky_map = *sky;
    return r == VDBGI_OK ? -1 : cli_fail(ctx, r);
}

void cli_light_defaults(vdbgi_bake_desc *b)
{
    b->model = VDBGI_MODEL_PHYSICAL;
    b->adaptive = 1;
}

int cli_light_check(const vdbgi_bake_desc *b)
{
    if (!b->adaptive && (b->noise != 0.0f || b->max_rays != 0))
        return cli_usage_error("--%s is for --rays auto, not a fixed --rays %d",
                               b->noise != 0.0f ? "noise" : "max-rays", b->rays);
    if (b->model != VDBGI_MODEL_PHYSICAL)
        return -1;
    if (b->ambient_is_set)
        return cli_usage_error("--ambient is the seed model's fill: give --model seed with it "
                               "(the physical model's bounces stand in for it)");
    if (b->falloff != 0.0f && !isinf(b->falloff))
        return cli_usage_error("--falloff is the seed model's: give --model seed with it "
                               "(physical light falls off as 1/d^2 by itself)");
    return -1;
}

int cli_rays_option(const char *arg, int most, vdbgi_bake_desc *b)
{
    long long i = 0;
    if (strcmp(arg, "auto") == 0) {
        b->adaptive = 1;
        b->rays = 0;
        return -2;
    }
    if (!cli_parse_int(arg, &i) || i < 1 || i > most)
        return cli_usage_error("--rays must be auto or an integer in 1..%d (got '%s')", most, arg);
    b->rays = (int)i;
    b->adaptive = 0;
    return -2;
}

int cli_light_option(int c, const char *arg, vdbgi_bake_desc *b)
{
    double d = 0.0;
    long long i = 0;
    float v[3];
    switch (c) {
    case CLI_OPT_NOISE:
        if (!cli_parse_double(arg, &d) || !(d > 0.0) || !isfinite(d))
            return cli_usage_error("--noise must be a number > 0 (got '%s')", arg);
        b->noise = (float)d;
        return -2;
    case CLI_OPT_MAX_RAYS:
        if (!cli_parse_int(arg, &i) || i < 64 || i > (1 << 20) || (i & (i - 1)))
            return cli_usage_error("--max-rays must be a power of two in 64..1048576 (got '%s')",
                                   arg);
        b->max_rays = (int)i;
        return -2;
    case CLI_OPT_RAY_DIST:
        if (!cli_parse_double(arg, &d) || !(d > 0.0) || !isfinite(d))
            return cli_usage_error("--ray-dist must be a number > 0 (got '%s')", arg);
        b->ray_dist = (float)d;
        return -2;
    case CLI_OPT_AMBIENT:
        if (!cli_parse_double(arg, &d) || !(d >= 0.0) || !isfinite(d))
            return cli_usage_error("--ambient must be a number >= 0 (got '%s')", arg);
        b->ambient = (float)d;
        b->ambient_is_set = 1;
        return -2;
    case CLI_OPT_SUN:
        cli_light.sun_scene = strcmp(arg, "scene") == 0;
        if (cli_light.sun_scene) {
            memset(b->sun_dir, 0, sizeof(b->sun_dir));
            return -2;
        }
        if (!cli_parse_vec3(arg, v) || (v[0] == 0.0f && v[1] == 0.0f && v[2] == 0.0f))
            return cli_usage_error("--sun must be scene or a non-zero direction x,y,z (got '%s')",
                                   arg);
        memcpy(b->sun_dir, v, sizeof(v));
        return -2;
    case CLI_OPT_LIGHTS:
        if (strcmp(arg, "scene") == 0 || strcmp(arg, "on") == 0)
            b->lights = VDBGI_LIGHTS_SCENE;
        else if (strcmp(arg, "off") == 0)
            b->lights = VDBGI_LIGHTS_OFF;
        else
            return cli_usage_error("--lights must be on or off (got '%s')", arg);
        return -2;
    case CLI_OPT_MODEL:
        if (strcmp(arg, "seed") == 0)
            b->model = VDBGI_MODEL_SEED;
        else if (strcmp(arg, "physical") == 0)
            b->model = VDBGI_MODEL_PHYSICAL;
        else
            return cli_usage_error("--model must be seed or physical (got '%s')", arg);
        return -2;
    case CLI_OPT_SKY_MAP: cli_light.sky_map = arg; return -2;
    case CLI_OPT_SKY_INTENSITY:
        if (!cli_parse_double(arg, &d) || !(d > 0.0 && d <= 1e6))
            return cli_usage_error("--sky-intensity must be a number in (0, 1e6] (got '%s')", arg);
        cli_light.sky_intensity = (float)d;
        return -2;
    case CLI_OPT_SKY_ROTATION:
        if (!cli_parse_double(arg, &d) || !isfinite(d))
            return cli_usage_error("--sky-rotation must be degrees (got '%s')", arg);
        cli_light.sky_rotation = (float)d;
        return -2;
    case CLI_OPT_SUN_COLOR:
        if (!cli_parse_vec3(arg, v) || v[0] < 0.0f || v[1] < 0.0f || v[2] < 0.0f)
            return cli_usage_error("--sun-color must be r,g,b >= 0 (got '%s')", arg);
        memcpy(b->sun_color, v, sizeof(v));
        b->sun_color_is_set = 1;
        return -2;
    case CLI_OPT_FALLOFF:
        if (!cli_parse_double(arg, &d) || !(d > 0.0))
            return cli_usage_error("--falloff must be a number > 0 or inf (got '%s')", arg);
        b->falloff = (float)d;
        return -2;
    case CLI_OPT_SKY:
        if (!cli_parse_vec3(arg, v) || v[0] < 0.0f || v[1] < 0.0f || v[2] < 0.0f)
            return cli_usage_error("--sky must be r,g,b >= 0 (got '%s')", arg);
        memcpy(b->sky, v, sizeof(v));
        return -2;
    case CLI_OPT_SAMPLING:
        if (strcmp(arg, "fibonacci") == 0)
            b->sampling = VDBGI_SAMPLING_FIBONACCI;
        else if (strcmp(arg, "random") == 0)
            b->sampling = VDBGI_SAMPLING_RANDOM;
        else
            return cli_usage_error("--sampling must be fibonacci or random (got '%s')", arg);
        return -2;
    case CLI_OPT_SEED:
        if (!cli_parse_int(arg, &i) || i < 0)
            return cli_usage_error("--seed must be an integer >= 0 (got '%s')", arg);
        b->seed = (uint64_t)i;
        return -2;
    case CLI_OPT_THREADS:
        if (!cli_parse_int(arg, &i) || i < 1 || i > 1024)
            return cli_usage_error("--threads must be an integer in 1..1024 (got '%s')", arg);
        b->threads = (int)i;
        return -2;
    case CLI_OPT_INVALID:
        if (!cli_parse_double(arg, &d) || !(d > 0.0 && d <= 1.0))
            return cli_usage_error("--invalid-threshold must be in (0, 1] (got '%s')", arg);
        b->invalid_threshold = (float)d;
        return -2;
    default: return -1;
    }
}

int cli_one_input(int argc, char **argv, const char *what, const char **out)
{
    if (optind == argc)
        return cli_usage_error("no %s given", what);
    if (argc - optind > 1)
        return cli_usage_error("one %s at a time (got '%s' and '%s')", what, argv[optind],
                               argv[optind + 1]);
    *out = argv[optind];
    return -1;
}

size_t cli_memory_limit = 0;
size_t cli_volume_budget = 0;

/* A size from 1M to 1024T: bytes, or with K, M, G or T (powers of 1024); 0 if it is not one. */
static size_t parse_size(const char *arg)
{
    char *end = NULL;
    errno = 0;
    const double v = strtod(arg, &end);
    double unit = 1.0;
    if (end && *end && !end[1]) {
        const char *const units = "KMGT";
        const char *const u = strchr(units, *end);
        if (u) {
            for (const char *k = units; k <= u; k++)
                unit *= 1024.0;
            end++;
        }
    }
    const double bytes = v * unit;
    if (errno || end == arg || *end || !(bytes >= 1048576.0 && bytes <= 1125899906842624.0))
        return 0;
    return (size_t)bytes;
}

int cli_memory_limit_option(const char *arg)
{
    if (!(cli_memory_limit = parse_size(arg)))
        return cli_usage_error("--memory-limit must be a size from 1M to 1024T (got '%s')", arg);
    return -2;
}

int cli_volume_budget_option(const char *arg)
{
    if (!(cli_volume_budget = parse_size(arg)))
        return cli_usage_error("--max-bytes must be a size from 1M to 1024T (got '%s')", arg);
    return -2;
}

vdbgi_context *cli_context(void)
{
    const vdbgi_context_desc cd = {
        .log = cli_log, .memory_limit = cli_memory_limit, .volume_budget = cli_volume_budget};
    vdbgi_context *ctx = NULL;
    if (vdbgi_context_create(&cd, &ctx) != VDBGI_OK)
        cli_error("cannot create a context: out of memory");
    return ctx;
}

void cli_log(void *user, vdbgi_log_level level, const char *message)
{
    (void)user;
    if ((int)level > cli_verbosity)
        return;
    fprintf(stderr, "%s: %s%s\n", cli_prog, level == VDBGI_LOG_WARNING ? "warning: " : "", message);
}

bool cli_parse_int(const char *s, long long *out)
{
    if (!s || !*s)
        return false;
    char *end = NULL;
    errno = 0;
    const long long v = strtoll(s, &end, 10);
    if (errno || *end)
        return false;
    *out = v;
    return true;
}

bool cli_parse_double(const char *s, double *out)
{
    if (!s || !*s)
        return false;
    char *end = NULL;
    errno = 0;
    const double v = strtod(s, &end);
    if (errno == ERANGE || *end || isnan(v))
        return false;
    *out = v;
    return true;
}

bool cli_parse_doubles(const char *s, double *out, int n)
{
    if (!s)
        return false;
    const char *p = s;
    for (int k = 0; k < n; k++) {
        char *end = NULL;
        errno = 0;
        const double v = strtod(p, &end);
        if (end == p || errno == ERANGE || !isfinite(v))
            return false;
        out[k] = v;
        if (k + 1 < n) {
            if (*end != ',')
                return false;
            p = end + 1;
        } else if (*end) {
            return false;
        }
    }
    return true;
}

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void cli_progress_begin(cli_progress *p, const char *what, const char *unit, double total)
{
    p->what = what;
    p->unit = unit;
    p->total = total;
    p->start = cli_now();
    p->shown = false;
}

int cli_progress_update(void *user, float done)
{
    cli_progress *const p = user;
    const double elapsed = cli_now() - p->start;
    if (cli_verbosity < 2 || elapsed < 1.0 || !isatty(STDERR_FILENO))
        return 0;
    const double units = done * p->total;
    const double rate = units / elapsed;
    const double left = rate > 0.0 ? (p->total - units) / rate : 0.0;
    fprintf(stderr, "\r%s: %s %3.0f%%  %.0f/%.0f %s  %.1fk %s/s  %.0f s left   ", cli_prog, p->what,
            100.0 * done, units, p->total, p->unit, rate / 1000.0, p->unit, left);
    fflush(stderr);
    p->shown = true;
    return 0;
}

void cli_progress_end(cli_progress *p)
{
    if (p->shown) {
        fprintf(stderr, "\r%*s\r", 79, "");
        fflush(stderr);
    }
    p->shown = false;
}

const char *cli_bytes(double bytes, char *buf, size_t cap)
{
    static const char *const units[] = {"B", "kB", "MB", "GB", "TB"};
    int u = 0;
    while (bytes >= 1000.0 && u < 4) {
        bytes /= 1000.0;
        u++;
    }
    snprintf(buf, cap, u ? "%.1f %s" : "%.0f %s", bytes, units[u]);
    return buf;
}

void cli_print_runtime(FILE *f, const vdbgi_volume_info *vi)
{
    char a[32], b[32];
    if (!vi->columns_size) {
        fprintf(f,
                "runtime      too large for vdbgi's runtime: its indirection as columns would "
                "pass %dx%d texels\n",
                VDBGI_COLUMNS_ROW, VDBGI_COLUMNS_ROW);
        return;
    }
    fprintf(f, "runtime      indirection as columns %ux%u texels, %s; VRAM %s\n",
            vi->columns_dims[0], vi->columns_dims[1],
            cli_bytes((double)vi->columns_size, a, sizeof(a)),
            cli_bytes((double)(vi->columns_size + vi->atlas_size + vi->sh_size), b, sizeof(b)));
}

size_t cli_term_bytes(const vdbgi_volume_info *vi)
{
    const size_t texels = vi->atlas_size / 4;
    return texels ? vi->sh_size / texels : 0;
}

bool cli_terms_luma2(const vdbgi_volume_info *vi)
{
    return cli_term_bytes(vi) == 14;
}

const char *cli_term_form(const vdbgi_volume_info *vi)
{
    return cli_terms_luma2(vi) ? "14 bytes a texel: the second band in luminance"
                               : "24 bytes a texel: all in colour";
}

bool cli_parse_vec3(const char *s, float out[3])
{
    double v[3];
    if (!cli_parse_doubles(s, v, 3))
        return false;
    for (int k = 0; k < 3; k++)
        out[k] = (float)v[k];
    return true;
}

/* Where path would be: its directory resolved (links and dots), then its name. */
static void canonical(const char *path, char *out, size_t cap)
{
    char dir[PATH_MAX], real[PATH_MAX];
    const char *const slash = strrchr(path, '/');
    const char *const name = slash ? slash + 1 : path;
    snprintf(dir, sizeof(dir), "%.*s", slash ? (int)(slash - path + (slash == path)) : 1,
             slash ? path : ".");
    if (realpath(dir, real))
        snprintf(out, cap, "%s/%s", real, name);
    else
        snprintf(out, cap, "%s", path);
}

static bool same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) == 0 && stat(b, &sb) == 0)
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    char ca[PATH_MAX + 256], cb[PATH_MAX + 256];
    canonical(a, ca, sizeof(ca));
    canonical(b, cb, sizeof(cb));
    return strcmp(ca, cb) == 0;
}

int cli_check_files(const char *const *inputs, int input_count, const cli_file *outputs,
                    int output_count)
{
    for (int i = 0; i < output_count; i++) {
        const cli_file *const o = &outputs[i];
        if (!o->path)
            continue;
        for (int k = 0; k < input_count; k++)
            if (inputs[k] && same_file(o->path, inputs[k])) {
                cli_error("output '%s' is the input '%s': not replacing it", o->path, inputs[k]);
                return CLI_FAILED;
            }
        for (int j = 0; j < i; j++)
            if (outputs[j].path && same_file(o->path, outputs[j].path)) {
                cli_error("outputs '%s' and '%s' are the same file", outputs[j].path, o->path);
                return CLI_FAILED;
            }
        FILE *const f = fopen(o->path, "rb");
        if (!f)
            continue; /* not there yet (or unwritable: the write will say) */
        char head[16] = {0};
        const size_t n = fread(head, 1, o->magic_size < sizeof(head) ? o->magic_size : 16, f);
        fclose(f);
        if (n > 0 && (n < o->magic_size || memcmp(head, o->magic, o->magic_size) != 0)) {
            cli_error("%s: exists and is not a %s file: not replacing it", o->path, o->kind);
            return CLI_FAILED;
        }
    }
    return -1;
}

/* A path as a JSON string body: quotes, backslashes and control characters escaped. */
void cli_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        const unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

vdbgi_result cli_write_printed(vdbgi_context *ctx, const char *path,
                               void (*print)(FILE *f, const void *arg), const void *arg)
{
    char *text = NULL;
    size_t size = 0;
    FILE *const f = open_memstream(&text, &size);
    if (!f)
        return VDBGI_ERR_OUT_OF_MEMORY;
    print(f, arg);
    const bool ok = !ferror(f) & (fclose(f) == 0);
    const vdbgi_result r =
        ok ? vdbgi_context_write_file(ctx, path, text, size) : VDBGI_ERR_OUT_OF_MEMORY;
    free(text);
    return r;
}
