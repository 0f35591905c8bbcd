// The C heap's counter for the "nothing allocates" tests of code that calls into shared libraries
// (docs/conventions.md, "The per-tick path"): include it right after allocation_counter.hpp, in a
// test's single translation unit. It replaces glibc's malloc family and counts their calls inside
// allocation_counter's window (malloc_counter::calls), where COOPDYN_COUNT_MALLOC is defined.
#pragma once

#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "include allocation_counter.hpp first"
#endif

#include <atomic>
#include <cstddef>

#include <cerrno>

// allocation_counter.hpp sees operator new everywhere and Eigen's heap only in code compiled here;
// liborocos-kdl's own Eigen code allocates with malloc inside the shared library. glibc lets a
// program replace malloc and friends (forwarding to __libc_*), so the solvers' insides are
// counted too. Not under AddressSanitizer, which replaces them itself.
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__clang__)
#define COOPDYN_COUNT_MALLOC 1
#elif defined(__GLIBC__) && defined(__clang__)
#if !__has_feature(address_sanitizer)
#define COOPDYN_COUNT_MALLOC 1
#endif
#endif
#ifdef COOPDYN_COUNT_MALLOC
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
extern "C" void* __libc_memalign(std::size_t, std::size_t);
namespace malloc_counter {
inline std::atomic<long> calls{0};
inline void count() noexcept
{
    if (allocation_counter::counting.load()) {
        ++calls;
    }
}
}  // namespace malloc_counter
extern "C" void* malloc(std::size_t n) noexcept { return malloc_counter::count(), __libc_malloc(n); }
extern "C" void* calloc(std::size_t n, std::size_t size) noexcept { return malloc_counter::count(), __libc_calloc(n, size); }
extern "C" void* realloc(void* p, std::size_t n) noexcept { return malloc_counter::count(), __libc_realloc(p, n); }
extern "C" void* aligned_alloc(std::size_t alignment, std::size_t n) noexcept
{
    return malloc_counter::count(), __libc_memalign(alignment, n);
}
extern "C" int posix_memalign(void** p, std::size_t alignment, std::size_t n) noexcept
{
    malloc_counter::count();
    *p = __libc_memalign(alignment, n);
    return *p != nullptr ? 0 : ENOMEM;
}
#endif
