// Work-precision study of the four IRB 1600 reference scenes (models/irb1600/*.json) and the
// passive closed-loop linkages (models/linkages/: four_bar, slider_crank, delta, palletiser,
// each its -passive.json): every scene x formulation x method over a sweep of tolerances
// (adaptive methods) or steps (fixed-step methods), one CSV row per run:
//
//   build/bench/work_precision --out docs/work_precision.csv
//   build/bench/work_precision --scenes four_bar,slider_crank,delta --out loops.csv
//   /usr/bin/python3 scripts/plot_work_precision.py --csv docs/work_precision.csv --out-dir docs
//
// Columns: scene, formulation, method, rtol (adaptive runs; atol = rtol / 100), step
// (fixed-step runs, s), error (m), cpu_s, steps, rhs_evals, status, then atol, t_reached (s),
// energy_error (RunStats::energy_error_max, relative), error_until (s) and drift (m,
// RunStats::drift_position_max of the body formulations: how far their joint points came
// apart; -1 for the others).
//
// Formulations: joint with every method, kinematic (seed-run), and the body-coordinate
// variants body-index3 and body-index2 with IDA and body-baumgarte with CVODE BDF (the
// --methods names body-index3/ida, body-index2/ida, body-baumgarte/bdf).
//
// error: for the linkages the largest joint difference (rad, or m for the slider) from the
// reference instead of the TCP's. For seed-run, whose joints are all prescribed,
// RunStats::tcp_error_max (the TCP against direct kinematics of the closed-form seed motion). For
// the other scenes, the largest TCP distance from a reference solution over the output frames in
// [0, error_until]: the reference is a tight run (ERK Fehlberg 13-7-8 at rtol 1e-14; for
// stiff-servo CVODE BDF at rtol 1e-12) checked against an independent tight run (ERK Verner 8-5-6
// at rtol 1e-13; DIRK at rtol 1e-12), and trusted over the leading frames where the two agree
// within 1e-8 m (all of them unless the motion is chaotic). Their agreement there is written as a
// row with method "reference" and status REFERENCE: the floor below which errors mean
// nothing. A failed run's error is taken over the frames it produced; status says why it
// stopped. Once a tolerance runs out of steps (TOO_MUCH_WORK) the tighter ones of that
// method are not run (status SKIPPED).
// cpu_s is the median of three runs for runs under 0.5 s, else the single run's.
//
// The linkages (scene names of models/linkages/*.sdf): their reference is the trees' (ERK
// Fehlberg at 1e-14 checked by Verner at 1e-13, with Baumgarte alone: no projection, whose
// Newton tolerance, atol / 100, limits BDF; agreement 5.5e-9 rad over the four-bar's 5 s,
// where BDF at 1e-11 and Adams at 1e-11 part by 4.4e-6). Their methods (default): bdf
// (Baumgarte and projection), adams, erk, erk-verner, dirk (Baumgarte alone), ida (the
// joint-space index-2 GGL DAE), rk4, and the body-coordinate formulations with the cut
// joints as constraints between bodies: body-index2/ida and body-baumgarte/bdf, and
// body-index3/ida (refused with loops: status REFUSED). drift is the largest position
// constraint residual (m or rad) over the frames.
//
// The contact scenes (issue 44: stiff contact against explicit methods): contact-bounce, a
// 1 kg ball of radius 0.1 m dropped 0.9 m onto a plane (tests/data/contact/ball_on_plane.sdf)
// with Hunt-Crossley contact, k = 1e6 N/m a surface (5e5 for the pair, a contact period of
// 2 pi sqrt(m/k) = 8.9 ms), d = 0.2 s/m, over 2 s (five bounces); contact-slide, a 0.2 m box
// launched at 1 m/s along a plane (box_on_plane.sdf) that friction (mu_d = 0.5) stops at
// t = 0.2 s and static friction then holds: the Stribeck function's slope below v_s = 1e-4
// m/s is the stiff part. Their error is the largest distance of the body's origin (m) from
// the reference (BDF at rtol 1e-12, checked by DIRK at 1e-12); their methods bdf, dirk, erk,
// rk4 and euler (semi-implicit), the fixed steps down to 1 us.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include "server/engine/engine.h"
#include "server/parse/sdf_import.h"
#include "server/parse/urdf_import.h"
#include "server/sim/loop_run.h"
#include "server/sim/run_config.h"
#include "server/sim/run_result.h"
#include "server/sim/run_validation.h"
#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

