#include "server/wire/frame_conversion.h"

#include <algorithm>

#include <cmath>
#include <string>
#include <vector>

#include "server/wire/contact_conversion.h"
#include "server/wire/stats_conversion.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// Writes `count` values at `offset` of `out`, which it resizes to offset + count.
void CopyFinite(const double* values, int count, google::protobuf::RepeatedField<double>* out,
                int offset = 0) {
  out->Resize(offset + count, 0.0);
  for (int i = 0; i < count; ++i) {
    MBSTREAM_CHECK_MSG(std::isfinite(values[i]), "a non-finite value reached the wire");
    out->Set(offset + i, values[i]);
  }
}

// The cut joints whose reactions a run's frames carry (RunSpec.report_loop_forces), from
// RunStats.loops.cut_joints ("NAME (TYPE)"): none for a tree or a run that reports none.
std::vector<std::string> LoopForceNames(const v1::RunInfo& info) {
  std::vector<std::string> names;
  if (!info.spec().report_loop_forces()) return names;
  for (const std::string& cut : info.stats().loops().cut_joints()) {
    names.push_back(cut.substr(0, cut.rfind(" (")));
  }
  return names;
}

}  // namespace

void FrameToProto(const RunResult& result, int k, v1::Frame* frame) {
  const int n = result.num_dofs;
  const int nq = result.positions();
  MBSTREAM_CHECK(k >= 0 && k < result.num_frames());
  frame->set_seq(result.first_seq + k);
  frame->set_t_s(result.t[k]);
  CopyFinite(&result.q[k * nq], nq, frame->mutable_q());
  CopyFinite(&result.qd[k * n], n, frame->mutable_qd());
  const double* p = &result.tcp[3 * k];
  MBSTREAM_CHECK_MSG(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]),
                     "a non-finite TCP reached the wire");
  frame->mutable_tcp_m()->set_x(p[0]);
  frame->mutable_tcp_m()->set_y(p[1]);
  frame->mutable_tcp_m()->set_z(p[2]);
  // tau: the drive efforts (n, when the run computes them), then the cut joints' reactions
  // (6 each, when the run reports them: RunSpec.report_loop_forces).
  const int efforts = result.has_torques ? n : 0;
  frame->clear_tau();
  if (result.has_torques) CopyFinite(&result.tau[k * n], n, frame->mutable_tau());
  const int forces = 6 * static_cast<int>(result.loop_force_names.size());
  if (forces > 0) {
    CopyFinite(&result.loop_forces[k * forces], forces, frame->mutable_tau(), efforts);
  }
  if (result.has_energy) {
    MBSTREAM_CHECK(std::isfinite(result.kinetic[k]) && std::isfinite(result.potential[k]));
    frame->set_kinetic_j(result.kinetic[k]);
    frame->set_potential_j(result.potential[k]);
  }
  ContactsToProto(result.contacts, result.t[k], frame->mutable_contacts());
}

RunResult ResultFromFrames(const v1::RunInfo& info, const std::vector<v1::Frame>& frames) {
  RunResult result;
  result.num_dofs = info.num_dofs();
  result.joint_names.assign(info.joint_names().begin(), info.joint_names().end());
  result.num_positions = info.num_positions();
  result.position_names.assign(info.position_names().begin(), info.position_names().end());
  if (result.num_positions > 0) {  // a one-coordinate joint's position has its own name
    for (const std::string& name : result.joint_names) {
      const auto at = std::find(result.position_names.begin(), result.position_names.end(), name);
      result.position_index.push_back(at == result.position_names.end()
                                          ? -1
                                          : static_cast<int>(at - result.position_names.begin()));
    }
  }
  result.has_energy = info.has_energy();
  result.stats = StatsFromProto(info);
  result.loop_force_names = LoopForceNames(info);
  const int n = result.num_dofs;
  const int nq = result.positions();
  const int forces = 6 * static_cast<int>(result.loop_force_names.size());
  // A run recovered from its stored frames guesses has_torques from a non-empty tau
  // (kept_frames.h), which the reactions alone also fill: the frames' width decides.
  result.has_torques =
      info.has_torques() && (frames.empty() || forces == 0 || frames[0].tau_size() == n + forces);
  const int efforts = result.has_torques ? n : 0;
  const size_t count = frames.size();
  result.t.reserve(count);
  result.q.reserve(count * nq);
  result.qd.reserve(count * n);
  result.tcp.reserve(count * 3);
  result.loop_forces.reserve(count * forces);
  for (const v1::Frame& frame : frames) {
    if (frame.q_size() != nq || frame.qd_size() != n || frame.tau_size() != efforts + forces) {
      throw InputError("run " + info.id() + ": frame " + std::to_string(frame.seq()) + " has " +
                       std::to_string(frame.q_size()) + " joint values and " +
                       std::to_string(frame.tau_size()) + " efforts and reactions, expected " +
                       std::to_string(nq) + " and " + std::to_string(efforts + forces) +
                       "; the result is corrupt, run it again");
    }
    result.t.push_back(frame.t_s());
    result.q.insert(result.q.end(), frame.q().begin(), frame.q().end());
    result.qd.insert(result.qd.end(), frame.qd().begin(), frame.qd().end());
    result.tcp.insert(result.tcp.end(), {frame.tcp_m().x(), frame.tcp_m().y(), frame.tcp_m().z()});
    if (result.has_torques) {
      result.tau.insert(result.tau.end(), frame.tau().begin(), frame.tau().begin() + n);
    }
    result.loop_forces.insert(result.loop_forces.end(), frame.tau().begin() + efforts,
                              frame.tau().end());
    if (result.has_energy) {
      result.kinetic.push_back(frame.kinetic_j());
      result.potential.push_back(frame.potential_j());
    }
  }
  ContactsFromFrames(frames, result.stats.contact.active, &result.contacts);
  return result;
}

}  // namespace mbstream
