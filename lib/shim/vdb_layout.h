/*
 * vdb_layout.h: GridLayout, the checked walk over a .vdb's table of grids and
 * trees that vdb_read.cpp reads through (C++, for the shims alone).
 */
#ifndef VDBGI_VDB_LAYOUT_H
#define VDBGI_VDB_LAYOUT_H

#include "lattice.h"
#include "vdbtree.h"

#include <openvdb/io/GridDescriptor.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

/*
 * The file's table of grids, checked against the file, and the grids vdbgi
 * uses read whole. io::File trusts what it reads: a truncated file made it
 * read a grid from whatever its buffers held (gigabytes under ASan's fill
 * pattern), a garbled length allocated gigabytes, and one flipped byte in a
 * chunk size corrupted the heap. So this walks the header and descriptors as
 * io::File::open does, bounds every length-prefixed field, and walks each
 * tree's bytes (vdbtree.c) before Archive::readGrid reads them.
 */
struct GridLayout : openvdb::io::Archive {
    /* A refusal from inside the walk: what is wrong, said after the file's name. Inside
       check_tree, only the reason: read() says which grid. */
    struct Damaged {
        std::string why;
    };
    /* A tree that is whole but too sparse for OpenVDB to hold (check_tree). */
    struct Sparse {
        std::string why;
    };
    /* A tree that admit() refused: the context holds why. */
    struct OverLimit {
    };
    /* Asked, before each grid is read, whether its bytes (an estimate) may be held. */
    std::function<bool(size_t)> admit;
    static constexpr size_t SPARSE_LEAVES = 65536, MIN_LEAF_ACTIVE = 8;

    /*
     * Do the n length-prefixed fields (u32 length, then bytes) at the stream's
     * position fit before end? OpenVDB allocates a string's length before it
     * reads it. The stream is left where it was.
     */
    static bool fields_fit(std::istream &is, std::streamoff end, int n)
    {
        const std::streamoff start = is.tellg();
        std::streamoff pos = start;
        bool ok = true;
        for (int f = 0; f < n && ok; f++) {
            uint32_t len = 0;
            ok = pos + 4 <= end;
            if (ok) {
                is.read(reinterpret_cast<char *>(&len), 4);
                pos += 4;
                ok = std::streamoff(len) <= end - pos;
                pos += len;
                if (ok)
                    is.seekg(pos);
            }
        }
        is.seekg(start);
        return ok;
    }

    /* MetaMap::readMeta from the stream, once its count and fields fit before end. */
    static openvdb::MetaMap read_meta_map(std::istream &is, std::streamoff end)
    {
        // A count, then name, type and value, each length-prefixed.
        const std::streamoff start = is.tellg();
        uint32_t count = 0;
        if (start + 4 > end)
            throw Damaged{"its metadata runs past its end"};
        is.read(reinterpret_cast<char *>(&count), 4);
        if (std::streamoff(count) > (end - start - 4) / 12)
            throw Damaged{"its metadata count is absurd"};
        for (uint32_t m = 0; m < count; m++) {
            if (!fields_fit(is, end, 3))
                throw Damaged{"its metadata runs past its end"};
            for (int f = 0; f < 3; f++) { // past this entry
                uint32_t len = 0;
                is.read(reinterpret_cast<char *>(&len), 4);
                is.seekg(len, std::ios::cur);
            }
        }
        is.seekg(start);
        openvdb::MetaMap meta;
        meta.readMeta(is);
        return meta;
    }

    std::streamoff size = 0;
    std::vector<openvdb::io::GridDescriptor> descriptors;
    openvdb::GridPtrVec grids;
    std::vector<vdbgi_vdb_tree_counts> counts;                /* per grid, once checked */
    std::vector<size_t> wanted;                               /* the grids checked, to be read */
    std::shared_ptr<openvdb::io::StreamMetadata> stream_meta; /* as long as the stream */

