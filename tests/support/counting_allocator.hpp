#pragma once
// Include in exactly one translation unit of a test executable: replaces every form of the
// global operator new/delete (plain, array, nothrow, sized) with malloc/free and counts the
// allocations, so that a test can prove a piece of code allocates nothing. The whole set
// must be replaced: a partial set mixes allocators (AddressSanitizer reports it).
#include <atomic>
#include <cstdlib>
#include <new>

namespace phynjo::test {
inline std::atomic<long> allocations{0};
inline void* counted_malloc(std::size_t n) {
    allocations.fetch_add(1, std::memory_order_relaxed);
    return std::malloc(n ? n : 1);
}
} // namespace phynjo::test

void* operator new(std::size_t n) {
    if (void* p = phynjo::test::counted_malloc(n)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
    if (void* p = phynjo::test::counted_malloc(n)) return p;
    throw std::bad_alloc();
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return phynjo::test::counted_malloc(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return phynjo::test::counted_malloc(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
