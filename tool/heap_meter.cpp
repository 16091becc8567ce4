// heap_meter.cpp: the CLI's global operator new and delete, which report every allocation to
// harness::note_heap_allocation, so that `refraster bench` can state the reference's heap
// high-water mark. Sizes are malloc's usable sizes, so an allocation and its release count the
// same bytes. Aligned forms are left to the library (the reference uses none). Framebuffer
// storage the reference maps itself (refraster::PixelAllocator) is reported through
// refraster::set_pixel_storage_observer.
#include <malloc.h>

#include <cstdlib>
#include <new>

#include "harness/bench.hpp"
#include "refraster/framebuffer.hpp"

namespace {

void note_pixel_storage(std::ptrdiff_t bytes) {
    if (bytes >= 0) {
        harness::note_heap_allocation(static_cast<std::size_t>(bytes));
    } else {
        harness::note_heap_release(static_cast<std::size_t>(-bytes));
    }
}

// Installed before main runs.
const bool kObserving = (refraster::set_pixel_storage_observer(&note_pixel_storage), true);

}  // namespace

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
