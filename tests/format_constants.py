#!/usr/bin/env python3
"""format_constants.py ROOT: the .gi format's constants in the JavaScript
runtime (web/) against the C headers and tables they were copied from
(issue 38, item 4). Each pair is read from both sides' source text, so a
change to one side alone fails here; a name that is no longer found fails
too. Prints one line a disagreement, then how many pairs agree."""
import re
import sys

ROOT = sys.argv[1]


def text(path):
    with open(f"{ROOT}/{path}") as f:
        return f.read()


def number(expr):
    """A C or JS integer or float literal, a shift of two (1 << 24) or a quotient (1.0f / 2)."""
    expr = re.sub(r"\((size_t|uint32_t)\)", "", expr).strip().strip("()")
    m = re.fullmatch(r"(\d+)\s*<<\s*(\d+)", expr)
    if m:
        return int(m.group(1)) << int(m.group(2))
    m = re.fullmatch(r"([0-9.]+)f?\s*/\s*([0-9.]+)f?", expr)
    if m:
        return float(m.group(1)) / float(m.group(2))
    return float(expr.rstrip("fu"))


def c_define(path, name):
    m = re.search(rf"^#define {name}\s+(.+?)\s*(/\*.*)?$", text(path), re.M)
    if not m:
        raise KeyError(f"{path}: no #define {name}")
    return number(m.group(1))


def c_enum(path, name):
    m = re.search(rf"\b{name}\s*=\s*([0-9]+)", text(path))
    if not m:
        raise KeyError(f"{path}: no enumerator {name}")
    return number(m.group(1))


def c_floats(path, name):
    """The floats of an initialiser `name[...] = {...}` (nested braces flattened)."""
    m = re.search(rf"\b{name}(\[\d*\])+\s*=\s*\{{(.*?)\}};", text(path), re.S)
    if not m:
        raise KeyError(f"{path}: no table {name}")
    return [number(v) for v in re.findall(r"[-0-9.]+f?", m.group(2))]


def js_const(path, name):
    m = re.search(rf"\b{name}\s*=\s*([^,;\n]+)", text(path))
    if not m:
        raise KeyError(f"{path}: no const {name}")
    value = m.group(1).strip()
    if value.startswith("Object.freeze("):
        return None
    return number(value)


def js_array(path, name):
    m = re.search(rf"\b{name}\s*=\s*Object\.freeze\((\[.*?\])\);", text(path), re.S)
    if not m:
        raise KeyError(f"{path}: no array {name}")
    return [number(v) for v in re.findall(r"[-0-9.]+", m.group(1))]


def js_match(path, pattern):
    m = re.search(pattern, text(path))
    if not m:
        raise KeyError(f"{path}: nothing matches {pattern}")
    return number(m.group(1))


