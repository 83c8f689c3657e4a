/* shim.h: the exception boundary shared by the two C++ shims (never seen by C). */
#ifndef VDBGI_SHIM_H
#define VDBGI_SHIM_H

#include "context.h"

#include <exception>
#include <new>

/*
 * Every extern "C" shim body sits between these two (Embree's pattern): no
 * exception crosses into C. An allocation failure is out of memory; anything
 * else is a backend error carrying what() behind the library's name.
 */
/* How a shim records a failure: vdbgi_fail, unless it is a module with a host table. */
#ifndef VDBGI_SHIM_FAIL
#define VDBGI_SHIM_FAIL vdbgi_fail
#endif

#define VDBGI_SHIM_BEGIN try {
#define VDBGI_SHIM_END(ctx, lib)                                                                   \
    }                                                                                              \
    catch (const std::bad_alloc &)                                                                 \
    {                                                                                              \
        return VDBGI_SHIM_FAIL((ctx), VDBGI_ERR_OUT_OF_MEMORY, lib ": out of memory");             \
    }                                                                                              \
    catch (const std::exception &e)                                                                \
    {                                                                                              \
        return VDBGI_SHIM_FAIL((ctx), VDBGI_ERR_BACKEND, lib ": %s", e.what());                    \
    }                                                                                              \
    catch (...)                                                                                    \
    {                                                                                              \
        return VDBGI_SHIM_FAIL((ctx), VDBGI_ERR_BACKEND, lib ": unknown exception");               \
    }

/* The same for a shim working on one file: its messages name the file. */
#define VDBGI_SHIM_END_FILE(ctx, lib, path)                                                        \
    }                                                                                              \
    catch (const std::bad_alloc &)                                                                 \
    {                                                                                              \
        return VDBGI_SHIM_FAIL((ctx), VDBGI_ERR_OUT_OF_MEMORY, "%s: " lib ": out of memory",       \
                               path);                                                              \
    }                                                                                              \
    catch (const std::exception &e)                                                                \
    {                                                                                              \
        return VDBGI_SHIM_FAIL((ctx), VDBGI_ERR_BACKEND, "%s: " lib ": %s", path, e.what());       \
    }                                                                                              \
    catch (...)                                                                                    \
    {                                                                                              \
        return VDBGI_SHIM_FAIL((ctx), VDBGI_ERR_BACKEND, "%s: " lib ": unknown exception", path);  \
    }

/* Bytes a library holds for vdbgi, counted against the context's memory limit while held. */
struct VdbgiMemoryCharge {
    vdbgi_context *ctx;
    size_t bytes = 0;
    explicit VdbgiMemoryCharge(vdbgi_context *c) : ctx(c)
    {
    }
    VdbgiMemoryCharge(const VdbgiMemoryCharge &) = delete;
    VdbgiMemoryCharge &operator=(const VdbgiMemoryCharge &) = delete;
    /* Hold now bytes instead of what was held; false (the failure recorded) past the limit. */
    bool hold(size_t now)
    {
        if (now > bytes && !vdbgi_memory_charge(ctx, now - bytes))
            return false;
        if (now < bytes)
            vdbgi_memory_release(ctx, bytes - now);
        bytes = now;
        return true;
    }
    ~VdbgiMemoryCharge()
    {
        vdbgi_memory_release(ctx, bytes);
    }
};

/* What a list of grids (OpenVDB's GridPtrVec; null entries allowed) holds in memory. */
template <class Grids> size_t vdbgi_grids_bytes(const Grids &grids)
{
    size_t sum = 0;
    for (const auto &g : grids)
        sum += g ? size_t(g->memUsage()) : 0;
    return sum;
}

#endif /* VDBGI_SHIM_H */
