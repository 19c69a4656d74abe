#include "client/cli/run_overrides.h"

namespace mbstream::cli {

void RunOverrides::AddTo(CLI::App& command) {
  command.add_option("--duration", duration, "simulated time span (s)");
  command.add_option("--output-interval", output_interval, "time between output frames (s)");
  command.add_option("--max-step", max_step, "largest internal step of the integrator (s)");
  command.add_option("--formulation", formulation,
                     "auto, kinematic, joint, body-index3, body-index2, body-baumgarte");
  command.add_option("--method", method, "bdf, adams, erk, dirk, ida, rk4, euler");
  command.add_option("--erk-table", erk_table, "ARKODE Butcher table for erk/dirk");
  command.add_option("--rtol", rtol, "relative tolerance");
  command.add_option("--atol", atol, "absolute tolerance");
  command.add_option("--step", step, "fixed step of rk4 and euler (s)");
  command.add_option("--target-tcp", target_tcp,
                     "accuracy target: largest TCP error (m); the method and tolerances are "
                     "chosen for it (method auto) unless --method is given");
  command.add_option("--target-joint", target_joint,
                     "accuracy target: largest joint error (rad), like --target-tcp");
  command.add_option("--target-energy", target_energy,
                     "accuracy target: largest relative energy-balance error, like --target-tcp");
  command.add_option("--verify", verify,
                     "check the achieved error after a target run (true, the default, or false)");
  command.add_option("--keep", keep,
                     "the frames kept: all (the default of simulate and run), every:N (every Nth "
                     "and the last), final or summary (none: stats.json's summary only; the "
                     "default of sweep)");
}

void RunOverrides::ApplyTo(v1::RunSpec& spec) const {
  if (duration) spec.set_duration_s(*duration);
  if (output_interval) spec.set_output_interval_s(*output_interval);
  if (max_step) spec.set_max_step_s(*max_step);
  if (formulation) spec.set_formulation(*formulation);
  if (method) spec.set_method(*method);
  if (erk_table) spec.set_erk_table(*erk_table);
  if (rtol) spec.set_rtol(*rtol);
  if (atol) spec.set_atol(*atol);
  if (step) spec.set_fixed_step_s(*step);
  if (target_tcp) spec.mutable_target()->set_tcp_error_m(*target_tcp);
  if (target_joint) spec.mutable_target()->set_joint_error_rad(*target_joint);
  if (target_energy) spec.mutable_target()->set_energy_error_rel(*target_energy);
  if ((target_tcp || target_joint || target_energy) && !method) spec.set_method("auto");
  if (verify) spec.set_verify(*verify);
  if (keep) spec.set_keep(*keep);
}

}  // namespace mbstream::cli
