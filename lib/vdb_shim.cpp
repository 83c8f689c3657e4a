/* vdb_shim.cpp: OpenVDB behind a C interface: topology, grid files, metadata. */
#include "vdb_shim.h"
#include "shim.h"

#include <openvdb/io/GridDescriptor.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <vector>

namespace
{

const char *const side_grid_names[6] = {"irradiance_px", "irradiance_nx", "irradiance_py",
                                        "irradiance_ny", "irradiance_pz", "irradiance_nz"};

openvdb::math::Transform::Ptr lattice_transform(const double origin[3], double spacing)
{
    auto xf = openvdb::math::Transform::createLinearTransform(spacing);
    xf->postTranslate(openvdb::Vec3d(origin[0], origin[1], origin[2]));
    return xf;
}

void add_meta(openvdb::GridBase &grid, const vdbgi_meta &m)
{
    switch (m.type) {
    case VDBGI_META_STRING: grid.insertMeta(m.name, openvdb::StringMetadata(m.text)); break;
    case VDBGI_META_INT: grid.insertMeta(m.name, openvdb::Int64Metadata(m.i)); break;
    case VDBGI_META_DOUBLE: grid.insertMeta(m.name, openvdb::DoubleMetadata(m.d)); break;
    case VDBGI_META_VEC3:
        grid.insertMeta(m.name, openvdb::Vec3SMetadata(openvdb::Vec3s(m.v[0], m.v[1], m.v[2])));
        break;
    }
}

/* Copy the grid's metadata we can represent into probes (other types are skipped). */
void read_meta(const openvdb::GridBase &grid, vdbgi_probes *p)
{
    for (auto it = grid.beginMeta(); it != grid.endMeta(); ++it) {
        const std::string &name = it->first;
        const openvdb::Metadata &md = *it->second;
        if (name.size() >= sizeof(p->meta.items[0].name))
            continue;
        if (const auto *s = dynamic_cast<const openvdb::StringMetadata *>(&md)) {
            vdbgi_meta_set_string(&p->meta, name.c_str(), s->value().c_str());
        } else if (const auto *i64 = dynamic_cast<const openvdb::Int64Metadata *>(&md)) {
            vdbgi_meta_set_int(&p->meta, name.c_str(), i64->value());
        } else if (const auto *i32 = dynamic_cast<const openvdb::Int32Metadata *>(&md)) {
            vdbgi_meta_set_int(&p->meta, name.c_str(), i32->value());
        } else if (const auto *d = dynamic_cast<const openvdb::DoubleMetadata *>(&md)) {
            vdbgi_meta_set_double(&p->meta, name.c_str(), d->value());
        } else if (const auto *f = dynamic_cast<const openvdb::FloatMetadata *>(&md)) {
            vdbgi_meta_set_double(&p->meta, name.c_str(), f->value());
        } else if (const auto *v = dynamic_cast<const openvdb::Vec3SMetadata *>(&md)) {
            const float xyz[3] = {v->value().x(), v->value().y(), v->value().z()};
            vdbgi_meta_set_vec3(&p->meta, name.c_str(), xyz);
        }
    }
}

} // namespace

