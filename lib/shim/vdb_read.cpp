/*
 * vdb_read.cpp: probes from a .vdb file, every byte OpenVDB will trust checked
 * first, and the lattice checked against what the rest of vdbgi can take.
 */
#include "shim.h"
#include "util.h"
#include "vdb_layout.h"
#include "vdb_shim.h"

#include <openvdb/io/GridDescriptor.h>
#include <openvdb/openvdb.h>

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace
{

/* Copy the grid's metadata we can represent (other types are skipped). */
void read_meta(const openvdb::GridBase &grid, vdbgi_meta_store *meta)
{
    for (auto it = grid.beginMeta(); it != grid.endMeta(); ++it) {
        const std::string &name = it->first;
        const openvdb::Metadata &md = *it->second;
        if (name.size() >= sizeof(meta->items[0].name))
            continue;
        if (const auto *s = dynamic_cast<const openvdb::StringMetadata *>(&md)) {
            vdbgi_meta_set_string(meta, name.c_str(), s->value().c_str());
        } else if (const auto *i64 = dynamic_cast<const openvdb::Int64Metadata *>(&md)) {
            vdbgi_meta_set_int(meta, name.c_str(), i64->value());
        } else if (const auto *i32 = dynamic_cast<const openvdb::Int32Metadata *>(&md)) {
            vdbgi_meta_set_int(meta, name.c_str(), i32->value());
        } else if (const auto *d = dynamic_cast<const openvdb::DoubleMetadata *>(&md)) {
            vdbgi_meta_set_double(meta, name.c_str(), d->value());
        } else if (const auto *f = dynamic_cast<const openvdb::FloatMetadata *>(&md)) {
            vdbgi_meta_set_double(meta, name.c_str(), f->value());
        } else if (const auto *v = dynamic_cast<const openvdb::Vec3SMetadata *>(&md)) {
            const float xyz[3] = {v->value().x(), v->value().y(), v->value().z()};
            vdbgi_meta_set_vec3(meta, name.c_str(), xyz);
        }
    }
}

} // namespace

namespace
{

/*
 * What the rest of vdbgi can take: one probe per active voxel (no tiles, whose
 * voxels would all be allocated), an axis-aligned lattice of one positive
 * spacing (no rotation, mirror or shear: the .gi box is axis-aligned), sane
 * numbers for the spacing and origin, and indices far enough inside int32 that
 * no cell, block or leaf arithmetic can overflow.
 */
vdbgi_result check_lattice(vdbgi_context *ctx, const char *path, const openvdb::Vec3SGrid &irr)
{
    if (irr.tree().activeTileCount() != 0)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                          "%s: grid 'irradiance' has active tiles: probes are single voxels", path);
    const openvdb::math::Transform &xf = irr.transform();
    if (!xf.isLinear())
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid 'irradiance' has a non-linear transform",
                          path);
    // A spacing out of range first: OpenVDB's affine map refuses a near-singular
    // one (1e-5 m) with an ArithmeticError that says nothing of the lattice.
    const openvdb::Vec3d size = xf.voxelSize();
    for (int k = 0; k < 3; k++)
        if (!(size[k] >= VDBGI_MIN_SPACING && size[k] <= VDBGI_MAX_SPACING))
            return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: probe spacing %g m is outside %g..%g m",
                              path, size[k], VDBGI_MIN_SPACING, VDBGI_MAX_SPACING);
    const openvdb::Mat4d m = xf.baseMap()->getAffineMap()->getMat4();
    const double s = m(0, 0);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            if (r == c ? !(std::fabs(m(r, c) - s) <= 1e-9 * std::fabs(s)) : m(r, c) != 0.0)
                return vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                                  "%s: grid 'irradiance' is rotated, mirrored, sheared or scaled "
                                  "unevenly: probes need an axis-aligned lattice",
                                  path);
    if (!(s >= VDBGI_MIN_SPACING && s <= VDBGI_MAX_SPACING))
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: probe spacing %g m is outside %g..%g m", path,
                          s, VDBGI_MIN_SPACING, VDBGI_MAX_SPACING);
    for (int k = 0; k < 3; k++)
        if (!(std::fabs(m(3, k)) <= VDBGI_MAX_ORIGIN))
            return vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                              "%s: lattice origin %g m on %c is not finite or beyond %g m", path,
                              m(3, k), "xyz"[k], VDBGI_MAX_ORIGIN);
    const openvdb::CoordBBox box = irr.evalActiveVoxelBoundingBox();
    for (int k = 0; k < 3; k++)
        if (!box.empty() && (box.min()[k] < -VDBGI_MAX_INDEX || box.max()[k] > VDBGI_MAX_INDEX))
            return vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                              "%s: probe indices reach %d..%d on %c, beyond +-%d", path,
                              box.min()[k], box.max()[k], "xyz"[k], VDBGI_MAX_INDEX);
    return VDBGI_OK;
}

