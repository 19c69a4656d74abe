// RunConfig -> RunSpec, for recording the spec a run used (every field set explicitly).
#include <cstdint>

#include "server/spec/contact_spec.h"
#include "server/spec/initial_bodies_spec.h"
#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

void ToTrajectorySpec(const Trajectory& trajectory, v1::Trajectory* spec) {
  switch (trajectory.kind) {
    case Trajectory::Kind::kSine: {
      MBSTREAM_CHECK(trajectory.omega.size() == trajectory.amplitude.size() &&
                     trajectory.phase.size() == trajectory.amplitude.size());
      v1::SumOfSines* sines = spec->mutable_sum_of_sines();
      sines->set_offset(trajectory.offset);
      for (size_t k = 0; k < trajectory.amplitude.size(); ++k) {
        v1::Sine* sine = sines->add_terms();
        sine->set_amplitude(trajectory.amplitude[k]);
        sine->set_omega(trajectory.omega[k]);
        sine->set_phase(trajectory.phase[k]);
      }
      return;
    }
    case Trajectory::Kind::kSpline: {
      v1::Spline* spline = spec->mutable_spline();
      spline->mutable_times_s()->Add(trajectory.times.begin(), trajectory.times.end());
      spline->mutable_values()->Add(trajectory.values.begin(), trajectory.values.end());
      return;
    }
  }
  MBSTREAM_CHECK_MSG(false, "unknown Trajectory::Kind");
}

void ToDriveSpec(const DriveConfig& drive, v1::Drive* spec) {
  switch (drive.kind) {
    case DriveConfig::Kind::kPassive:
      spec->mutable_passive();
      return;
    case DriveConfig::Kind::kPrescribed:
      ToTrajectorySpec(drive.trajectory, spec->mutable_prescribed()->mutable_trajectory());
      spec->mutable_prescribed()->set_velocity_source(drive.velocity_source);
      return;
    case DriveConfig::Kind::kTorque: {
      v1::Drive::Torque* torque = spec->mutable_torque();
      torque->set_constant(drive.constant);
      torque->set_amplitude(drive.amplitude);
      torque->set_omega(drive.omega);
      torque->set_phase(drive.phase);
      return;
    }
    case DriveConfig::Kind::kPdServo: {
      v1::Drive::PdServo* servo = spec->mutable_pd_servo();
      servo->set_kp(drive.kp);
      servo->set_kd(drive.kd);
      ToTrajectorySpec(drive.trajectory, servo->mutable_trajectory());
      servo->set_period_s(drive.period);
      return;
    }
    case DriveConfig::Kind::kExternal: {
      v1::Drive::External* external = spec->mutable_external();
      external->set_command(drive.command == DriveConfig::Command::kEffort     ? "effort"
                            : drive.command == DriveConfig::Command::kPosition ? "position"
                                                                               : "velocity");
      external->set_period_s(drive.period);
      external->set_kp(drive.kp);
      external->set_kd(drive.kd);
      return;
    }
  }
  MBSTREAM_CHECK_MSG(false, "unknown DriveConfig::Kind");
}

}  // namespace

v1::RunSpec ToRunSpec(const RunConfig& config) {
  v1::RunSpec spec;
  spec.set_duration_s(config.duration);
  spec.set_output_interval_s(config.output_interval);
  spec.set_max_step_s(config.max_step);
  spec.set_formulation(FormulationName(config.formulation));
  spec.set_method(config.method_auto ? "auto" : MethodName(config.method));
  if (config.target.any()) {
    v1::Target* target = spec.mutable_target();
    if (config.target.tcp_error_m > 0.0) target->set_tcp_error_m(config.target.tcp_error_m);
    if (config.target.joint_error_rad > 0.0) {
      target->set_joint_error_rad(config.target.joint_error_rad);
    }
    if (config.target.energy_error_rel > 0.0) {
      target->set_energy_error_rel(config.target.energy_error_rel);
    }
  }
  spec.set_verify(config.verify);
  if (config.keep.mode != FrameKeep::Mode::kAll) spec.set_keep(FrameKeepName(config.keep));
  spec.set_erk_table(config.erk_table);
  spec.set_rtol(config.rtol);
  spec.set_atol(config.atol);
  spec.set_fixed_step_s(config.fixed_step);
  spec.mutable_gravity()->set_x(config.gravity.x());
  spec.mutable_gravity()->set_y(config.gravity.y());
  spec.mutable_gravity()->set_z(config.gravity.z());
  spec.mutable_initial_q()->Add(config.q0.begin(), config.q0.end());
  spec.mutable_initial_qd()->Add(config.qd0.begin(), config.qd0.end());
  ToBodyStateSpecs(config.initial_bodies, spec.mutable_initial_bodies());
  for (const DriveConfig& drive : config.drives) ToDriveSpec(drive, spec.add_drives());
  spec.set_want_torques(config.want_torques);
  spec.set_report_loop_forces(config.want_loop_forces);
  spec.mutable_baumgarte()->set_alpha(config.baumgarte.alpha);
  spec.mutable_baumgarte()->set_beta(config.baumgarte.beta);
  ToContactSpec(config.contact, spec.mutable_contact());
  for (const SensorPointConfig& sensor : config.sensor_points) {
    v1::SensorPoint* point = spec.add_sensor_points();
    point->set_name(sensor.name);
    point->set_link(sensor.link);
    point->mutable_offset_m()->set_x(sensor.offset.x());
    point->mutable_offset_m()->set_y(sensor.offset.y());
    point->mutable_offset_m()->set_z(sensor.offset.z());
  }
  // 0 = the default budget: the fields stay absent.
  MBSTREAM_CHECK_MSG(config.max_steps >= 0 && config.max_steps <= INT32_MAX,
                     "RunConfig::max_steps must fit RunSpec.max_internal_steps (int32)");
  if (config.max_steps > 0) spec.set_max_internal_steps(static_cast<int32_t>(config.max_steps));
  if (config.max_cpu_s > 0.0) spec.set_max_cpu_s(config.max_cpu_s);
  return spec;
}

}  // namespace mbstream