constexpr double kQuickDuration = 1.0;  // s, the duration of every scene with --quick
constexpr double kRepeatBelow = 0.5;    // s of CPU: runs faster than this are timed 3 times
// m: the reference is trusted over the leading frames where its check agrees this well.
constexpr double kReferenceAgreement = 1e-8;

struct Options {
  std::string out = "work_precision.csv";
  std::string models_dir = MBSTREAM_SOURCE_DIR "/models/irb1600";
  std::string linkages_dir = MBSTREAM_SOURCE_DIR "/models/linkages";
  std::vector<std::string> scenes = {"seed-run", "seed-servo", "passive-swing", "stiff-servo"};
  std::vector<std::string> methods;  // empty = all (or the quick subset)
  bool quick = false;
  double duration = 0.0;  // s, > 0: overrides every scene's duration
  long max_steps = 2'000'000;
};

// One integrator setting: a formulation and a method, with an ARKODE table for the ERK
// variants.
struct MethodVariant {
  std::string label;  // the CSV's method column
  Method method;
  std::string table;
  bool fixed_step;
  Formulation formulation = Formulation::kJoint;
  long max_steps = 0;  // > 0: a smaller step budget than the study's (--max-steps)
  // The name --methods selects it by: the label for the joint formulation, else
  // "<formulation>/<label>".
  std::string name() const {
    return formulation == Formulation::kJoint
               ? label
               : std::string(FormulationName(formulation)) + "/" + label;
  }
};

// body-index3 at loose tolerances fails the error test at almost every step (about 0.2 ms
// each): its budget keeps a sweep to seconds per run.
constexpr long kIndex3MaxSteps = 100'000;

const std::vector<MethodVariant>& AllMethods() {
  static const std::vector<MethodVariant> methods = {
      {"bdf", Method::kBdf, "", false},
      {"adams", Method::kAdams, "", false},
      {"erk", Method::kErk, "", false},
      {"erk-verner", Method::kErk, "verner", false},
      {"dirk", Method::kDirk, "", false},
      {"rk4", Method::kRk4, "", true},
      {"euler", Method::kEuler, "", true},
      {"ida", Method::kIda, "", false, Formulation::kBodyIndex3, kIndex3MaxSteps},
      {"ida", Method::kIda, "", false, Formulation::kBodyIndex2},
      {"bdf", Method::kBdf, "", false, Formulation::kBodyBaumgarte},
      {"ida", Method::kIda, "", false},  // joint space: the loops' GGL DAE
  };
  return methods;
}

// The linkages' default methods (by name()).
const std::vector<std::string> kLoopMethods = {"bdf",
                                               "adams",
                                               "erk",
                                               "erk-verner",
                                               "dirk",
                                               "ida",
                                               "rk4",
                                               "body-index2/ida",
                                               "body-baumgarte/bdf",
                                               "body-index3/ida"};

// The contact scenes' methods: the implicit and the explicit ones the issue compares.
const std::vector<std::string> kContactMethods = {"bdf", "dirk", "erk", "rk4", "euler"};

bool IsContactScene(const std::string& scene) {
  return scene == "contact-bounce" || scene == "contact-slide";
}

bool IsLinkage(const std::string& scene) {
  return scene == "four_bar" || scene == "slider_crank" || scene == "delta" ||
         scene == "palletiser";
}

