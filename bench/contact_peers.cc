// Contact side by side with MuJoCo 2.2.2 and DART 6.12 (issue 44, "Figures"; DART where CMake
// finds it, scripts/setup.sh --peers installs it): three scenes with closed
// forms, each engine at its defaults and at finer settings, the error against the closed
// form and the CPU time per simulated second, one CSV row per run:
//
//   build/bench/contact_peers --out docs/contact_peers.csv
//   /usr/bin/python3 scripts/plot_contact_peers.py --csv docs/contact_peers.csv --out docs
//
// Scenes (the incline is gravity turned by theta about y, so that the plane stays z = 0, in
// every engine):
//   incline  a 0.2 m box of 2 kg slides down a 30 degree incline, mu_d 0.3 (mbstream's
//            mu_s 0.4; MuJoCo and DART have one coefficient): a = g (sin 30 - 0.3 cos 30); measured
//            as the least-squares slope of the velocity along the incline over t in [1, 2] s
//            (sampled every 10 ms: the contact's vibration averages out).
//   rolling  a solid cylinder (r 0.1 m, 2 kg) rolls down 20 degrees, mu 0.8:
//            a = (2/3) g sin 20; measured likewise over [0.25, 0.5] s.
//   bounce   a 1 kg ball (r 0.1 m) dropped 0.9 m onto a plane, elastic: every apex at the
//            drop height; error the largest |apex - 1 m| / 0.9 m over 3 s (three bounces).
// Error: |measured / closed form - 1| (relative). Compliance is part of it: a soft contact
// rolls on a radius a little under r, and a default soft contact may not bounce at all.
//
// mbstream: the scenes of tests/data/contact/ with the run spec's defaults (k 1e5 N/m a
// surface, BDF; rtol 1e-6; the bounce with d = 0, the scene's elasticity) and tighter
// tolerances down to 1e-10; the incline and the rolling cylinder also with the rolling check's
// d = 20 s/m and v_s = 1e-3 m/s at k = 1e5, 1e6, 1e7 and 1e8 (stiffer surfaces: at 1e8 the
// rolling radius is r to 2e-6).
// MuJoCo: the same bodies in MJCF at its defaults (timestep 2 ms, Euler, solref 0.02 1, pyramidal
// cone) and at smaller timesteps; the bounce also with solref "-k 0" (stiffness k = 5e4 N/m,
// mbstream's pair, no damping: MuJoCo's elastic contact) at smaller timesteps. DART
// (contact_peers_dart.h: rigid LCP contact, restitution 1 for the bounce): its defaults (time step
// 1 ms, FCL with the shapes as meshes, the boxed LCP solver), 2 ms and smaller steps, and FCL's
// primitive shapes at the same steps. CPU: the median of three runs, this process's CPU clock.
#include <mujoco/mujoco.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/contact_peers_common.h"
#ifdef MBSTREAM_HAVE_DART
#include "bench/contact_peers_dart.h"
#endif
#include "server/engine/engine.h"
#include "server/parse/sdf_import.h"
#include "server/sim/run_validation.h"