extern "C" vdbgi_result vdbgi_vdb_topology(vdbgi_context *ctx, const float *positions,
                                           size_t vertex_count, const uint32_t *indices,
                                           size_t triangle_count, const double origin[3],
                                           double spacing, double margin, uint64_t max_count,
                                           int32_t **ijk_out, size_t *count_out)
{
    VDBGI_SHIM_BEGIN
    *ijk_out = nullptr;
    *count_out = 0;
    openvdb::initialize();
    std::vector<openvdb::Vec3s> points(vertex_count);
    for (size_t i = 0; i < vertex_count; i++)
        points[i] = openvdb::Vec3s(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
    std::vector<openvdb::Vec3I> tris(triangle_count);
    for (size_t t = 0; t < triangle_count; t++)
        tris[t] = openvdb::Vec3I(indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]);
    const std::vector<openvdb::Vec4I> quads;
    // The band is in voxels; it reaches half a voxel past the margin so that probes at exactly
    // the margin (common where geometry lines up with the lattice) survive float rounding.
    const float band = float(margin / spacing) + 0.5f;
    const auto dist = openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(
        *lattice_transform(origin, spacing), points, tris, quads, band);
    const float limit = float(margin);
    uint64_t count = 0;
    for (auto it = dist->tree().cbeginValueOn(); it; ++it)
        count += *it <= limit;
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
    for (auto it = dist->tree().cbeginValueOn(); it; ++it) {
        if (*it > limit)
            continue;
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

} // namespace

extern "C" vdbgi_result vdbgi_vdb_write(vdbgi_context *ctx, const char *path, const char *name,
                                        const vdbgi_probes *p)
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
    if (p->cube) {
        // Ambient-cube sides: one Vec3s grid each, sharing the topology.
        for (int side = 0; side < 6; side++) {
            auto g = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
            g->setName(side_grid_names[side]);
            g->setTransform(xf->copy());
            g->setGridClass(openvdb::GRID_UNKNOWN);
            g->setVectorType(openvdb::VEC_INVARIANT);
            auto a = g->getAccessor();
            for (size_t n = 0; n < p->count; n++) {
                const float *const c = &p->cube[18 * n + 3 * side];
                a.setValue(openvdb::Coord(p->ijk[3 * n], p->ijk[3 * n + 1], p->ijk[3 * n + 2]),
                           openvdb::Vec3s(c[0], c[1], c[2]));
            }
            grids.push_back(g);
        }
    }
    for (auto &g : grids)
        for (size_t m = 0; m < p->meta.count; m++)
            add_meta(*g, p->meta.items[m]);
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
    VDBGI_SHIM_END(ctx, "openvdb")
}

/*
 * Does every grid of the file end within it, as its descriptors say? OpenVDB
 * reads a grid that a truncated file cuts short from whatever its buffers
 * held: under ASan's fill pattern that asked for gigabytes. This walks the
 * descriptors the way io::File::open does, without reading any grid.
 */
struct GridLayout : openvdb::io::Archive {
    /*
     * Do the n length-prefixed fields (u32 length, then bytes) at the stream's
     * position fit before size? OpenVDB allocates a string's length before it
     * reads it: a garbled length would cost gigabytes. The stream is left
     * where it was.
     */
    static bool fields_fit(std::istream &is, std::streamoff size, int n)
    {
        const std::streamoff start = is.tellg();
        std::streamoff pos = start;
        bool ok = true;
        for (int f = 0; f < n && ok; f++) {
            uint32_t len = 0;
            ok = pos + 4 <= size;
            if (ok) {
                is.read(reinterpret_cast<char *>(&len), 4);
                pos += 4;
                ok = std::streamoff(len) <= size - pos;
                pos += len;
                if (ok)
                    is.seekg(pos);
            }
        }
        is.seekg(start);
        return ok;
    }

    std::vector<openvdb::io::GridDescriptor> descriptors;
    openvdb::GridPtrVec grids;

    bool grids_fit(const char *path)
    {
        std::ifstream is(path, std::ios::binary | std::ios::ate);
        const std::streamoff size = is.tellg();
        is.seekg(0);
        // Reading past the end throws: a damaged count must not read zeros forever.
        is.exceptions(std::ios::failbit | std::ios::badbit | std::ios::eofbit);
        readHeader(is);
        openvdb::io::setVersion(is, libraryVersion(), fileVersion()); // as io::File::open tags it
        openvdb::io::setDataCompression(is, compression());
        if (!inputHasGridOffsets())
            return true; // read sequentially: nothing to check against
        // File metadata: a count, then name, type and value, each length-prefixed.
        uint32_t meta_count = 0;
        const std::streamoff meta_start = is.tellg();
        if (meta_start + 4 > size)
            return false;
        is.read(reinterpret_cast<char *>(&meta_count), 4);
        if (std::streamoff(meta_count) > (size - meta_start - 4) / 12)
            return false;
        for (uint32_t m = 0; m < meta_count; m++) {
            if (!fields_fit(is, size, 3))
                return false;
            for (int f = 0; f < 3; f++) { // past this entry
                uint32_t len = 0;
                is.read(reinterpret_cast<char *>(&len), 4);
                is.seekg(len, std::ios::cur);
            }
        }
        is.seekg(meta_start);
        openvdb::MetaMap meta;
        meta.readMeta(is);
        const int32_t count = readGridCount(is);
        if (count < 0 || std::streamoff(count) > size / 36)
            return false;
        for (int32_t i = 0; i < count; i++) {
            // Name, type and instance parent, then three offsets that only move forward.
            if (!fields_fit(is, size, 3))
                return false;
            openvdb::io::GridDescriptor gd;
            openvdb::GridBase::Ptr grid = gd.read(is);
            const std::streamoff here = is.tellg();
            if (!is || gd.getGridPos() < here || gd.getBlockPos() < gd.getGridPos() ||
                gd.getEndPos() < gd.getBlockPos() || gd.getEndPos() > size)
                return false;
            descriptors.push_back(gd);
            grids.push_back(grid);
            gd.seekToEnd(is);
        }
        return bool(is);
    }