// What a scene's error is measured on, per output frame (TrackOf).
enum class Track {
  kTcp,           // the TCP, 3 values (m); the distance between two frames the Euclidean norm
  kJoints,        // every joint (rad or m; the largest difference): the linkages, whose TCP may
                  // not move (the four-bar's and slider-crank's)
  kBodyPosition,  // the first free body's origin, x y z (m; Euclidean): the contact scenes
};

struct Scene {
  std::string name;
  Track track = Track::kTcp;
  Model model;
  std::vector<LoopClosure> loops;       // the linkages' cut joints (empty: a tree)
  RunConfig config;                     // as shipped (duration shortened with --quick)
  bool closed_form = false;             // every joint prescribed: error = tcp_error_max
  std::vector<double> reference_track;  // TrackOf the reference (scenes without a closed form)
  int window_frames = 0;                // errors are measured over these leading frames
  double window_end = 0.0;              // s, the time of the last of them
};

struct Row {
  std::string scene, formulation, method;
  std::optional<double> rtol, atol, step;
  double error = 0.0;
  double error_until = 0.0;  // s, the end of the window the error is measured over
  double cpu_s = 0.0;
  long steps = 0, rhs_evals = 0;
  std::string status;
  double t_reached = 0.0;
  double energy_error = -1.0;
  double drift = -1.0;
};

std::string FormatOptional(const std::optional<double>& value) {
  if (!value) return "";
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", *value);
  return text;
}

// The values TrackOf `result` has per frame.
size_t Stride(const Scene& scene, const RunResult& result) {
  return scene.track == Track::kJoints ? static_cast<size_t>(result.num_dofs) : 3;
}

// The scene's track of `result`, Stride values per output frame.
std::vector<double> TrackOf(const Scene& scene, const RunResult& result) {
  switch (scene.track) {
    case Track::kTcp:
      return result.tcp;
    case Track::kJoints:
      return result.q;
    case Track::kBodyPosition:
      break;
  }
  std::vector<double> origin;
  const size_t n = static_cast<size_t>(result.num_positions);
  for (size_t k = 0; k < result.t.size(); ++k) {
    for (size_t c = 0; c < 3; ++c) origin.push_back(result.q[n * k + c]);
  }
  return origin;
}

// The distance of frame k of `track` from the reference's (Stride `n` values a frame).
double FrameDistance(const Scene& scene, const std::vector<double>& track, size_t n,
                     const std::vector<double>& reference, size_t k) {
  double squared = 0.0, largest = 0.0;
  for (size_t c = 0; c < n; ++c) {
    const double d = track[n * k + c] - reference[n * k + c];
    squared += d * d;
    largest = std::max(largest, std::abs(d));
  }
  return scene.track == Track::kJoints ? largest : std::sqrt(squared);
}

// Largest distance of `result`'s track from `reference` over the first `frames` frames (or
// fewer, when the run stopped early).
double TrackDistanceMax(const Scene& scene, const RunResult& result,
                        const std::vector<double>& reference, int frames) {
  const size_t n = Stride(scene, result);
  const std::vector<double> track = TrackOf(scene, result);
  const size_t count =
      std::min({static_cast<size_t>(result.num_frames()), reference.size() / std::max<size_t>(1, n),
                static_cast<size_t>(frames)});
  double error = 0.0;
  for (size_t k = 0; k < count; ++k) {
    error = std::max(error, FrameDistance(scene, track, n, reference, k));
  }
  return error;
}

// Runs `config` once, or three times when it is fast, and returns the first result with
// the median CPU time in its stats.
RunResult TimedRun(const Scene& scene, const RunConfig& config) {
  if (!scene.loops.empty()) ValidateLoopRun(scene.model, scene.loops, config);
  auto run = [&] { return Simulate(scene.model, scene.loops, config); };
  RunResult result = run();
  if (result.stats.cpu_s < kRepeatBelow) {
    std::array<double, 3> cpu{result.stats.cpu_s, run().stats.cpu_s, run().stats.cpu_s};
    std::sort(cpu.begin(), cpu.end());
    result.stats.cpu_s = cpu[1];
  }
  return result;
}

