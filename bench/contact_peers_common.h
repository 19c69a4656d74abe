// What every engine of bench/contact_peers shares: the scenes' constants and closed forms, a
// run's row of the CSV, the measurements (the least-squares slope of a velocity, the apexes
// of a bounce) and the CPU clock. The scenes themselves: contact_peers.cc's header.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace mbstream::contact_peers {

constexpr double kG = 9.81;
inline const double kInclineTheta = 30.0 * M_PI / 180.0;
inline const double kRollingTheta = 20.0 * M_PI / 180.0;

struct Row {
  std::string scene, engine, setting;
  double error = 0.0;          // relative, against the closed form
  double cpu_per_sim_s = 0.0;  // s of CPU per s of simulated time
  std::string status = "FINISHED";
};

// The simulated time of a scene (s) and the interval of its samples (s).
inline double Duration(const std::string& scene) {
  return scene == "incline" ? 2.0 : scene == "rolling" ? 0.5 : 3.0;
}
inline double SampleInterval(const std::string& scene) { return scene == "bounce" ? 1e-3 : 0.01; }

inline double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// The median CPU time of three calls of `run`, which returns its measurement each time.
inline double MedianCpu(const std::function<void()>& run) {
  std::array<double, 3> cpu{};
  for (double& c : cpu) {
    const double t0 = CpuSeconds();
    run();
    c = CpuSeconds() - t0;
  }
  std::sort(cpu.begin(), cpu.end());
  return cpu[1];
}

// The apexes of a height track sampled every h (a local maximum's parabola vertex).
inline std::vector<double> Apexes(const std::vector<double>& z, double h) {
  std::vector<double> apexes;
  for (size_t k = 1; k + 1 < z.size(); ++k) {
    if (!(z[k] > z[k - 1] && z[k] >= z[k + 1])) continue;
    const double a = (z[k - 1] - 2 * z[k] + z[k + 1]) / (2 * h * h);
    const double b = (z[k + 1] - z[k - 1]) / (2 * h);
    apexes.push_back(z[k] - b * b / (4 * a));
  }
  return apexes;
}

// The largest |apex - 1 m| / 0.9 m of the first three bounces; 1 with fewer than three.
inline double BounceError(const std::vector<double>& z, double h) {
  const std::vector<double> apexes = Apexes(z, h);
  if (apexes.size() < 3) return 1.0;  // no bounce (or fewer than three): the whole height lost
  double worst = 0.0;
  for (size_t k = 0; k < 3; ++k) worst = std::max(worst, std::abs(apexes[k] - 1.0) / 0.9);
  return worst;
}

// Gravity turned by theta about y: the plane stays z = 0 and the body runs along +x.
inline Eigen::Vector3d TiltedGravity(double theta) {
  return {kG * std::sin(theta), 0.0, -kG * std::cos(theta)};
}

inline Eigen::Vector3d SceneGravity(const std::string& scene) {
  return scene == "incline"   ? TiltedGravity(kInclineTheta)
         : scene == "rolling" ? TiltedGravity(kRollingTheta)
                              : Eigen::Vector3d(0.0, 0.0, -kG);
}

// The least-squares slope of v(t) over the samples at t >= t_from: the acceleration,
// averaged over what the contact's vibration adds to it.
inline double Slope(const std::vector<double>& t, const std::vector<double>& v, double t_from) {
  double n = 0, st = 0, sv = 0, stt = 0, stv = 0;
  for (size_t k = 0; k < t.size(); ++k) {
    if (t[k] < t_from - 1e-12) continue;
    n += 1;
    st += t[k];
    sv += v[k];
    stt += t[k] * t[k];
    stv += t[k] * v[k];
  }
  return (n * stv - st * sv) / (n * stt - st * st);
}

// The acceleration along the incline of the incline and rolling scenes.
inline double ClosedForm(const std::string& scene) {
  if (scene == "incline") {
    return kG * (std::sin(kInclineTheta) - 0.3 * std::cos(kInclineTheta));
  }
  return 2.0 / 3.0 * kG * std::sin(kRollingTheta);  // rolling
}

// A scene's error from its samples (bounce: heights; the others: velocities along x at
// `times`); 1 (and status DIVERGED) when a sample is not finite.
inline void Measure(const std::string& scene, const std::vector<double>& times,
                    const std::vector<double>& samples, double sample_interval, Row* row) {
  bool finite = !samples.empty();
  for (double v : samples) finite = finite && std::isfinite(v);
  if (!finite) {
    row->status = "DIVERGED";
    row->error = 1.0;
  } else if (scene == "bounce") {
    row->error = BounceError(samples, sample_interval);
  } else {
    row->error = std::abs(Slope(times, samples, Duration(scene) / 2) / ClosedForm(scene) - 1.0);
  }
}

inline std::string Format(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

}  // namespace mbstream::contact_peers
