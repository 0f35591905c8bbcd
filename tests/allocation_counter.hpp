// Allocation detectors for the "nothing allocates on the per-tick path" tests (docs/conventions.md,
// "The per-tick path"). Include this FIRST in a test's single translation unit, before any Eigen
// header: it replaces the global allocation functions of that executable.
//
// Two independent detectors, both active inside a counting window (count_allocations):
// - every replaceable global operator new / new[] (plain, nothrow, aligned) is replaced and counts
//   its calls: catches std::vector, std::string, std::function, ...;
// - Eigen allocates its dynamic storage with std::malloc, not operator new, so that is caught
//   with EIGEN_RUNTIME_NO_MALLOC: Eigen::internal::set_is_malloc_allowed(false) makes every Eigen
//   heap allocation fail an eigen_assert, which is redefined here to count inside a window (also
//   in Release builds, where eigen_assert is normally compiled out) and to abort outside one, so
//   Eigen's own checks stay active for every other test.
#pragma once

#ifdef EIGEN_CORE_MODULE_H
#error "include allocation_counter.hpp before any Eigen header"
#endif

#define EIGEN_RUNTIME_NO_MALLOC

#include <atomic>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <new>

namespace allocation_counter {
inline std::atomic<bool> counting{false};
inline std::atomic<long> operator_new_calls{0};
inline std::atomic<long> eigen_assert_failures{0};

/// Inside a counting window: count (an Eigen heap allocation trips the malloc check). Outside:
/// behave like a real assertion, also in Release builds.
inline void record_eigen_assert_failure(const char* condition, const char* file, int line) noexcept
{
    if (counting.load()) {
        ++eigen_assert_failures;
        return;
    }
    std::fprintf(stderr, "eigen_assert failed: %s (%s:%d)\n", condition, file, line);
    std::abort();
}

inline void* allocate(std::size_t size) noexcept
{
    if (counting.load()) {
        ++operator_new_calls;
    }
    return std::malloc(size == 0 ? 1 : size);
}

inline void* allocate_aligned(std::size_t size, std::align_val_t alignment) noexcept
{
    if (counting.load()) {
        ++operator_new_calls;
    }
    const std::size_t align = static_cast<std::size_t>(alignment);
    const std::size_t rounded = ((size == 0 ? 1 : size) + align - 1) / align * align;
    return std::aligned_alloc(align, rounded);
}

inline void* allocate_or_throw(std::size_t size)
{
    void* pointer = allocate(size);
    if (pointer == nullptr) {
        throw std::bad_alloc();
    }
    return pointer;
}

inline void* allocate_aligned_or_throw(std::size_t size, std::align_val_t alignment)
{
    void* pointer = allocate_aligned(size, alignment);
    if (pointer == nullptr) {
        throw std::bad_alloc();
    }
    return pointer;
}
}  // namespace allocation_counter

#define eigen_assert(x) \
    ((x) ? static_cast<void>(0) : ::allocation_counter::record_eigen_assert_failure(#x, __FILE__, __LINE__))

// Replaced global allocation functions (they count only inside a counting window). Defined here,
// not inline: this header belongs to exactly one translation unit per test executable.
void* operator new(std::size_t size) { return allocation_counter::allocate_or_throw(size); }
void* operator new[](std::size_t size) { return allocation_counter::allocate_or_throw(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return allocation_counter::allocate(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return allocation_counter::allocate(size); }
void* operator new(std::size_t size, std::align_val_t alignment)
{
    return allocation_counter::allocate_aligned_or_throw(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment)
{
    return allocation_counter::allocate_aligned_or_throw(size, alignment);
}
void* operator new(std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept
{
    return allocation_counter::allocate_aligned(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept
{
    return allocation_counter::allocate_aligned(size, alignment);
}

namespace allocation_counter {
// Not inlined on purpose: with optimisation GCC inlines std::free into callers that obtained the
// pointer from operator new and reports -Wmismatched-new-delete, although both replacements here
// use malloc/free consistently.
[[gnu::noinline]] inline void release(void* pointer) noexcept { std::free(pointer); }
}  // namespace allocation_counter

void operator delete(void* pointer) noexcept { allocation_counter::release(pointer); }
void operator delete[](void* pointer) noexcept { allocation_counter::release(pointer); }
void operator delete(void* pointer, std::size_t) noexcept { allocation_counter::release(pointer); }
void operator delete[](void* pointer, std::size_t) noexcept { allocation_counter::release(pointer); }
void operator delete(void* pointer, const std::nothrow_t&) noexcept { allocation_counter::release(pointer); }
void operator delete[](void* pointer, const std::nothrow_t&) noexcept { allocation_counter::release(pointer); }
void operator delete(void* pointer, std::align_val_t) noexcept { allocation_counter::release(pointer); }
void operator delete[](void* pointer, std::align_val_t) noexcept { allocation_counter::release(pointer); }
void operator delete(void* pointer, std::size_t, std::align_val_t) noexcept { allocation_counter::release(pointer); }
void operator delete[](void* pointer, std::size_t, std::align_val_t) noexcept { allocation_counter::release(pointer); }
void operator delete(void* pointer, std::align_val_t, const std::nothrow_t&) noexcept { allocation_counter::release(pointer); }
void operator delete[](void* pointer, std::align_val_t, const std::nothrow_t&) noexcept { allocation_counter::release(pointer); }

#include <Eigen/Core>

namespace allocation_counter {

/// Calls counted while a function ran.
struct Allocations {
    long operator_new = 0;
    long eigen = 0;
};

/// Run f with both detectors armed; no gtest assertion may run inside.
template <typename F> Allocations count_allocations(F&& f)
{
    operator_new_calls = 0;
    eigen_assert_failures = 0;
    Eigen::internal::set_is_malloc_allowed(false);
    counting = true;
    f();
    counting = false;
    Eigen::internal::set_is_malloc_allowed(true);
    return {operator_new_calls.load(), eigen_assert_failures.load()};
}

/// Somewhere to store a pointer so the compiler cannot remove an allocation.
inline void* volatile sink = nullptr;

}  // namespace allocation_counter