RunConfig WithMethod(RunConfig config, const MethodVariant& variant) {
  config.method = variant.method;
  config.erk_table = variant.table;
  return config;
}

RunResult MustFinish(const Scene& scene, const RunConfig& config, const std::string& what) {
  RunResult result = Simulate(scene.model, scene.loops, config);
  if (result.stats.status != RunStatus::kFinished) {
    throw std::runtime_error(what + " did not finish: " + RunStatusName(result.stats.status) +
                             ": " + result.stats.message);
  }
  return result;
}

// How a scene's reference is computed: a tight run and an independent tight check.
struct ReferencePlan {
  MethodVariant reference, check;
  double reference_rtol, check_rtol;
};

// Explicit high-order tables, except where stiffness makes them hopeless: in stiff-servo the
// wrist servo's fast eigenvalue (about kd / J6 = 2e4 / 0.00375 = 5e6 1/s) holds explicit
// steps below a microsecond, so its reference is implicit.
ReferencePlan ReferencePlanFor(const std::string& scene) {
  if (scene == "stiff-servo" || IsContactScene(scene)) {
    return {{"bdf", Method::kBdf, "", false}, {"dirk", Method::kDirk, "", false}, 1e-12, 1e-12};
  }
  return {{"erk-fehlberg", Method::kErk, "fehlberg", false},
          {"erk-verner", Method::kErk, "verner", false},
          1e-14,
          1e-13};
}

// Computes the scene's reference TCP track and the window over which it is trusted (the
// leading frames where the check agrees within kReferenceAgreement), and returns the row
// that reports how converged it is.
Row ComputeReference(Scene& scene) {
  RunConfig config = scene.config;
  config.formulation = Formulation::kJoint;
  config.max_steps = 50'000'000;
  config.max_step = 0.0;
  const ReferencePlan plan = ReferencePlanFor(scene.name);

  RunConfig reference_config = WithMethod(config, plan.reference);
  reference_config.rtol = plan.reference_rtol;
  reference_config.atol = plan.reference_rtol * 1e-2;
  const RunResult reference = MustFinish(scene, reference_config, scene.name + " reference");
  scene.reference_track = TrackOf(scene, reference);

  RunConfig check_config = WithMethod(config, plan.check);
  check_config.rtol = plan.check_rtol;
  check_config.atol = plan.check_rtol * 1e-2;
  const RunResult check = MustFinish(scene, check_config, scene.name + " reference check");
  const int frames = reference.num_frames();
  const double agreement_limit = kReferenceAgreement;
  const std::vector<double> check_track = TrackOf(scene, check);
  const size_t stride = Stride(scene, check);
  int window = 0;
  double agreement = 0.0;       // over the window
  double difference_max = 0.0;  // over the whole run
  for (int k = 0; k < frames; ++k) {
    const double d =
        FrameDistance(scene, check_track, stride, scene.reference_track, static_cast<size_t>(k));
    difference_max = std::max(difference_max, d);
    if (window == k && d <= agreement_limit) {
      ++window;
      agreement = std::max(agreement, d);
    }
  }
  scene.window_frames = window;
  scene.window_end = reference.t[window - 1];
  std::printf(
      "%s: reference %s rtol %.0e atol %.0e (%ld steps, %.3g s CPU); check %s rtol %.0e: max "
      "difference %.3g (TCP m; linkages: joints, rad or m; contact: the body's origin, m) over the "
      "run",
      scene.name.c_str(), plan.reference.label.c_str(), reference_config.rtol,
      reference_config.atol, reference.stats.solver.steps, reference.stats.cpu_s,
      plan.check.label.c_str(), check_config.rtol, difference_max);
  if (window < frames) {
    std::printf("; within %.0e m up to t = %.3g s: errors are measured over [0, %.3g] s\n",
                agreement_limit, scene.window_end, scene.window_end);
  } else {
    std::printf("\n");
  }
  std::fflush(stdout);

  Row row;
  row.scene = scene.name;
  row.formulation = "joint";
  row.method = "reference";
  row.rtol = reference_config.rtol;
  row.atol = reference_config.atol;
  row.error = agreement;
  row.error_until = scene.window_end;
  row.cpu_s = reference.stats.cpu_s;
  row.steps = reference.stats.solver.steps;
  row.rhs_evals = reference.stats.solver.rhs_evals;
  row.status = "REFERENCE";
  row.t_reached = reference.stats.t_reached;
  row.energy_error = reference.stats.energy_error_max;
  return row;
}