namespace mbstream::contact_peers {
namespace {

// ---- mbstream ----

struct OurScene {
  Model model;
  RunConfig config;
};

// `damped`: the rolling check's surface (contact_scenes_test.cc), d = 20 s/m and v_s = 1e-3
// m/s, instead of the defaults (0.2 s/m, 1e-4 m/s); the bounce stays elastic.
OurScene Ours(const std::string& scene, double rtol, double stiffness, bool damped) {
  const std::string file = scene == "incline"   ? "box_on_plane.sdf"
                           : scene == "rolling" ? "cylinder_on_plane.sdf"
                                                : "ball_on_plane.sdf";
  OurScene s;
  s.model = ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/contact/" + file).model;
  RunConfig& c = s.config;
  c.formulation = Formulation::kJoint;
  c.want_torques = false;
  c.rtol = rtol;
  c.atol = rtol * 1e-2;
  c.max_steps = 5'000'000;
  c.contact.stiffness = stiffness;
  c.drives.resize(static_cast<size_t>(s.model.nv()));
  if (scene == "incline") {
    c.duration = 2.0;
    c.output_interval = 0.01;
    c.gravity = TiltedGravity(kInclineTheta);
    c.contact.mu_static = 0.4;
    c.contact.mu_dynamic = 0.3;
  } else if (scene == "rolling") {
    c.duration = 0.5;
    c.output_interval = 0.01;
    c.gravity = TiltedGravity(kRollingTheta);
    c.contact.mu_static = 0.8;
    c.contact.mu_dynamic = 0.8;
  } else {
    c.duration = 3.0;
    c.output_interval = 1e-3;
    c.contact.dissipation = 0.0;  // the scene is elastic
  }
  if (damped && scene != "bounce") {
    c.contact.stiction_tolerance = 1e-3;
    c.contact.dissipation = 20.0;
  }
  ValidateRun(s.model, c);
  return s;
}

Row RunOurs(const std::string& scene, double rtol, double stiffness, bool damped,
            const std::string& setting) {
  const OurScene s = Ours(scene, rtol, stiffness, damped);
  RunResult result;
  Row row{scene, "mbstream", setting};
  row.cpu_per_sim_s = MedianCpu([&] { result = Simulate(s.model, s.config); }) / s.config.duration;
  if (result.stats.status != RunStatus::kFinished) {
    row.status = RunStatusName(result.stats.status);
    row.error = 1.0;
    return row;
  }
  if (scene == "bounce") {
    std::vector<double> z;
    const size_t nq = static_cast<size_t>(result.num_positions);
    for (size_t k = 0; k < result.t.size(); ++k) z.push_back(result.q[k * nq + 2]);
    row.error = BounceError(z, s.config.output_interval);
  } else {
    std::vector<double> vx;
    const size_t nv = static_cast<size_t>(result.num_dofs);
    for (size_t k = 0; k < result.t.size(); ++k) vx.push_back(result.qd[k * nv]);
    const double a = Slope(result.t, vx, s.config.duration / 2);
    row.error = std::abs(a / ClosedForm(scene) - 1.0);
  }
  return row;
}

// ---- MuJoCo ----

// The scene in MJCF: the same bodies, masses and inertias as tests/data/contact/.
std::string Mjcf(const std::string& scene, double timestep, const std::string& solref) {
  const Eigen::Vector3d g = scene == "incline"   ? TiltedGravity(kInclineTheta)
                            : scene == "rolling" ? TiltedGravity(kRollingTheta)
                                                 : Eigen::Vector3d(0.0, 0.0, -kG);
  char option[256];
  std::snprintf(option, sizeof(option),
                "<option timestep=\"%.17g\" gravity=\"%.17g %.17g %.17g\"/>", timestep, g.x(),
                g.y(), g.z());
  const std::string ref = solref.empty() ? "" : " solref=\"" + solref + "\"";
  // MuJoCo combines two geoms' friction by the larger: the plane gets the body's (its
  // default, 1, would hold the box on the incline).
  const std::string friction = scene == "incline" ? "0.3" : scene == "rolling" ? "0.8" : "1";
  std::string body;
  if (scene == "incline") {
    body =
        "<body pos=\"0 0 0.1\"><freejoint/><geom type=\"box\" size=\"0.1 0.1 0.1\" "
        "friction=\"0.3 0.005 0.0001\"" +
        ref +
        "/><inertial pos=\"0 0 0\" mass=\"2\" diaginertia=\"0.013333333333333334 "
        "0.013333333333333334 0.013333333333333334\"/></body>";
  } else if (scene == "rolling") {
    body =
        "<body pos=\"0 0 0.1\" euler=\"90 0 0\"><freejoint/><geom type=\"cylinder\" "
        "size=\"0.1 0.1\" friction=\"0.8 0.005 0.0001\"" +
        ref +
        "/><inertial pos=\"0 0 0\" mass=\"2\" diaginertia=\"0.011666666666666667 "
        "0.011666666666666667 0.010000000000000002\"/></body>";
  } else {
    body = "<body pos=\"0 0 1\"><freejoint/><geom type=\"sphere\" size=\"0.1\"" + ref +
           "/><inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"0.004 0.004 0.004\"/></body>";
  }
  return "<mujoco model=\"" + scene + "\"><compiler angle=\"degree\"/>" + option +
         "<worldbody><geom type=\"plane\" size=\"10 10 0.1\" friction=\"" + friction +
         " 0.005 0.0001\"" + ref + "/>" + body + "</worldbody></mujoco>";
}

Row RunMujoco(const std::string& scene, double timestep, const std::string& solref,
              const std::string& setting) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("mbstream_contact_peers_" + scene + ".xml");
  std::ofstream(path) << Mjcf(scene, timestep, solref);
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  std::filesystem::remove(path);
  if (m == nullptr) throw std::runtime_error("MuJoCo refused the " + scene + " scene: " + error);
  mjData* d = mj_makeData(m);
  const double duration = Duration(scene);
  const double sample = SampleInterval(scene);  // s between samples
  const long steps = std::lround(duration / timestep);
  const long every = std::max(1L, std::lround(sample / timestep));
  std::vector<double> samples, times;  // bounce: z; others: vx
  auto run = [&] {
    mj_resetData(m, d);
    samples.clear();
    times.clear();
    for (long k = 1; k <= steps; ++k) {
      mj_step(m, d);
      if (k % every == 0) {
        samples.push_back(scene == "bounce" ? d->qpos[2] : d->qvel[0]);
        times.push_back(d->time);
      }
    }
  };
  Row row{scene, "mujoco", setting};
  row.cpu_per_sim_s = MedianCpu(run) / duration;
  Measure(scene, times, samples, static_cast<double>(every) * timestep, &row);
  mj_deleteData(d);
  mj_deleteModel(m);
  return row;
}

int Run(const std::string& out, bool quick) {
  const std::vector<double> rtols =
      quick ? std::vector<double>{1e-6} : std::vector<double>{1e-4, 1e-6, 1e-8, 1e-10};
  const std::vector<double> timesteps =
      quick ? std::vector<double>{2e-3} : std::vector<double>{2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5};
#ifdef MBSTREAM_HAVE_DART
  const std::vector<double> dart_timesteps =
      quick ? std::vector<double>{1e-3} : std::vector<double>{2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5};
#endif
  std::vector<Row> rows;
  auto add = [&](Row row) {
    std::printf("%-8s %-9s %-28s error %-10.3g cpu/sim-s %-10.4g %s\n", row.scene.c_str(),
                row.engine.c_str(), row.setting.c_str(), row.error, row.cpu_per_sim_s,
                row.status.c_str());
    std::fflush(stdout);
    rows.push_back(std::move(row));
  };
  for (const std::string scene : {"incline", "rolling", "bounce"}) {
    for (double rtol : rtols) {
      add(RunOurs(scene, rtol, 1e5, false,
                  "k 1e5; rtol " + Format(rtol) + (rtol == 1e-6 ? " (default)" : "")));
    }
    if (scene != std::string("bounce")) {  // damped, stiffer surfaces: less compliance
      for (int e : quick ? std::vector<int>{8} : std::vector<int>{5, 6, 7, 8}) {
        for (double rtol : rtols) {
          add(RunOurs(scene, rtol, std::pow(10.0, e), true,
                      "k 1e" + std::to_string(e) + " d 20; rtol " + Format(rtol)));
        }
      }
    }
    for (double h : timesteps) {
      add(RunMujoco(scene, h, "", "dt " + Format(h) + (h == 2e-3 ? " (default)" : "")));
    }
    if (scene == std::string("bounce")) {  // MuJoCo's elastic contact: stiffness, no damping
      for (double h : timesteps)
        add(RunMujoco(scene, h, "-50000 0", "solref -5e4 0; dt " + Format(h)));
    }
#ifdef MBSTREAM_HAVE_DART
    for (const bool primitives :
         quick ? std::vector<bool>{false} : std::vector<bool>{false, true}) {
      for (double h : dart_timesteps) {
        add(RunDart(scene, DartSetting{h, primitives},
                    std::string(primitives ? "fcl primitive; " : "fcl mesh; ") + "dt " + Format(h) +
                        (h == 1e-3 && !primitives ? " (default)" : "")));
      }
    }
#endif
  }
  std::FILE* file = std::fopen(out.c_str(), "w");
  if (file == nullptr) throw std::runtime_error("cannot write " + out);
  std::fprintf(file, "scene,engine,setting,error,cpu_per_sim_s,status\n");
  for (const Row& r : rows) {
    std::fprintf(file, "%s,%s,%s,%.6e,%.6e,%s\n", r.scene.c_str(), r.engine.c_str(),
                 r.setting.c_str(), r.error, r.cpu_per_sim_s, r.status.c_str());
  }
  if (std::fclose(file) != 0) throw std::runtime_error("cannot write " + out);
  std::printf("%zu rows written to %s\n", rows.size(), out.c_str());
  return 0;
}

}  // namespace
}  // namespace mbstream::contact_peers

int main(int argc, char** argv) {
  std::string out = "contact_peers.csv";
  bool quick = false;
  CLI::App app{
      "Contact side by side with MuJoCo (and DART): the incline, the rolling cylinder and the "
      "bounce"};
  app.add_option("--out", out, "the CSV to write")->capture_default_str();
  app.add_flag("--quick", quick, "each engine at its default only");
  CLI11_PARSE(app, argc, argv);
  try {
    return mbstream::contact_peers::Run(out, quick);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "contact_peers: %s\n", e.what());
    return 1;
  }
}
