/* lattice.h: what a probe lattice may be, for the bake, the files and the converter alike. */
#ifndef VDBGI_LATTICE_H
#define VDBGI_LATTICE_H

/*
 * What a lattice may be, so that no index arithmetic (cells, blocks, leaves,
 * their neighbours) can overflow int32 and no .gi box is meaningless.
 */
#define VDBGI_MAX_INDEX (1 << 26)
#define VDBGI_MIN_SPACING 1e-4 /* metres */
#define VDBGI_MAX_SPACING 1e4
#define VDBGI_MAX_ORIGIN 1e9

#endif /* VDBGI_LATTICE_H */