Row RunOne(const Scene& scene, const RunConfig& config, const std::string& method_label) {
  Row row;
  row.scene = scene.name;
  row.formulation = FormulationName(config.formulation);
  row.method = method_label;
  try {
    const RunResult result = TimedRun(scene, config);
    const RunStats& s = result.stats;
    row.error = scene.closed_form
                    ? s.tcp_error_max
                    : TrackDistanceMax(scene, result, scene.reference_track, scene.window_frames);
    row.error_until = std::min(scene.window_end, s.t_reached);
    row.cpu_s = s.cpu_s;
    row.steps = s.solver.steps;
    row.rhs_evals = s.solver.rhs_evals;
    row.status = RunStatusName(s.status);
    row.t_reached = s.t_reached;
    row.energy_error = s.energy_error_max;
    row.drift = s.drift_position_max;
  } catch (const InputError& e) {
    row.status = "REFUSED";
    std::fprintf(stderr, "%s %s: refused: %s\n", scene.name.c_str(), method_label.c_str(),
                 e.what());
  }
  return row;
}

void PrintRow(const Row& row) {
  std::printf("%-13s %-14s %-10s rtol %-7s step %-7s error %-9.3g cpu %9.4f s steps %8ld %s\n",
              row.scene.c_str(), row.formulation.c_str(), row.method.c_str(),
              FormatOptional(row.rtol).c_str(), FormatOptional(row.step).c_str(), row.error,
              row.cpu_s, row.steps, row.status.c_str());
  std::fflush(stdout);
}

void WriteCsv(const std::string& path, const std::vector<Row>& rows) {
  FILE* file = std::fopen(path.c_str(), "w");
  if (!file) throw std::runtime_error("cannot write " + path);
  std::fprintf(file,
               "scene,formulation,method,rtol,step,error,cpu_s,steps,rhs_evals,status,atol,"
               "t_reached,energy_error,error_until,drift\n");
  for (const Row& r : rows) {
    std::fprintf(file, "%s,%s,%s,%s,%s,%.6e,%.6e,%ld,%ld,%s,%s,%.6g,%.6e,%.6g,%.6e\n",
                 r.scene.c_str(), r.formulation.c_str(), r.method.c_str(),
                 FormatOptional(r.rtol).c_str(), FormatOptional(r.step).c_str(), r.error, r.cpu_s,
                 r.steps, r.rhs_evals, r.status.c_str(), FormatOptional(r.atol).c_str(),
                 r.t_reached, r.energy_error, r.error_until, r.drift);
  }
  if (std::fclose(file) != 0) throw std::runtime_error("cannot write " + path);
}

std::vector<MethodVariant> SelectedMethods(const Options& options, bool linkage, bool contact) {
  std::vector<std::string> names = options.methods;
  if (names.empty() && linkage) names = kLoopMethods;
  if (names.empty() && contact) names = kContactMethods;
  if (names.empty() && options.quick) {
    names = {"bdf", "rk4", "body-index3/ida", "body-index2/ida", "body-baumgarte/bdf"};
  }
  if (names.empty()) {  // the trees: every method but the loops' DAE
    std::vector<MethodVariant> all;
    for (const MethodVariant& m : AllMethods()) {
      if (!(m.method == Method::kIda && m.formulation == Formulation::kJoint)) all.push_back(m);
    }
    return all;
  }
  std::vector<MethodVariant> selected;
  for (const std::string& name : names) {
    const auto it = std::find_if(AllMethods().begin(), AllMethods().end(),
                                 [&](const MethodVariant& m) { return m.name() == name; });
    if (it == AllMethods().end()) throw InputError("unknown method '" + name + "'");
    selected.push_back(*it);
  }
  return selected;
}

