// traced_models.cpp: every model's setup instantiated for the trace observer, so that a model
// names no observer but the stages' own (stages/observer.hpp).
#include "models/llvmpipe/llvmpipe_model_impl.hpp"
#include "models/softpipe/softpipe_model_impl.hpp"
#include "trace/trace_observer.hpp"

namespace refraster::detail {

template void LlvmpipeModel::setup(VertexStage&, TraceObserver&, const ListSink<SetupList>&);
template void SoftpipeModel::setup(VertexStage&, TraceObserver&, const ListSink<ScanlineList>&);

}  // namespace refraster::detail