    /*
     * Read every grid whole, as io::File does (seek to it, Archive::readGrid),
     * but from a stream that throws at the end of the file: a damaged count
     * then ends the read instead of building nodes from zeros for minutes.
     * Only after grids_fit has returned true on the same path.
     */
    void read_grids(const char *path)
    {
        std::ifstream is(path, std::ios::binary);
        is.exceptions(std::ios::failbit | std::ios::badbit | std::ios::eofbit);
        openvdb::io::setVersion(is, libraryVersion(), fileVersion());
        openvdb::io::setDataCompression(is, compression());
        auto meta = std::make_shared<openvdb::io::StreamMetadata>();
        meta->setFileVersion(fileVersion());
        meta->setLibraryVersion(libraryVersion());
        meta->setCompression(compression());
        meta->setSeekable(true);
        openvdb::io::setStreamMetadataPtr(is, meta, /*transfer=*/false);
        for (size_t i = 0; i < descriptors.size(); i++) {
            const openvdb::io::GridDescriptor &gd = descriptors[i];
            if (gd.isInstance()) // vdbgi never writes instances: read as absent
                continue;
            gd.seekToGrid(is);
            readGrid(grids[i], gd, is);
            grids[i]->setName(gd.gridName());
        }
    }

    /* The grid of that name (instances aside), or null. */
    openvdb::GridBase::Ptr find(const char *name) const
    {
        for (size_t i = 0; i < grids.size(); i++)
            if (grids[i] && !descriptors[i].isInstance() && descriptors[i].gridName() == name)
                return grids[i];
        return nullptr;
    }
};

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

/* The per-probe extras beside the irradiance: noise, rays and cube sides, at p's n probes. */
void copy_extras(vdbgi_probes *p, size_t n, const openvdb::FloatGrid::Ptr &se,
                 const openvdb::Int32Grid::Ptr &rays, const openvdb::Vec3SGrid::Ptr side_grids[6],
                 bool has_cube)
{
    if (se || rays) {
        // Grids of another type under these names are not ours: left as absent.
        openvdb::FloatGrid::Ptr se_or_empty = se ? se : openvdb::FloatGrid::create();
        openvdb::Int32Grid::Ptr rays_or_empty = rays ? rays : openvdb::Int32Grid::create();
        const auto sa = se_or_empty->getConstAccessor();
        const auto ra = rays_or_empty->getConstAccessor();
        for (size_t i = 0; i < n; i++) {
            const openvdb::Coord c(p->ijk[3 * i], p->ijk[3 * i + 1], p->ijk[3 * i + 2]);
            if (se)
                p->stderr_[i] = sa.getValue(c);
            if (rays)
                p->rays[i] = uint32_t(std::max(0, ra.getValue(c)));
        }
    }
    for (int side = 0; has_cube && side < 6; side++) {
        const auto a = side_grids[side]->getConstAccessor();
        for (size_t i = 0; i < n; i++) {
            const openvdb::Vec3s v =
                a.getValue(openvdb::Coord(p->ijk[3 * i], p->ijk[3 * i + 1], p->ijk[3 * i + 2]));
            float *const c = &p->cube[18 * i + 3 * side];
            c[0] = v.x(), c[1] = v.y(), c[2] = v.z();
        }
    }
}

} // namespace