// A contact scene's model and run (IsContactScene), built here: a passive free body, BDF at
// the study's tolerances, output every 1 ms.
Model ContactScene(const std::string& name, RunConfig* config) {
  const bool bounce = name == "contact-bounce";
  Model model = ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/contact/" +
                              (bounce ? "ball_on_plane.sdf" : "box_on_plane.sdf"))
                    .model;
  *config = RunConfig{};
  config->formulation = Formulation::kJoint;
  config->duration = bounce ? 2.0 : 1.0;
  config->output_interval = 1e-3;
  config->want_torques = false;
  config->drives.resize(static_cast<size_t>(model.nv()));  // passive
  config->contact.stiffness = 1e6;                         // N/m a surface: 5e5 the pair
  config->contact.dissipation = 0.2;                       // s/m
  config->q0 = Eigen::VectorXd(model.nq());
  NeutralPositions(model, config->q0.data());  // each free body at its pose in the file
  config->qd0 = Eigen::VectorXd::Zero(model.nv());
  if (bounce) {
    config->q0(2) = 1.0;  // the ball's centre 0.9 m above the plane's contact
  } else {
    // The box resting on the plane (its static penetration m g / k = 2e-5 m) at 1 m/s.
    config->q0(2) = 0.1 - 9.81 / 5e5;
    config->qd0(0) = 1.0;
  }
  ValidateRun(model, *config);
  return model;
}

