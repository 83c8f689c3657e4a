/* convert_report.h: vdb-to-gi's options, and what it prints of a conversion (convert_report.c). */
#ifndef VDBGI_CONVERT_REPORT_H
#define VDBGI_CONVERT_REPORT_H

#include "vdbgi.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef struct options {
    const char *input, *output, *slices, *stats, *bevy, *bevy_baked_gi;
    size_t memory_peak; /* the most the context held, once converted */
    int region;         /* lattice points a region, 0: the whole lattice at once */
    vdbgi_bevy_format bevy_format;
    vdbgi_bevy_desc bevy_desc;
    vdbgi_convert_desc convert;
    vdbgi_axis axis;
    double slice_at, exposure; /* NAN: automatic */
    double budget;             /* --budget in bytes, 0: none */
    int budget_tries;          /* conversions built to fit it */
    float budget_eps;          /* the one that fitted (or the smallest): its eps */
    bool budget_terms;         /* and whether it kept the L2 terms */
    size_t budget_smallest;    /* the least VRAM a conversion took */
} options;

/* The conversion's figures, as text or as JSON. */
void print_stats(FILE *f, const options *o, const vdbgi_volume_info *vi,
                 const vdbgi_probes_info *pi, double read_seconds, bool json);
/* The Bevy volume's size, box and files, on stdout. */
void print_bevy(const vdbgi_bevy *b, const options *o);

/* What the JSON statistics are printed from, for cli_write_printed's print_json. */
typedef struct stats_args {
    const options *o;
    const vdbgi_volume_info *vi;
    const vdbgi_probes_info *pi;
    double read_seconds;
} stats_args;
void print_json(FILE *f, const void *arg);

#endif /* VDBGI_CONVERT_REPORT_H */
