/* vdb_shim.cpp: OpenVDB behind a C interface: sets of lattice points, and writing grids. */
#include "vdb_shim.h"
#include "shim.h"
#include "util.h"

#include <openvdb/io/GridDescriptor.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

extern "C" const char *vdbgi_side_grid_name(int side)
{
    static const char *const names[6] = {"irradiance_px", "irradiance_nx", "irradiance_py",
                                         "irradiance_ny", "irradiance_pz", "irradiance_nz"};
    return names[side];
}

extern "C" const char *vdbgi_sh_grid_name(int term)
{
    static const char *const names[8] = {"irradiance_sh1", "irradiance_sh2", "irradiance_sh3",
                                         "irradiance_sh4", "irradiance_sh5", "irradiance_sh6",
                                         "irradiance_sh7", "irradiance_sh8"};
    return names[term - 1];
}

namespace
{

openvdb::math::Transform::Ptr lattice_transform(const double origin[3], double spacing)
{
    auto xf = openvdb::math::Transform::createLinearTransform(spacing);
    xf->postTranslate(openvdb::Vec3d(origin[0], origin[1], origin[2]));
    return xf;
}

void add_meta(openvdb::GridBase &grid, const vdbgi_meta &m)
{
    // Probes read from a file carry OpenVDB's own grid metadata too: its name, class,
    // vector type and file statistics belong to each grid, not to the bake (a copied
    // "name" named every grid of a rewritten file 'irradiance').
    static const char *const owned[] = {
        openvdb::GridBase::META_GRID_NAME,        openvdb::GridBase::META_GRID_CLASS,
        openvdb::GridBase::META_GRID_CREATOR,     openvdb::GridBase::META_VECTOR_TYPE,
        openvdb::GridBase::META_IS_LOCAL_SPACE,   openvdb::GridBase::META_SAVE_HALF_FLOAT,
        openvdb::GridBase::META_FILE_BBOX_MIN,    openvdb::GridBase::META_FILE_BBOX_MAX,
        openvdb::GridBase::META_FILE_COMPRESSION, openvdb::GridBase::META_FILE_MEM_BYTES,
        openvdb::GridBase::META_FILE_VOXEL_COUNT, openvdb::GridBase::META_FILE_DELAYED_LOAD};
    for (const char *name : owned)
        if (std::strcmp(m.name, name) == 0)
            return;
    switch (m.type) {
    case VDBGI_META_STRING: grid.insertMeta(m.name, openvdb::StringMetadata(m.text)); break;
    case VDBGI_META_INT: grid.insertMeta(m.name, openvdb::Int64Metadata(m.i)); break;
    case VDBGI_META_DOUBLE: grid.insertMeta(m.name, openvdb::DoubleMetadata(m.d)); break;
    case VDBGI_META_VEC3:
        grid.insertMeta(m.name, openvdb::Vec3SMetadata(openvdb::Vec3s(m.v[0], m.v[1], m.v[2])));
        break;
    }
}

} // namespace

struct vdbgi_vdb_mask {
    openvdb::MaskGrid::Ptr grid;
};

extern "C" vdbgi_result vdbgi_vdb_mask_create(vdbgi_context *ctx, vdbgi_vdb_mask **out)
{
    VDBGI_SHIM_BEGIN
    *out = nullptr;
    openvdb::initialize();
    std::unique_ptr<vdbgi_vdb_mask> mask(new vdbgi_vdb_mask);
    mask->grid = openvdb::MaskGrid::create();
    *out = mask.release();
    return VDBGI_OK;
    VDBGI_SHIM_END(ctx, "openvdb")
}

extern "C" void vdbgi_vdb_mask_destroy(vdbgi_vdb_mask *mask)
{
    delete mask;
}