/* A probe's rays as a file holds them: a float (now) or an Int32 (files before it). */
uint32_t rays_count(float v)
{
    return v > 0.0f ? (v < 4.0e9f ? uint32_t(v) : UINT32_MAX) : 0u; // NaN: 0
}

/* The per-probe extras beside the irradiance: noise, rays, cube sides and L2 terms, at n probes. */
void copy_extras(vdbgi_vdb_arrays *p, size_t n, const openvdb::FloatGrid::Ptr &se,
                 const openvdb::FloatGrid::Ptr &rays, const openvdb::Int32Grid::Ptr &old_rays,
                 const openvdb::Vec3SGrid::Ptr *vec_grids, int vec_count)
{
    if (se || rays || old_rays) {
        // Grids of another type under these names are not ours: left as absent.
        openvdb::FloatGrid::Ptr se_or_empty = se ? se : openvdb::FloatGrid::create();
        openvdb::FloatGrid::Ptr rays_or_empty = rays ? rays : openvdb::FloatGrid::create();
        openvdb::Int32Grid::Ptr old_or_empty = old_rays ? old_rays : openvdb::Int32Grid::create();
        const auto sa = se_or_empty->getConstAccessor();
        const auto ra = rays_or_empty->getConstAccessor();
        const auto oa = old_or_empty->getConstAccessor();
        for (size_t i = 0; i < n; i++) {
            const openvdb::Coord c(p->ijk[3 * i], p->ijk[3 * i + 1], p->ijk[3 * i + 2]);
            if (se)
                p->stderr_[i] = sa.getValue(c);
            if (rays)
                p->rays[i] = rays_count(ra.getValue(c));
            else if (old_rays)
                p->rays[i] = uint32_t(std::max(0, oa.getValue(c)));
        }
    }
    // Cube sides as they are; L2 terms as the probes hold them, ratios to L0 (probes.h).
    for (int e = 0; e < vec_count; e++) {
        const auto a = vec_grids[e]->getConstAccessor();
        for (size_t i = 0; i < n; i++) {
            const openvdb::Vec3s v =
                a.getValue(openvdb::Coord(p->ijk[3 * i], p->ijk[3 * i + 1], p->ijk[3 * i + 2]));
            const size_t at = 3 * (size_t(vec_count) * i + size_t(e));
            for (int k = 0; k < 3; k++)
                if (p->sh)
                    p->sh[at + k] = vdbgi_term_encode(v[k], p->rgb[3 * i + size_t(k)]);
                else
                    p->cube[at + k] = v[k];
        }
    }
}

} // namespace

namespace
{

/* The named grids read through GridLayout, each failure a one-line refusal naming the file. */
template <class F> vdbgi_result read_layout(vdbgi_context *ctx, const char *path, F read)
{
    try {
        read();
    } catch (const GridLayout::OverLimit &) {
        return vdbgi_fail_about(ctx, VDBGI_ERR_OUT_OF_MEMORY, path);
    } catch (const GridLayout::Damaged &d) {
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: %s", path, d.why.c_str());
    } catch (const std::ios_base::failure &) {
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: damaged VDB file (it ends inside a grid)",
                          path);
    } catch (const openvdb::Exception &e) {
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: not a readable VDB file (%s)", path,
                          e.what());
    } catch (const std::bad_alloc &) {
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: damaged VDB file (a size in it is absurd)",
                          path);
    }
    return VDBGI_OK;
}

/* The names of the grids vdbgi reads. */
std::vector<std::string> probe_grid_names()
{
    std::vector<std::string> names{"irradiance", "validity", "stderr", "rays"};
    for (int side = 0; side < 6; side++)
        names.push_back(vdbgi_side_grid_name(side));
    for (int term = 1; term <= 8; term++)
        names.push_back(vdbgi_sh_grid_name(term));
    return names;
}

/*
 * Check the grids read (whole or a region of them) for their types and
 * transform, and copy their values into the sink's arrays (about 70 lines:
 * the OpenVDB objects live only inside the callers' exception boundary).
 */