    /* Header, file metadata and grid descriptors, each grid inside the file. */
    void read_table(std::istream &is)
    {
        is.seekg(0, std::ios::end);
        size = is.tellg();
        is.seekg(0);
        // The format version, checked before readHeader warns of it on stdout and goes on.
        int64_t magic = 0;
        uint32_t version = 0;
        if (size >= 12) {
            is.read(reinterpret_cast<char *>(&magic), 8);
            is.read(reinterpret_cast<char *>(&version), 4);
            is.seekg(0);
        }
        if (magic == openvdb::OPENVDB_MAGIC &&
            (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION ||
             version > openvdb::OPENVDB_FILE_VERSION))
            throw Damaged{"VDB file format " + std::to_string(version) + " is outside the " +
                          std::to_string(openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) +
                          ".." + std::to_string(openvdb::OPENVDB_FILE_VERSION) + " vdbgi reads"};
        readHeader(is);
        if (!inputHasGridOffsets())
            throw Damaged{"VDB file written as a stream, without grid offsets"};
        openvdb::io::setVersion(is, libraryVersion(), fileVersion()); // as io::File::open tags it
        openvdb::io::setDataCompression(is, compression());
        try {
            read_meta_map(is, size);
        } catch (const Damaged &d) {
            throw Damaged{"damaged VDB file (" + d.why + ")"};
        }
        const int32_t count = readGridCount(is);
        if (count < 0 || std::streamoff(count) > size / 36)
            throw Damaged{"damaged VDB file (its grid count is absurd)"};
        for (int32_t i = 0; i < count; i++) {
            // Name, type and instance parent, then three offsets that only move forward.
            if (!fields_fit(is, size, 3))
                throw Damaged{"damaged VDB file (a grid descriptor runs past its end)"};
            openvdb::io::GridDescriptor gd;
            openvdb::GridBase::Ptr grid = gd.read(is);
            const std::streamoff here = is.tellg();
            if (gd.getGridPos() < here || gd.getBlockPos() < gd.getGridPos() ||
                gd.getEndPos() < gd.getBlockPos() || gd.getEndPos() > size)
                throw Damaged{"truncated or damaged VDB file (a grid ends past its end)"};
            descriptors.push_back(gd);
            grids.push_back(grid);
            counts.push_back(vdbgi_vdb_tree_counts{});
            gd.seekToEnd(is);
        }
    }

    /* The bytes of grid i's tree, walked by vdbtree.c; the stream is left anywhere. */
    void check_tree(std::istream &is, size_t i)
    {
        const openvdb::io::GridDescriptor &gd = descriptors[i];
        const std::streamoff block = gd.getBlockPos();
        gd.seekToGrid(is);
        readGridCompression(is);
        const openvdb::MetaMap meta = read_meta_map(is, block);
        if (!fields_fit(is, block, 1)) // the transform's map type
            throw Damaged{"its transform runs into its data"};
        openvdb::math::Transform().read(is);
        const std::streamoff topology = is.tellg();
        if (topology > block)
            throw Damaged{"its transform runs into its data"};
        std::vector<uint8_t> bytes(size_t(gd.getEndPos() - topology));
        is.read(reinterpret_cast<char *>(bytes.data()), std::streamsize(bytes.size()));
        const auto as_half = meta.getMetadata<openvdb::BoolMetadata>("is_saved_as_half_float");
        const openvdb::GridBase &g = *grids[i];
        vdbgi_vdb_tree_format f = {};
        f.compression = openvdb::io::getDataCompression(is);
        f.value_size = g.isType<openvdb::Vec3SGrid>() ? 12 : 4;
        f.saved_size = as_half && as_half->value() && !g.isType<openvdb::Int32Grid>()
                           ? f.value_size / 2
                           : f.value_size;
        f.max_index = VDBGI_MAX_INDEX;
        char why[160];
        vdbgi_vdb_tree_counts &n = counts[i];
        if (!vdbgi_vdb_tree_check(bytes.data(), size_t(block - topology), bytes.size(), &f, &n, why,
                                  sizeof why))
            throw Damaged{why};
        const size_t leaves = n.leaves, active = n.active;
        /*
         * OpenVDB holds every leaf whole (512 values): probes one per leaf cost
         * 6 kB each (200 000 of them, 1.2 GB from a 33 MB file). A bake's leaves
         * straddle surfaces in a band 8 probes thick and hold 50 to 500 each.
         */
        if (leaves > SPARSE_LEAVES && active < MIN_LEAF_ACTIVE * leaves)
            throw Sparse{"its " + std::to_string(leaves) + " leaves hold " +
                         std::to_string(active) + " voxels (fewer than " +
                         std::to_string(MIN_LEAF_ACTIVE) + " a leaf, past " +
                         std::to_string(SPARSE_LEAVES) + " leaves)"};
        // What OpenVDB will hold for it (its leaves whole, their masks), asked of the
        // memory limit before it is spent.
        if (admit && !admit(leaves * (512 * f.value_size + 128)))
            throw OverLimit{};
    }