namespace
{

/*
 * The grid table checked against the file (io::File::open itself reads past
 * the end of a truncated file), then every grid read whole: each failure a
 * one-line refusal naming the file.
 */
vdbgi_result read_layout(vdbgi_context *ctx, const char *path, GridLayout &layout)
{
    bool fits = false;
    try {
        fits = layout.grids_fit(path);
    } catch (const openvdb::Exception &e) {
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: not a readable VDB file (%s)", path,
                          e.what());
    } catch (const std::ios_base::failure &) {
        fits = false;
    } catch (const std::bad_alloc &) {
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                          "%s: damaged VDB file (a count in its header is absurd)", path);
    }
    if (!fits)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                          "%s: truncated or damaged VDB file (a grid ends past its end)", path);
    try {
        // Every grid read whole: delayed loading crashed on damaged leaf buffers.
        layout.read_grids(path);
    } catch (const std::ios_base::failure &) {
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: damaged VDB file (it ends inside a grid)",
                          path);
    } catch (const openvdb::Exception &e) {
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: damaged grid data (%s)", path, e.what());
    } catch (const std::bad_alloc &) {
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: damaged grid data (a size in it is absurd)",
                          path);
    }
    return VDBGI_OK;
}

} // namespace

/*
 * Read the grids, check their types and transform, copy them into probes
 * (about 70 lines: the OpenVDB objects live only inside this exception
 * boundary).
 */
extern "C" vdbgi_result vdbgi_vdb_read(vdbgi_context *ctx, const char *path, vdbgi_probes **out)
{
    VDBGI_SHIM_BEGIN
    *out = nullptr;
    openvdb::initialize();
    GridLayout layout;
    VDBGI_TRY(read_layout(ctx, path, layout));
    const auto grid = [&](const char *name) { return layout.find(name); };
    const openvdb::GridBase::Ptr base = grid("irradiance"), vbase = grid("validity");
    const openvdb::GridBase::Ptr sebase = grid("stderr"), raysbase = grid("rays");
    if (!base)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: no grid named 'irradiance'", path);
    openvdb::GridBase::Ptr sides[6];
    bool has_cube = true;
    for (int side = 0; side < 6; side++)
        has_cube = has_cube && (sides[side] = grid(side_grid_names[side]));
    const auto irr = openvdb::gridPtrCast<openvdb::Vec3SGrid>(base);
    if (!irr)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid 'irradiance' is %s, not vec3s", path,
                          base->valueType().c_str());
    const auto val = openvdb::gridPtrCast<openvdb::FloatGrid>(vbase);
    if (vbase && !val)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid 'validity' is %s, not float", path,
                          vbase->valueType().c_str());
    openvdb::Vec3SGrid::Ptr side_grids[6];
    for (int side = 0; has_cube && side < 6; side++)
        if (!(side_grids[side] = openvdb::gridPtrCast<openvdb::Vec3SGrid>(sides[side])))
            return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid '%s' is %s, not vec3s", path,
                              side_grid_names[side], sides[side]->valueType().c_str());
    VDBGI_TRY(check_lattice(ctx, path, *irr));
    if (val && val->tree().activeTileCount() != 0)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                          "%s: grid 'validity' has active tiles: probes are single voxels", path);
    const openvdb::math::Transform &xf = irr->transform();
    const openvdb::Vec3d vs = xf.voxelSize();
    const openvdb::Vec3d o = xf.indexToWorld(openvdb::Vec3d(0.0));
    const size_t count = size_t(irr->activeVoxelCount());
    vdbgi_probes *p = nullptr;
    VDBGI_TRY(vdbgi_probes_alloc(ctx, count, true, &p));
    // Destroys p if anything below throws; released on success.
    std::unique_ptr<vdbgi_probes, void (*)(vdbgi_probes *)> guard(p, vdbgi_probes_destroy);
    p->spacing = vs.x();
    p->origin[0] = o.x(), p->origin[1] = o.y(), p->origin[2] = o.z();
    read_meta(*irr, p);
    const auto se = openvdb::gridPtrCast<openvdb::FloatGrid>(sebase);
    const auto rays = openvdb::gridPtrCast<openvdb::Int32Grid>(raysbase);
    if ((se && !(p->stderr_ = (float *)vdbgi_calloc(ctx, count ? count : 1, sizeof(float)))) ||
        (rays && !(p->rays = (uint32_t *)vdbgi_calloc(ctx, count ? count : 1, sizeof(uint32_t)))))
        return VDBGI_ERR_OUT_OF_MEMORY;
    if (has_cube && !(p->cube = (float *)vdbgi_calloc(ctx, count ? count : 1, 18 * sizeof(float))))
        return VDBGI_ERR_OUT_OF_MEMORY;
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
    copy_extras(p, n, se, rays, side_grids, has_cube);
    p->count = n;
    *out = guard.release();
    return VDBGI_OK;
    VDBGI_SHIM_END(ctx, "openvdb")
}