vdbgi_result to_sink(vdbgi_context *ctx, const char *path, const GridLayout &layout,
                     const openvdb::GridPtrVec &read, vdbgi_vdb_arrays *p)
{
    const auto grid = [&](const char *name) { return layout.find(read, name); };
    const openvdb::GridBase::Ptr base = grid("irradiance"), vbase = grid("validity");
    const openvdb::GridBase::Ptr sebase = grid("stderr"), raysbase = grid("rays");
    if (!base)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: no grid named 'irradiance'", path);
    // A basis is all its grids or none: six cube sides, or eight L2 terms.
    bool has_cube = true, has_sh = true;
    for (int side = 0; side < 6; side++)
        has_cube = has_cube && grid(vdbgi_side_grid_name(side));
    for (int term = 1; term <= 8; term++)
        has_sh = has_sh && grid(vdbgi_sh_grid_name(term));
    const int vec_count = has_cube ? 6 : has_sh ? 8 : 0;
    const auto irr = openvdb::gridPtrCast<openvdb::Vec3SGrid>(base);
    if (!irr)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid 'irradiance' is %s, not vec3s", path,
                          base->valueType().c_str());
    const auto val = openvdb::gridPtrCast<openvdb::FloatGrid>(vbase);
    if (vbase && !val)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid 'validity' is %s, not float", path,
                          vbase->valueType().c_str());
    openvdb::Vec3SGrid::Ptr vec_grids[8];
    for (int e = 0; e < vec_count; e++) {
        const char *const name = has_cube ? vdbgi_side_grid_name(e) : vdbgi_sh_grid_name(e + 1);
        const openvdb::GridBase::Ptr b = grid(name);
        if (!(vec_grids[e] = openvdb::gridPtrCast<openvdb::Vec3SGrid>(b)))
            return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid '%s' is %s, not vec3s", path, name,
                              b->valueType().c_str());
    }
    VDBGI_TRY(check_lattice(ctx, path, *irr));
    if (val && val->tree().activeTileCount() != 0)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                          "%s: grid 'validity' has active tiles: probes are single voxels", path);
    const openvdb::math::Transform &xf = irr->transform();
    const openvdb::Vec3d vs = xf.voxelSize();
    const openvdb::Vec3d o = xf.indexToWorld(openvdb::Vec3d(0.0));
    const size_t count = size_t(irr->activeVoxelCount());
    const auto se = openvdb::gridPtrCast<openvdb::FloatGrid>(sebase);
    const auto rays = openvdb::gridPtrCast<openvdb::FloatGrid>(raysbase);
    const auto old_rays = openvdb::gridPtrCast<openvdb::Int32Grid>(raysbase);
    if (p->make(p, count, se != nullptr, rays || old_rays, has_cube, !has_cube && has_sh) !=
        VDBGI_OK)
        return vdbgi_fail_about(ctx, VDBGI_ERR_OUT_OF_MEMORY, path);
    p->spacing = vs.x();
    p->origin[0] = o.x(), p->origin[1] = o.y(), p->origin[2] = o.z();
    read_meta(*irr, p->meta);
    auto va = val ? std::make_unique<openvdb::FloatGrid::ConstAccessor>(val->getConstAccessor())
                  : nullptr;
    size_t n = 0;
    for (auto it = irr->tree().cbeginValueOn(); it && n < count; ++it, ++n) {
        const openvdb::Coord c = it.getCoord();
        const openvdb::Vec3s v = *it;
        p->ijk[3 * n] = c.x(), p->ijk[3 * n + 1] = c.y(), p->ijk[3 * n + 2] = c.z();
        p->rgb[3 * n] = v.x(), p->rgb[3 * n + 1] = v.y(), p->rgb[3 * n + 2] = v.z();
        p->backface[n] = va ? va->getValue(c) : 0.0f;
    }
    copy_extras(p, n, se, rays, old_rays, vec_grids, vec_count);
    p->count = n;
    return VDBGI_OK;
}

} // namespace

extern "C" vdbgi_result vdbgi_vdb_read(vdbgi_context *ctx, const char *path, vdbgi_vdb_arrays *p)
{
    VDBGI_SHIM_BEGIN
    openvdb::initialize();
    GridLayout layout;
    // Each grid's estimate is held before OpenVDB reads it, then what it holds.
    VdbgiMemoryCharge held(ctx);
    layout.admit = [&](size_t bytes) { return held.hold(held.bytes + bytes); };
    VDBGI_TRY(read_layout(ctx, path, [&] { layout.read(path, probe_grid_names()); }));
    if (!held.hold(vdbgi_grids_bytes(layout.grids)))
        return vdbgi_fail_about(ctx, VDBGI_ERR_OUT_OF_MEMORY, path);
    return to_sink(ctx, path, layout, layout.grids, p);
    VDBGI_SHIM_END_FILE(ctx, "openvdb", path)
}

