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

#endif /* VDBGI_SHIM_H */