extern "C" vdbgi_result vdbgi_vdb_mask_add_leaf(vdbgi_vdb_mask *mask, const int32_t origin[3],
                                                const uint64_t bits[8])
{
    try {
        auto *leaf = mask->grid->tree().touchLeaf(openvdb::Coord(origin[0], origin[1], origin[2]));
        auto &on = leaf->getValueMask();
        for (openvdb::Index w = 0; w < 8; w++)
            on.template getWord<openvdb::Index64>(w) |= bits[w];
        return VDBGI_OK;
    } catch (const std::bad_alloc &) {
        return VDBGI_ERR_OUT_OF_MEMORY;
    } catch (...) {
        return VDBGI_ERR_BACKEND;
    }
}

extern "C" vdbgi_result vdbgi_vdb_mask_merge(vdbgi_context *ctx, vdbgi_vdb_mask *mask,
                                             const vdbgi_vdb_mask *from)
{
    VDBGI_SHIM_BEGIN
    mask->grid->tree().topologyUnion(from->grid->tree());
    return VDBGI_OK;
    VDBGI_SHIM_END(ctx, "openvdb")
}

extern "C" vdbgi_result vdbgi_vdb_mask_points(vdbgi_context *ctx, const vdbgi_vdb_mask *mask,
                                              uint64_t max_count, int32_t **ijk_out,
                                              size_t *count_out)
{
    VDBGI_SHIM_BEGIN
    *ijk_out = nullptr;
    *count_out = 0;
    const uint64_t count = mask->grid->tree().activeVoxelCount();
    if (count > max_count) {
        return vdbgi_fail(ctx, VDBGI_ERR_OUT_OF_MEMORY,
                          "lattice would hold %llu probes (%.1f GiB), above the limit of %llu",
                          (unsigned long long)count,
                          double(count) * VDBGI_BYTES_PER_PROBE / (1 << 30),
                          (unsigned long long)max_count);
    }
    int32_t *const ijk = (int32_t *)vdbgi_calloc(ctx, count ? count : 1, 3 * sizeof(int32_t));
    if (!ijk)
        return VDBGI_ERR_OUT_OF_MEMORY;
    size_t n = 0;
    for (auto it = mask->grid->tree().cbeginValueOn(); it; ++it) {
        const openvdb::Coord c = it.getCoord();
        ijk[3 * n + 0] = c.x();
        ijk[3 * n + 1] = c.y();
        ijk[3 * n + 2] = c.z();
        n++;
    }
    *ijk_out = ijk;
    *count_out = n;
    return VDBGI_OK;
    VDBGI_SHIM_END(ctx, "openvdb")
}

namespace
{

/*
 * io::File::write's archive (seekable, so readers can find each grid), on a
 * stream of ours that is checked: io::File::write never looks at its stream
 * again, and a full disk left a truncated file behind a success. Grids go
 * out one at a time, as Archive::write lays them out (header, no file
 * metadata, the count, then each grid under its own name), so a caller can
 * build each just before it is written and free it just after: a bake's
 * grids need not all be in memory at once.
 */
class GridWriter : openvdb::io::Archive
{
  public:
    GridWriter(const char *path, int32_t count)
    {
        errno = 0;
        os_.open(path, std::ios_base::out | std::ios_base::binary | std::ios_base::trunc);
        if (!os_) {
            err_ = errno;
            return;
        }
        openvdb::io::setDataCompression(os_, compression());
        openvdb::io::setWriteGridStatsMetadata(os_, isGridStatsMetadataEnabled());
        writeHeader(os_, /*seekable=*/true);
        openvdb::MetaMap().writeMeta(os_);
        os_.write(reinterpret_cast<const char *>(&count), sizeof(count));
        note_failure();
    }

    /* False once a write failed: what follows would go nowhere. */
    bool good() const
    {
        return bool(os_);
    }

    /* Grid names must be unique and not empty, as this writer's are. */
    void write_grid(const openvdb::GridBase::ConstPtr &grid)
    {
        if (!os_)
            return;
        errno = 0;
        openvdb::io::GridDescriptor gd(grid->getName(), grid->type(), grid->saveFloatAsHalf());
        writeGrid(gd, grid, os_, /*seekable=*/true);
        openvdb::io::setDataCompression(os_, compression()); // mask compression is per grid
        note_failure();
    }

    /* Flush and close; false (error() says why, where errno did) if any write failed. */
    bool close()
    {
        errno = 0;
        os_.flush();
        note_failure();
        os_.close();
        note_failure();
        return bool(os_);
    }

