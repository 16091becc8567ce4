// heap_meter.cpp: the CLI's global operator new and delete, which report every allocation to
// harness::note_heap_allocation, so that `refraster bench` can state the reference's heap
// high-water mark. Sizes are malloc's usable sizes, so an allocation and its release count the
// same bytes. Aligned forms are left to the library (the reference uses none).
#include <malloc.h>

#include <cstdlib>
#include <new>

#include "harness/bench.hpp"

void* operator new(std::size_t n) {
    void* p = std::malloc(n == 0 ? 1 : n);
    if (p == nullptr) throw std::bad_alloc();
    harness::note_heap_allocation(malloc_usable_size(p));
    return p;
}

void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
    void* p = std::malloc(n == 0 ? 1 : n);
    if (p != nullptr) harness::note_heap_allocation(malloc_usable_size(p));
    return p;
}

void operator delete(void* p) noexcept {
    if (p == nullptr) return;
    harness::note_heap_release(malloc_usable_size(p));
    std::free(p);
}

void operator delete(void* p, std::size_t) noexcept {
    operator delete(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
    operator delete(p);
}