int Run(const Options& options) {
  const auto wall0 = std::chrono::steady_clock::now();
  const Model irb1600 = ImportUrdfFile(options.models_dir + "/irb1600.urdf").model;

  const std::vector<double> tolerances =
      options.quick ? std::vector<double>{1e-4, 1e-7}
                    : std::vector<double>{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10};
  const std::vector<double> steps =
      options.quick ? std::vector<double>{1e-2, 1e-3}
                    : std::vector<double>{1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5};

  // The contact scenes' fixed steps: their contact lasts milliseconds.
  const std::vector<double> contact_steps =
      options.quick ? std::vector<double>{1e-4, 1e-5}
                    : std::vector<double>{1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6};

  std::vector<Row> rows;
  for (const std::string& name : options.scenes) {
    const bool linkage = IsLinkage(name);
    const bool contact = IsContactScene(name);
    const std::vector<MethodVariant> methods = SelectedMethods(options, linkage, contact);
    Scene scene;
    scene.name = name;
    std::string path = options.models_dir + "/" + name + ".json";
    if (contact) {
      scene.track = Track::kBodyPosition;
      scene.model = ContactScene(name, &scene.config);
    } else if (linkage) {
      scene.track = Track::kJoints;
      SdfImport sdf = ImportSdfFile(options.linkages_dir + "/" + name + ".sdf");
      scene.model = std::move(sdf.model);
      scene.loops = std::move(sdf.loops);
      path = options.linkages_dir + "/" + name + "-passive.json";
    } else {
      scene.model = irb1600;
    }
    if (!contact) {
      std::vector<std::string> joints;
      for (const Body& body : scene.model.bodies) joints.push_back(body.joint.name);
      scene.config = ToRunConfig(LoadRunSpecFile(path), joints, path);
    }
    if (options.quick) scene.config.duration = kQuickDuration;
    if (options.duration > 0.0) scene.config.duration = options.duration;
    scene.config.max_steps = options.max_steps;
    bool all_prescribed = true;
    for (const DriveConfig& drive : scene.config.drives) {
      all_prescribed = all_prescribed && drive.kind == DriveConfig::Kind::kPrescribed;
    }
    scene.closed_form = all_prescribed;
    scene.window_end = scene.config.duration;

    if (scene.closed_form) {
      // Closed form: no method, no tolerance (the spec's want_torques as shipped).
      RunConfig config = scene.config;
      config.formulation = Formulation::kKinematic;
      rows.push_back(RunOne(scene, config, "none"));
      PrintRow(rows.back());
    } else {
      rows.push_back(ComputeReference(scene));
    }

    for (const MethodVariant& variant : methods) {
      RunConfig config = WithMethod(scene.config, variant);
      config.formulation = variant.formulation;
      if (variant.max_steps > 0) config.max_steps = std::min(config.max_steps, variant.max_steps);
      if (variant.fixed_step) {
        for (double step : contact ? contact_steps : steps) {
          const double needed = config.duration / step;
          if (needed > static_cast<double>(options.max_steps) * (1.0 + 1e-9)) {
            std::printf("%-13s %-9s %-10s step %.3g skipped: %.3g steps > %ld\n", name.c_str(),
                        FormulationName(variant.formulation), variant.label.c_str(), step, needed,
                        options.max_steps);
            continue;
          }
          config.fixed_step = step;
          Row row = RunOne(scene, config, variant.label);
          row.step = step;
          rows.push_back(row);
          PrintRow(row);
        }
      } else {
        // Once a tolerance runs out of steps, tighter ones would too: they are not run (nor
        // after a refusal).
        bool out_of_steps = false;
        for (double rtol : tolerances) {
          config.rtol = rtol;
          config.atol = rtol * 1e-2;
          Row row;
          if (out_of_steps) {
            row.scene = name;
            row.formulation = FormulationName(variant.formulation);
            row.method = variant.label;
            row.status = "SKIPPED";
          } else {
            row = RunOne(scene, config, variant.label);
            out_of_steps = row.status == "TOO_MUCH_WORK" || row.status == "REFUSED";
          }
          row.rtol = config.rtol;
          row.atol = config.atol;
          rows.push_back(row);
          PrintRow(row);
        }
      }
    }
    WriteCsv(options.out, rows);  // after each scene, so a long run leaves partial results
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  std::printf("%zu rows written to %s in %.1f s\n", rows.size(), options.out.c_str(), wall);
  return 0;
}

}  // namespace
}  // namespace mbstream

int main(int argc, char** argv) {
  mbstream::Options options;
  CLI::App app{
      "Work-precision study of the IRB 1600 scenes: error against CPU time for every "
      "formulation, method and tolerance; writes a CSV for scripts/plot_work_precision.py"};
  app.add_flag("--quick", options.quick,
               "a smoke run: 1 s of each scene, methods bdf and rk4 and the three body "
               "variants, two tolerances/steps");
  app.add_option("--out", options.out, "the CSV to write")->capture_default_str();
  app.add_option("--scenes", options.scenes, "scenes to run (comma-separated)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--methods", options.methods,
                 "methods to run (comma-separated; default all): bdf, adams, erk, erk-verner, "
                 "dirk, rk4, euler, ida (joint formulation; ida: the linkages' GGL DAE), "
                 "body-index3/ida, body-index2/ida, body-baumgarte/bdf (body coordinates)")
      ->delimiter(',');
  app.add_option("--duration", options.duration,
                 "simulated time of every scene (s); default: each scene's own (1 s with --quick)")
      ->check(CLI::PositiveNumber);
  app.add_option("--models-dir", options.models_dir,
                 "the folder of irb1600.urdf and the scenes' JSON files")
      ->capture_default_str();
  app.add_option("--linkages-dir", options.linkages_dir,
                 "the folder of the linkages' SDF and -passive.json files")
      ->capture_default_str();
  app.add_option("--max-steps", options.max_steps,
                 "internal step budget of a run; fixed steps needing more are skipped")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    return mbstream::Run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "work_precision: %s\n", e.what());
    return 1;
  }
}