    int error() const
    {
        return err_;
    }

  private:
    /* The errno of the first write that failed (a full disk), before later calls touch it. */
    void note_failure()
    {
        if (!os_ && !err_)
            err_ = errno;
    }

    std::ofstream os_;
    int err_ = 0;
};

vdbgi_result write_failed(vdbgi_context *ctx, const char *name, int err)
{
    return vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: cannot write: %s", name,
                      err ? std::strerror(err) : "write failed");
}

/*
 * A grid of the probes' lattice, its value at probe n from value(n); the
 * light's grids (not stderr and rays, which never said) say their class.
 */
template <class G, class F>
typename G::Ptr probe_grid(const vdbgi_vdb_arrays *p, const char *name,
                           const openvdb::math::Transform &xf, const vdbgi_meta_store *meta,
                           bool light, F value)
{
    auto g = G::create(typename G::ValueType(0));
    g->setName(name);
    g->setTransform(xf.copy());
    if (light)
        g->setGridClass(openvdb::GRID_UNKNOWN);
    {
        auto a = g->getAccessor();
        for (size_t n = 0; n < p->count; n++)
            a.setValue(openvdb::Coord(p->ijk[3 * n], p->ijk[3 * n + 1], p->ijk[3 * n + 2]),
                       value(n));
    }
    for (size_t m = 0; m < meta->count; m++)
        add_meta(*g, meta->items[m]);
    return g;
}

} // namespace

extern "C" vdbgi_result vdbgi_vdb_write(vdbgi_context *ctx, const char *path, const char *name,
                                        const vdbgi_vdb_arrays *p, const vdbgi_meta_store *meta)
{
    VDBGI_SHIM_BEGIN
    openvdb::initialize();
    const auto xf = lattice_transform(p->origin, p->spacing);
    const int extra = p->cube ? 6 : p->sh ? 8 : 0;
    GridWriter out(path, int32_t(2 + (p->stderr_ != nullptr) + (p->rays != nullptr) + extra));
    if (!out.good())
        return write_failed(ctx, name, out.error());
    const auto rgb = [](const float *c) { return openvdb::Vec3s(c[0], c[1], c[2]); };
    {
        auto irr = probe_grid<openvdb::Vec3SGrid>(p, "irradiance", *xf, meta, true,
                                                  [&](size_t n) { return rgb(&p->rgb[3 * n]); });
        // A colour is not a direction: it must not turn with the transform.
        irr->setVectorType(openvdb::VEC_INVARIANT);
        out.write_grid(irr);
    }
    out.write_grid(probe_grid<openvdb::FloatGrid>(p, "validity", *xf, meta, true,
                                                  [&](size_t n) { return p->backface[n]; }));
    // Sampling noise per probe, and the rays an adaptive bake spent on it: a float grid
    // (whole numbers up to 2^20, exact), which every reader opens; pyopenvdb reads no Int32.
    if (p->stderr_)
        out.write_grid(probe_grid<openvdb::FloatGrid>(p, "stderr", *xf, meta, false,
                                                      [&](size_t n) { return p->stderr_[n]; }));
    if (p->rays)
        out.write_grid(probe_grid<openvdb::FloatGrid>(p, "rays", *xf, meta, false,
                                                      [&](size_t n) { return float(p->rays[n]); }));
    // Ambient-cube sides or L2 terms: one Vec3s grid each, built as it is written. The
    // terms are held as ratios to L0 (vdbgi_term_encode); the file has the terms themselves.
    for (int e = 0; e < extra && out.good(); e++) {
        const auto term = [&](size_t n) {
            float c[3];
            for (size_t k = 0; k < 3; k++)
                c[k] = vdbgi_term_decode(p->sh[24 * n + 3 * size_t(e) + k], p->rgb[3 * n + k]);
            return rgb(c);
        };
        auto g = p->cube ? probe_grid<openvdb::Vec3SGrid>(
                               p, vdbgi_side_grid_name(e), *xf, meta, true,
                               [&](size_t n) { return rgb(&p->cube[18 * n + 3 * size_t(e)]); })
                         : probe_grid<openvdb::Vec3SGrid>(p, vdbgi_sh_grid_name(e + 1), *xf, meta,
                                                          true, term);
        g->setVectorType(openvdb::VEC_INVARIANT);
        out.write_grid(g);
    }
    return out.close() ? VDBGI_OK : write_failed(ctx, name, out.error());
    VDBGI_SHIM_END(ctx, "openvdb")
}

