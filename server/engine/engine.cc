#include "server/engine/engine.h"

#include "server/choose/loop_target_run.h"
#include "server/choose/target_run.h"
#include "server/engine/summary_sink.h"
#include "server/sim/loop_run.h"
#include "server/sim/simulate.h"

namespace mbstream {

namespace {

RunResult Dispatch(const Model& model, const std::vector<LoopClosure>& loops,
                   const RunConfig& config, FrameSink* sink, const std::atomic<bool>* cancel,
                   ControlLaw* control) {
  if (!loops.empty()) {
    if (config.target.any()) return RunLoopsWithTarget(model, loops, config, sink, cancel);
    return SimulateLoops(model, loops, config, sink, cancel);
  }
  if (config.target.any()) return RunWithTarget(model, config, sink, cancel);
  return SimulateTree(model, config, sink, cancel, {}, control);
}

}  // namespace

RunResult Simulate(const Model& model, const std::vector<LoopClosure>& loops,
                   const RunConfig& config, FrameSink* sink, const std::atomic<bool>* cancel,
                   ControlLaw* control) {
  SummarySink summary(config, sink);
  RunResult result = Dispatch(model, loops, config, &summary, cancel, control);
  summary.Finish(&result);
  return result;
}

RunResult Simulate(const Model& model, const RunConfig& config, FrameSink* sink,
                   const std::atomic<bool>* cancel) {
  return Simulate(model, {}, config, sink, cancel);
}

}  // namespace mbstream
