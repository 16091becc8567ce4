// observer.hpp: what the pipeline tells whoever watches one pixel, and the watcher that is
// not there.
//
// Implements: the observer interface every model and the stage-order loop call at each
// decision (a primitive begins, the clipper's polygons, a triangle's snapping, edges and
// outcome, a line or point set up, the exact oracle's weights, a primitive ends, a set-up
// primitive is about to be shaded), and NoObserver, whose hooks are empty inline functions:
// an untraced render is compiled with it and carries no trace code. TraceObserver
// (trace_observer.hpp) fills a PixelTrace through the same hooks.
//
// Deliberately does not: decide anything. No hook changes what is drawn.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "refraster/framebuffer.hpp"

namespace refraster::detail {

struct StageVertex;
struct StageTriangle;
struct TriangleSetup;
struct LineSetup;
struct PointSetup;
class VertexStage;
class ExactCoverage;
struct ScanlineRow;

// When a primitive's record is kept: always (a line the clipper removed), when it covers the
// pixel or one of its set-up boxes holds it, or only when it covers it (points).
enum class KeepRecord : std::uint8_t { Always, CoveredOrNear, Covered };

struct NoObserver {
    // Whether the observer reads planes no fragment kernel of the draw needs (fragment.hpp,
    // PlaneNeeds): setup leaves those out otherwise.
    static constexpr bool kReadsEveryPlane = false;

    void begin_primitive(std::string_view, std::size_t, std::size_t, std::span<const std::uint32_t>,
                         const VertexStage&, bool = false) {}
    void note(const char*) {}
    void dropped_draw(std::size_t, const char*) {}
    std::vector<std::vector<StageVertex>>* clip_polygons() { return nullptr; }
    void clipped(bool) {}
    void triangle_start(const std::array<const StageVertex*, 3>&, bool, int) {}
    void triangle_outcome(const char*) {}
    void triangle_setup(const TriangleSetup&) {}
    void triangle_drawn(const TriangleSetup&, std::size_t) {}
    void line_drawn(const StageVertex&, const StageVertex&, const LineSetup&, std::size_t) {}
    void point_drawn(const StageVertex&, const PointSetup&, std::size_t) {}
    void exact_setup(const ExactCoverage&) {}
    // The scanline model: a set-up primitive with its window vertices and covered rows, or
    // one setup rejected.
    void scanline_drawn(std::span<const std::array<float, 4>>, bool, std::span<const ScanlineRow>,
                        std::size_t) {}
    void scanline_rejected(std::span<const std::array<float, 4>>, bool, const char*) {}
    void end_primitive(KeepRecord) {}
    template <class List, class Primitive, class Kernel>
    void before_fragments(std::size_t, const List&, const Primitive&, const Kernel&,
                          const Framebuffer&) {}
    void list_done() {}
};

}  // namespace refraster::detail