namespace
{

/* Move b's leaves into a when both are grids of type G (tiles hold disjoint leaves). */
template <class G> bool merge_as(const openvdb::GridBase::Ptr &a, const openvdb::GridBase::Ptr &b)
{
    const auto ga = openvdb::GridBase::grid<G>(a);
    const auto gb = openvdb::GridBase::grid<G>(b);
    if (!ga || !gb)
        return false;
    ga->tree().merge(gb->tree(), openvdb::MERGE_ACTIVE_STATES);
    return true;
}

/* The names of the grids a tile holds, in its order, read without their trees. */
std::vector<std::string> tile_grids(const char *path)
{
    openvdb::io::File file(path);
    file.open(false);
    const openvdb::GridPtrVecPtr grids = file.readAllGridMetadata();
    file.close();
    std::vector<std::string> out;
    for (const auto &g : *grids)
        out.push_back(g->getName());
    return out;
}

} // namespace

/*
 * One grid at a time: each is read from every tile, merged, written and
 * freed before the next, so the merge holds one grid of the whole lattice
 * (and the tiles' copies of it), not every grid of every tile.
 */
extern "C" vdbgi_result vdbgi_vdb_merge(vdbgi_context *ctx, const char *path, const char *name,
                                        const char *const *tiles, size_t count,
                                        const char *const *drop, size_t drop_count,
                                        const vdbgi_meta_store *set)
{
    VDBGI_SHIM_BEGIN
    openvdb::initialize();
    const auto names = tile_grids(tiles[0]);
    for (size_t t = 1; t < count; t++) {
        const auto other = tile_grids(tiles[t]);
        if (other.size() != names.size())
            return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: %zu grids, where %s has %zu", tiles[t],
                              other.size(), tiles[0], names.size());
        for (const auto &g : other)
            if (std::find(names.begin(), names.end(), g) == names.end())
                return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid '%s' is not in %s", tiles[t],
                                  g.c_str(), tiles[0]);
    }
    GridWriter out(path, int32_t(names.size()));
    if (!out.good())
        return write_failed(ctx, name, out.error());
    for (const auto &n : names) {
        if (!out.good()) // a full disk: the rest would go nowhere
            break;
        VdbgiMemoryCharge held(ctx); // this grid's tiles read so far: the merge moves their leaves
        openvdb::GridBase::Ptr whole;
        for (size_t t = 0; t < count; t++) {
            openvdb::io::File file(tiles[t]);
            file.open(false); // read it now: the file is closed before the next one
            const openvdb::GridBase::Ptr g = file.readGrid(n);
            file.close();
            if (!held.hold(held.bytes + vdbgi_grids_bytes(openvdb::GridPtrVec{g})))
                return vdbgi_fail_about(ctx, VDBGI_ERR_OUT_OF_MEMORY, tiles[t]);
            if (t == 0)
                whole = g;
            else if (!merge_as<openvdb::Vec3SGrid>(whole, g) &&
                     !merge_as<openvdb::FloatGrid>(whole, g) &&
                     !merge_as<openvdb::Int32Grid>(whole, g))
                return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid '%s' (%s) is not one of ours",
                                  tiles[t], g->getName().c_str(), g->type().c_str());
        }
        for (size_t d = 0; d < drop_count; d++)
            whole->removeMeta(drop[d]);
        for (size_t m = 0; m < set->count; m++)
            add_meta(*whole, set->items[m]);
        out.write_grid(whole);
    }
    return out.close() ? VDBGI_OK : write_failed(ctx, name, out.error());
    VDBGI_SHIM_END(ctx, "openvdb")
}