GIH, SAMP, API = "lib/format/gifile.h", "lib/format/sampler.h", "lib/vdbgi.h"
LAT = "lib/core/lattice.h"
FMT, PACKED, RUNTIME = "web/gi-format.js", "web/gi-packed.js", "web/vdbgi.js"
STREAM = "web/gi-stream.js"
PAIRS = [
    ("header bytes", lambda: js_const(FMT, "HEADER_BYTES"), lambda: c_define(GIH, "VDBGI_GI_HEADER_SIZE")),
    ("newest version", lambda: js_match(FMT, r"version < 1 \|\| version > (\d+)"),
     lambda: c_define(GIH, "VDBGI_GI_VERSION")),
    ("L2 term bytes, versions 6 and 7", lambda: js_const(PACKED, "SH_BYTES"), lambda: c_define(GIH, "VDBGI_SH_BYTES")),
    ("L2 term bytes, version 8", lambda: js_const(PACKED, "SH_BYTES_LUMA2"),
     lambda: c_define(GIH, "VDBGI_SH_BYTES_LUMA2")),
    ("header bytes, versions 6 to 8", lambda: js_const(FMT, "HEADER_BYTES_V6"),
     lambda: c_define(GIH, "VDBGI_GI_HEADER_MAX")),
    ("RGBM encoding", lambda: js_const(FMT, "ENCODING_RGBM"), lambda: c_enum(API, "VDBGI_ENCODING_RGBM")),
    ("RGB9E5 encoding", lambda: js_const(FMT, "ENCODING_RGB9E5"), lambda: c_enum(API, "VDBGI_ENCODING_RGB9E5")),
    ("seed layout", lambda: js_const(FMT, "LAYOUT_SEED"), lambda: c_enum(API, "VDBGI_LAYOUT_SEED")),
    ("compact layout", lambda: js_const(FMT, "LAYOUT_COMPACT"), lambda: c_enum(API, "VDBGI_LAYOUT_COMPACT")),
    ("old seed layout", lambda: js_const(FMT, "OLD_LAYOUT_SEED"), lambda: c_define(GIH, "VDBGI_GI_LAYOUT_SEED_OLD")),
    ("old compact layout", lambda: js_const(FMT, "OLD_LAYOUT_COMPACT"),
     lambda: c_define(GIH, "VDBGI_GI_LAYOUT_COMPACT_OLD")),
    ("scalar basis", lambda: js_const(FMT, "BASIS_SCALAR"), lambda: c_enum(API, "VDBGI_BASIS_SCALAR")),
    ("L2 basis", lambda: js_const(FMT, "BASIS_SH2"), lambda: c_enum(API, "VDBGI_BASIS_SH2")),
    ("sparse cells", lambda: js_const(FMT, "SPARSE_CELLS"), lambda: c_define(GIH, "VDBGI_SPARSE_CELLS")),
    ("volume budget", lambda: js_const(STREAM, "MAX_BYTES"), lambda: c_define(API, "VDBGI_VOLUME_BUDGET")),
    ("compact atlas side", lambda: js_const(FMT, "ATLAS_MAX"), lambda: c_define(GIH, "VDBGI_ATLAS_MAX")),
    ("columns texture row", lambda: js_const(FMT, "COLUMNS_ROW_MAX"), lambda: c_define(API, "VDBGI_COLUMNS_ROW")),
    ("compact brick side (format)", lambda: js_match(FMT, r"LAYOUT_COMPACT \? \{ brick: (\d+)"),
     lambda: c_define(SAMP, "VDBGI_BRICK_COMPACT")),
    ("seed brick side, padded", lambda: js_match(FMT, r": \{ brick: (\d+), pad: 1"),
     lambda: c_define(SAMP, "VDBGI_BRICK_PADDED")),
    ("compact brick side (packed)", lambda: js_const(PACKED, "N"), lambda: c_define(SAMP, "VDBGI_BRICK_COMPACT")),
    ("texels a compact brick", lambda: js_const(PACKED, "TEXELS"), lambda: c_define(SAMP, "VDBGI_BRICK_COMPACT") ** 3),
    ("atlas texels a brick brings", lambda: js_const(PACKED, "ATLAS_TEXELS_PER_BRICK"),
     lambda: c_define(GIH, "VDBGI_ATLAS_TEXELS_PER_BRICK")),
    ("L2 terms' ranges (encoder)", lambda: js_array(FMT, "SH2_RANGE"), lambda: c_floats("lib/core/encode.c", "range")),
    ("L2 terms' ranges (sampler)", lambda: js_array(FMT, "SH2_RANGE"), lambda: c_floats("lib/format/sampler.c", "range")),
    ("level colours", lambda: js_array(RUNTIME, "LEVEL_COLOURS"), lambda: c_floats("lib/convert/slices.c", "colour")),
    ("least RGBM range", lambda: js_const(FMT, "RANGE_MIN"), lambda: c_define(GIH, "VDBGI_GI_RANGE_MIN")),
    ("largest RGBM range", lambda: js_const(FMT, "RANGE_MAX"), lambda: c_define(GIH, "VDBGI_GI_RANGE_MAX")),
    ("least spacing", lambda: js_const(FMT, "MIN_SPACING"), lambda: c_define(LAT, "VDBGI_MIN_SPACING")),
    ("largest spacing", lambda: js_const(FMT, "MAX_SPACING"), lambda: c_define(LAT, "VDBGI_MAX_SPACING")),
    ("farthest lattice origin", lambda: js_const(FMT, "MAX_ORIGIN"), lambda: c_define(LAT, "VDBGI_MAX_ORIGIN")),
    ("largest lattice index", lambda: js_const(FMT, "MAX_INDEX"), lambda: c_define(LAT, "VDBGI_MAX_INDEX")),
]

agree = 0
for what, js, c in PAIRS:
    try:
        a, b = js(), c()
    except KeyError as e:
        print(f"{what}: {e}")
        continue
    if a == b:
        agree += 1
    else:
        print(f"{what}: JavaScript {a}, C {b}")
print(f"{agree} of {len(PAIRS)} pairs of constants agree")
