// trace_observer.hpp: the observer that records every decision about one pixel.
//
// Implements: TraceObserver, which fills a PixelTrace (refraster/trace.hpp) through the hooks
// of observer.hpp: the primitive's input and clip masks, the clipper's polygons, each set-up
// triangle, line or point with its edge values and tie decisions at the pixel, and the
// fragment stage's decisions there, taken from the draw's fragment kernel just before the
// primitive is shaded (so that the depth and colour it read are those of that moment).
//
// Deliberately does not: run in an untraced render (NoObserver stands in), or format anything.
#pragma once

#include <cstddef>
#include <vector>

#include "models/llvmpipe/setup.hpp"
#include "refraster/trace.hpp"
#include "stages/observer.hpp"
#include "stages/vertex_stage.hpp"  // StageVertex complete: the clipper polygons are held by value

namespace refraster::detail {

class TraceObserver {
  public:
    static constexpr bool kReadsEveryPlane = true;  // the trace shows the z and 1/w planes

    // `multisample`: the draw's coverage is tested at the samples (SetupParams::multisample);
    // edges are then evaluated at sample trace.sample of the pixel.
    explicit TraceObserver(PixelTrace& trace, bool multisample = false)
        : trace_(trace), multisample_(multisample) {}

    void begin_primitive(std::string_view kind, std::size_t draw, std::size_t primitive,
                         std::span<const std::uint32_t> vertices, const VertexStage& stage,
                         bool in_pipeline = false);
    void note(const char* text) { pt_.note = text; }
    void dropped_draw(std::size_t draw, const char* why);
    std::vector<std::vector<StageVertex>>* clip_polygons() { return &polygons_; }
    void clipped(bool nothing_left);
    void triangle_start(const std::array<const StageVertex*, 3>& v, bool clipped, int bits);
    void triangle_outcome(const char* outcome);
    void triangle_setup(const TriangleSetup& t);
    void triangle_drawn(const TriangleSetup& t, std::size_t list_index);
    void line_drawn(const StageVertex& v1, const StageVertex& v2, const LineSetup& s,
                    std::size_t list_index);
    void point_drawn(const StageVertex& v, const PointSetup& s, std::size_t list_index);
    void exact_setup(const ExactCoverage& ex);
    void scanline_drawn(std::span<const std::array<float, 4>> window, bool clipped,
                        std::span<const ScanlineRow> rows, std::size_t list_index);
    void scanline_rejected(std::span<const std::array<float, 4>> window, bool clipped,
                           const char* outcome);
    void end_primitive(KeepRecord keep);

    template <class List, class Primitive, class Kernel>
    void before_fragments(std::size_t list_index, const List& list, const Primitive& prim,
                          const Kernel& kernel, const Framebuffer& fb) {
        while (next_ < ready_.size() && ready_[next_].list_index == list_index) {
            const Pending& p = ready_[next_++];
            trace_.primitives[p.primitive].setups[p.setup].fragment = kernel.trace(
                list, prim, trace_.x, trace_.y, static_cast<unsigned>(trace_.sample), fb);
        }
    }
    void list_done() {
        ready_.clear();
        next_ = 0;
    }

  private:
    // A set-up primitive of the current list whose fragment at the pixel is still to be traced.
    struct Pending {
        std::size_t list_index = 0;
        std::size_t primitive = 0;  // in trace_.primitives
        std::size_t setup = 0;      // in its setups
    };
    template <class Setup>
    void record_edges(const Setup& t, std::size_t edge_count);
    void covered(bool in, std::size_t list_index);
    bool in_box(const PixelRect& b) const;
    bool near(const PrimitiveTrace& pt) const;
    // The traced point's offset on edge e: the sample's, or 0 at the pixel.
    std::int64_t point_offset(const EdgeFunction& e, int bits) const;
    template <class Setup>
    bool covers(const Setup& t, std::size_t edge_count);

    PixelTrace& trace_;
    bool multisample_ = false;
    PrimitiveTrace pt_;
    SetupTrace s_;
    std::vector<std::vector<StageVertex>> polygons_;
    std::vector<Pending> open_;   // of pt_: primitive not known yet
    std::vector<Pending> ready_;  // in list order
    std::size_t next_ = 0;
};

}  // namespace refraster::detail