/* An open .vdb file whose grids were checked once, read a z range at a time. */
struct vdbgi_vdb_regions {
    vdbgi_context *ctx;
    std::string path;
    GridLayout layout;
    std::ifstream is;
    /* The irradiance grid's leaves along x and y: OpenVDB's clip fills every empty
       128-point tile that a region's faces cut across its box, so it is kept tight. */
    openvdb::CoordBBox box;
    /* The file as it was checked: OpenVDB trusts what it reads, so a file rewritten
       in place since open is refused, not read. */
    struct stat checked;
};

namespace
{

bool same_file(const struct stat &a, const struct stat &b)
{
    return a.st_dev == b.st_dev && a.st_ino == b.st_ino && a.st_size == b.st_size &&
           a.st_mtim.tv_sec == b.st_mtim.tv_sec && a.st_mtim.tv_nsec == b.st_mtim.tv_nsec;
}

} // namespace

extern "C" vdbgi_result vdbgi_vdb_regions_open(vdbgi_context *ctx, const char *path,
                                               vdbgi_vdb_regions **out, int32_t lo[3],
                                               int32_t hi[3])
{
    *out = nullptr;
    VDBGI_SHIM_BEGIN
    openvdb::initialize();
    auto f = std::make_unique<vdbgi_vdb_regions>();
    f->ctx = ctx;
    f->path = path;
    if (stat(path, &f->checked) != 0)
        return vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    VDBGI_TRY(read_layout(ctx, path, [&] {
        f->layout.open(f->is, path);
        f->layout.check(f->is, probe_grid_names());
    }));
    struct stat now;
    if (stat(path, &now) != 0 || !same_file(now, f->checked))
        return vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: changed while it was read", path);
    lo[0] = lo[1] = lo[2] = 1, hi[0] = hi[1] = hi[2] = 0;
    bool found = false;
    for (size_t i : f->layout.wanted) {
        const std::string &name = f->layout.descriptors[i].gridName();
        const vdbgi_vdb_tree_counts &n = f->layout.counts[i];
        // Refused as the whole read refuses them, before a clipped read makes tiles its own.
        if (n.tiles && (name == "irradiance" || name == "validity"))
            return vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                              "%s: grid '%s' has active tiles: probes are single voxels", path,
                              name.c_str());
        if (name != "irradiance")
            continue;
        found = true;
        if (n.active) {
            memcpy(lo, n.leaf_min, sizeof(n.leaf_min));
            memcpy(hi, n.leaf_max, sizeof(n.leaf_max));
            f->box = openvdb::CoordBBox(openvdb::Coord(n.leaf_min), openvdb::Coord(n.leaf_max));
        }
    }
    if (!found)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: no grid named 'irradiance'", path);
    *out = f.release();
    return VDBGI_OK;
    VDBGI_SHIM_END_FILE(ctx, "openvdb", path)
}

extern "C" vdbgi_result vdbgi_vdb_regions_read(vdbgi_vdb_regions *f, int32_t z0, int32_t z1,
                                               vdbgi_vdb_arrays *p)
{
    vdbgi_context *const ctx = f->ctx;
    const char *const path = f->path.c_str();
    VDBGI_SHIM_BEGIN
    const openvdb::Coord &lo = f->box.min(), &hi = f->box.max();
    const openvdb::CoordBBox box(openvdb::Coord(lo.x(), lo.y(), z0),
                                 openvdb::Coord(hi.x(), hi.y(), z1 - 1));
    struct stat now;
    if (stat(path, &now) != 0 || !same_file(now, f->checked))
        return vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: changed since it was opened", path);
    openvdb::GridPtrVec read;
    VDBGI_TRY(read_layout(ctx, path, [&] { f->layout.load(f->is, &box, read); }));
    VdbgiMemoryCharge held(ctx);
    if (!held.hold(vdbgi_grids_bytes(read)))
        return vdbgi_fail_about(ctx, VDBGI_ERR_OUT_OF_MEMORY, path);
    return to_sink(ctx, path, f->layout, read, p);
    VDBGI_SHIM_END_FILE(ctx, "openvdb", path)
}

extern "C" void vdbgi_vdb_regions_close(vdbgi_vdb_regions *f)
{
    delete f;
}