    /*
     * Open the file at path on is as io::File does: a stream that throws at
     * its end (a damaged count must not read zeros forever), the table read,
     * the stream tagged for seeking.
     */
    void open(std::ifstream &is, const char *path)
    {
        is.open(path, std::ios::binary);
        is.exceptions(std::ios::failbit | std::ios::badbit | std::ios::eofbit);
        read_table(is);
        stream_meta = std::make_shared<openvdb::io::StreamMetadata>();
        stream_meta->setFileVersion(fileVersion());
        stream_meta->setLibraryVersion(libraryVersion());
        stream_meta->setCompression(compression());
        stream_meta->setSeekable(true);
        openvdb::io::setStreamMetadataPtr(is, stream_meta, /*transfer=*/false);
    }

    /* f(), with what it throws said about grid gd. */
    template <class F> static void about(const openvdb::io::GridDescriptor &gd, F f)
    {
        try {
            f();
        } catch (const Sparse &d) {
            throw Damaged{"grid '" + gd.gridName() + "': " + d.why +
                          ": too sparse a lattice to read"};
        } catch (const Damaged &d) {
            throw Damaged{"damaged VDB file (grid '" + gd.gridName() + "': " + d.why + ")"};
        } catch (const openvdb::Exception &e) {
            throw Damaged{"damaged VDB file (grid '" + gd.gridName() + "': " + e.what() + ")"};
        }
    }

    /*
     * Walk the named grids of the types vdbgi takes (check_tree) and list
     * them in wanted; other grids stay unread.
     */
    void check(std::istream &is, const std::vector<std::string> &names)
    {
        // Two grids of one name vdbgi reads: which one holds the probes is anyone's guess.
        for (size_t i = 0; i < descriptors.size(); i++)
            for (size_t j = 0; j < i; j++)
                if (!descriptors[i].isInstance() && !descriptors[j].isInstance() &&
                    descriptors[i].gridName() == descriptors[j].gridName() &&
                    std::find(names.begin(), names.end(), descriptors[i].gridName()) != names.end())
                    throw Damaged{"two grids are named '" + descriptors[i].gridName() + "'"};
        for (size_t i = 0; i < descriptors.size(); i++) {
            const openvdb::io::GridDescriptor &gd = descriptors[i];
            const openvdb::GridBase &g = *grids[i];
            if (gd.isInstance() || // vdbgi never writes instances: read as absent
                std::find(names.begin(), names.end(), gd.gridName()) == names.end() ||
                !(g.isType<openvdb::Vec3SGrid>() || g.isType<openvdb::FloatGrid>() ||
                  g.isType<openvdb::Int32Grid>()))
                continue;
            about(gd, [&] { check_tree(is, i); });
            wanted.push_back(i);
        }
    }

    /*
     * Read the checked grids (Archive::readGrid, as io::File does), whole
     * into grids, or with box only the voxels inside it, into fresh grids
     * in out (OpenVDB reads the topology whole and seeks past the other
     * leaves' values).
     */
    void load(std::istream &is, const openvdb::CoordBBox *box, openvdb::GridPtrVec &out)
    {
        out = grids;
        for (size_t i : wanted) {
            const openvdb::io::GridDescriptor &gd = descriptors[i];
            about(gd, [&] {
                gd.seekToGrid(is);
                if (box) {
                    out[i] = grids[i]->copyGridWithNewTree();
                    readGrid(out[i], gd, is, *box);
                    // The clipped read prunes: a leaf of equal active values becomes an
                    // active tile. Irradiance and validity held none in the file
                    // (vdbgi_vdb_regions_open), so theirs are probes, made voxels again;
                    // the other grids are only looked up, tiles or not.
                    const bool probes =
                        gd.gridName() == "irradiance" || gd.gridName() == "validity";
                    if (auto g = openvdb::gridPtrCast<openvdb::Vec3SGrid>(out[i]); g && probes)
                        g->tree().voxelizeActiveTiles();
                    else if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(out[i]); f && probes)
                        f->tree().voxelizeActiveTiles();
                } else {
                    readGrid(grids[i], gd, is);
                }
            });
            out[i]->setName(gd.gridName());
        }
    }

    /* The named grids read whole. */
    void read(const char *path, const std::vector<std::string> &names)
    {
        std::ifstream is;
        open(is, path);
        check(is, names);
        load(is, nullptr, grids);
    }

    /* The grid of that name in read (grids, or what load put in out), or null; one not
       read still tells its type. */
    openvdb::GridBase::Ptr find(const openvdb::GridPtrVec &read, const std::string &name) const
    {
        for (size_t i = 0; i < read.size(); i++)
            if (read[i] && !descriptors[i].isInstance() && descriptors[i].gridName() == name)
                return read[i];
        return nullptr;
    }
};

#endif /* VDBGI_VDB_LAYOUT_H */
