#pragma once
// Include in exactly one translation unit of a test executable: counts every heap allocation
// the process makes, so that a test can prove a piece of code allocates nothing.
//
// Every path is counted, not only `operator new`: malloc, calloc, realloc, aligned_alloc,
// posix_memalign, memalign, valloc, pvalloc, and through them every form of operator new
// (plain, array, nothrow, aligned), which libstdc++ implements on malloc and aligned_alloc.
// - Ordinary builds replace the C allocation functions (glibc allows an executable to
//   interpose them) and forward to glibc's own (__libc_malloc, …).
// - Sanitizer builds leave the allocator to AddressSanitizer and count through its allocation
//   hook (__sanitizer_install_malloc_and_free_hooks), which sees every path the same way.
// `test_allocation.cpp` checks that each path is counted (a blind counter fails it).
#include <atomic>
#include <cstddef>

namespace phynjo::test {
inline std::atomic<long> allocations{0};
inline void count_allocation() { allocations.fetch_add(1, std::memory_order_relaxed); }
} // namespace phynjo::test

#if defined(__SANITIZE_ADDRESS__)
// From <sanitizer/allocator_interface.h>, which GCC does not install; libasan exports it.
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*, std::size_t),
                                                         void (*free_hook)(const volatile void*));
namespace phynjo::test {
inline void on_malloc(const volatile void*, std::size_t) { count_allocation(); }
inline void on_free(const volatile void*) {}
inline const int hooks_installed = __sanitizer_install_malloc_and_free_hooks(on_malloc, on_free);
} // namespace phynjo::test
#else
#include <cerrno>
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void* __libc_valloc(std::size_t);
void* __libc_pvalloc(std::size_t);
void __libc_free(void*);

void* malloc(std::size_t n) noexcept {
    phynjo::test::count_allocation();
    return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t size) noexcept {
    phynjo::test::count_allocation();
    return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t n) noexcept {
    phynjo::test::count_allocation();
    return __libc_realloc(p, n);
}
void* memalign(std::size_t alignment, std::size_t n) noexcept {
    phynjo::test::count_allocation();
    return __libc_memalign(alignment, n);
}
void* aligned_alloc(std::size_t alignment, std::size_t n) noexcept {
    phynjo::test::count_allocation();
    return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) noexcept {
    if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0) return EINVAL;
    phynjo::test::count_allocation();
    void* p = __libc_memalign(alignment, n);
    if (!p) return ENOMEM;
    *out = p;
    return 0;
}
void* valloc(std::size_t n) noexcept {
    phynjo::test::count_allocation();
    return __libc_valloc(n);
}
void* pvalloc(std::size_t n) noexcept {
    phynjo::test::count_allocation();
    return __libc_pvalloc(n);
}
void free(void* p) noexcept { __libc_free(p); }
}
#endif
