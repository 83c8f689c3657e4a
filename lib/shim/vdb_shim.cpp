/* vdb_shim.cpp: OpenVDB behind a C interface: sets of lattice points, and writing grids. */
#include "vdb_shim.h"
#include "shim.h"

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

/* io::File::write's archive (seekable, so readers can find each grid), on a given stream. */
struct CheckedWriter : openvdb::io::Archive {
    void write_to(std::ostream &os, const openvdb::GridPtrVec &grids) const
    {
        write(os, grids, /*seekable=*/true);
    }
};

/* Write grids to path through CheckedWriter; messages say name. */
vdbgi_result write_grids(vdbgi_context *ctx, const char *path, const char *name,
                         const openvdb::GridPtrVec &grids)
{
    // io::File::write never looks at its stream again: a full disk left a truncated file
    // behind a success. The same archive, written to a stream of ours that is checked.
    std::ofstream os(path, std::ios_base::out | std::ios_base::binary | std::ios_base::trunc);
    if (!os)
        return vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: cannot write: %s", name, std::strerror(errno));
    errno = 0;
    CheckedWriter().write_to(os, grids);
    os.flush();
    const int err = errno;
    os.close();
    if (!os)
        return vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: cannot write: %s", name,
                          err ? std::strerror(err) : "write failed");
    return VDBGI_OK;
}

} // namespace

extern "C" vdbgi_result vdbgi_vdb_write(vdbgi_context *ctx, const char *path, const char *name,
                                        const vdbgi_vdb_arrays *p, const vdbgi_meta_store *meta)
{
    VDBGI_SHIM_BEGIN
    openvdb::initialize();
    const auto xf = lattice_transform(p->origin, p->spacing);
    auto irr = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    auto val = openvdb::FloatGrid::create(0.0f);
    irr->setName("irradiance");
    val->setName("validity");
    irr->setTransform(xf);
    val->setTransform(xf->copy());
    irr->setGridClass(openvdb::GRID_UNKNOWN);
    val->setGridClass(openvdb::GRID_UNKNOWN);
    // A colour is not a direction: it must not turn with the transform.
    irr->setVectorType(openvdb::VEC_INVARIANT);
    {
        auto ia = irr->getAccessor();
        auto va = val->getAccessor();
        for (size_t n = 0; n < p->count; n++) {
            const openvdb::Coord c(p->ijk[3 * n], p->ijk[3 * n + 1], p->ijk[3 * n + 2]);
            ia.setValue(c, openvdb::Vec3s(p->rgb[3 * n], p->rgb[3 * n + 1], p->rgb[3 * n + 2]));
            va.setValue(c, p->backface[n]);
        }
    }
    openvdb::GridPtrVec grids{irr, val};
    if (p->stderr_ || p->rays) {
        // Sampling noise per probe, and the rays an adaptive bake spent on it.
        auto se = openvdb::FloatGrid::create(0.0f);
        auto rays = openvdb::Int32Grid::create(0);
        se->setName("stderr");
        rays->setName("rays");
        se->setTransform(xf->copy());
        rays->setTransform(xf->copy());
        auto sa = se->getAccessor();
        auto ra = rays->getAccessor();
        for (size_t n = 0; n < p->count; n++) {
            const openvdb::Coord c(p->ijk[3 * n], p->ijk[3 * n + 1], p->ijk[3 * n + 2]);
            if (p->stderr_)
                sa.setValue(c, p->stderr_[n]);
            if (p->rays)
                ra.setValue(c, int32_t(p->rays[n]));
        }
        if (p->stderr_)
            grids.push_back(se);
        if (p->rays)
            grids.push_back(rays);
    }
    // Ambient-cube sides or L2 terms: one Vec3s grid each, sharing the topology.
    const int extra = p->cube ? 6 : p->sh ? 8 : 0;
    for (int e = 0; e < extra; e++) {
        const float *const values = p->cube ? p->cube : p->sh;
        const int stride = p->cube ? 18 : 24;
        auto g = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
        g->setName(p->cube ? vdbgi_side_grid_name(e) : vdbgi_sh_grid_name(e + 1));
        g->setTransform(xf->copy());
        g->setGridClass(openvdb::GRID_UNKNOWN);
        g->setVectorType(openvdb::VEC_INVARIANT);
        auto a = g->getAccessor();
        for (size_t n = 0; n < p->count; n++) {
            const float *const c = &values[stride * n + 3 * e];
            a.setValue(openvdb::Coord(p->ijk[3 * n], p->ijk[3 * n + 1], p->ijk[3 * n + 2]),
                       openvdb::Vec3s(c[0], c[1], c[2]));
        }
        grids.push_back(g);
    }
    for (auto &g : grids)
        for (size_t m = 0; m < meta->count; m++)
            add_meta(*g, meta->items[m]);
    return write_grids(ctx, path, name, grids);
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

} // namespace

extern "C" vdbgi_result vdbgi_vdb_merge(vdbgi_context *ctx, const char *path, const char *name,
                                        const char *const *tiles, size_t count,
                                        const char *const *drop, size_t drop_count,
                                        const vdbgi_meta_store *set)
{
    VDBGI_SHIM_BEGIN
    openvdb::initialize();
    openvdb::GridPtrVec whole;
    VdbgiMemoryCharge held(ctx); // the tiles read so far: the merge moves their leaves
    for (size_t t = 0; t < count; t++) {
        openvdb::io::File file(tiles[t]);
        file.open(false); // read it all now: the file is closed before the next one
        const openvdb::GridPtrVecPtr grids = file.getGrids();
        file.close();
        if (!held.hold(held.bytes + vdbgi_grids_bytes(*grids)))
            return vdbgi_fail_about(ctx, VDBGI_ERR_OUT_OF_MEMORY, tiles[t]);
        if (t == 0) {
            whole = *grids;
            continue;
        }
        if (grids->size() != whole.size())
            return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: %zu grids, where %s has %zu", tiles[t],
                              grids->size(), tiles[0], whole.size());
        for (const auto &g : *grids) {
            const auto into = std::find_if(whole.begin(), whole.end(), [&](const auto &w) {
                return w->getName() == g->getName();
            });
            if (into == whole.end())
                return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid '%s' is not in %s", tiles[t],
                                  g->getName().c_str(), tiles[0]);
            if (!merge_as<openvdb::Vec3SGrid>(*into, g) &&
                !merge_as<openvdb::FloatGrid>(*into, g) && !merge_as<openvdb::Int32Grid>(*into, g))
                return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid '%s' (%s) is not one of ours",
                                  tiles[t], g->getName().c_str(), g->type().c_str());
        }
    }
    for (auto &g : whole) {
        for (size_t d = 0; d < drop_count; d++)
            g->removeMeta(drop[d]);
        for (size_t m = 0; m < set->count; m++)
            add_meta(*g, set->items[m]);
    }
    return write_grids(ctx, path, name, whole);
    VDBGI_SHIM_END(ctx, "openvdb")
}
