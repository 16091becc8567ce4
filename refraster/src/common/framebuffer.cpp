#include "refraster/framebuffer.hpp"

#include <atomic>
#include <cstdint>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace refraster {

namespace {

std::atomic<PixelStorageObserver> g_observer{nullptr};

#if defined(__linux__) && defined(MADV_HUGEPAGE)
constexpr std::size_t kHugePage = std::size_t{2} << 20;
// Mapped storage rounds up to whole huge pages.
constexpr std::size_t mapped_size(std::size_t bytes) {
    return (bytes + kHugePage - 1) & ~(kHugePage - 1);
}
#endif

}  // namespace

void set_pixel_storage_observer(PixelStorageObserver observer) {
    g_observer.store(observer);
}

namespace detail {

void* allocate_pixels(std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= kHugePage) {
        // Map one huge page more than needed, keep the part that starts on a huge-page
        // boundary, and ask for huge pages before anything touches it.
        const std::size_t size = mapped_size(bytes);
        void* m = mmap(nullptr, size + kHugePage, PROT_READ | PROT_WRITE,
                       MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (m == MAP_FAILED) throw std::bad_alloc();
        const auto base = reinterpret_cast<std::uintptr_t>(m);
        const std::uintptr_t aligned = (base + kHugePage - 1) & ~(kHugePage - 1);
        if (aligned > base) munmap(m, aligned - base);
        const std::uintptr_t end = base + size + kHugePage;
        if (end > aligned + size)
            munmap(reinterpret_cast<void*>(aligned + size), end - aligned - size);
        // Advice only: without transparent huge pages the kernel refuses it, and nothing else
        // depends on it.
        (void)madvise(reinterpret_cast<void*>(aligned), size, MADV_HUGEPAGE);
        if (const auto observer = g_observer.load()) observer(static_cast<std::ptrdiff_t>(size));
        return reinterpret_cast<void*>(aligned);
    }
#endif
    return ::operator new(bytes);
}

void release_pixels(void* p, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= kHugePage) {
        const std::size_t size = mapped_size(bytes);
        munmap(p, size);
        if (const auto observer = g_observer.load()) observer(-static_cast<std::ptrdiff_t>(size));
        return;
    }
#endif
    ::operator delete(p);
}

}  // namespace detail

Framebuffer::Framebuffer(std::uint32_t w, std::uint32_t h, ColorFormat cf, DepthFormat df,
                         std::uint32_t sample_count)
    : width(w), height(h), color_format(cf), depth_format(df), samples(sample_count) {
    const std::size_t n = pixel_count() * samples;
    if (cf == ColorFormat::Rgba8) {
        color8.assign(n * 4, 0);
    } else {
        color32f.assign(n * 4, 0.0f);
    }
    if (df != DepthFormat::None) depth.assign(n, 0);
}

}  // namespace refraster
