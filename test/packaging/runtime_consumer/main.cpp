// The sensor maps as robot-side code uses them, in float and double, each
// forward map checked against its inverse and against hand-computed values.
#include <cmath>
#include <cstdio>

#include "stac/runtime/sensor_maps.hpp"

namespace rt = stac::runtime;

static int failures = 0;
static void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "FAILED: %s\n", what);
    ++failures;
  }
}

int main() {
  // Joint sensor: p = gain q + bias and back.
  const double q = 0.7, gain = -1.5, bias = 0.4;
  const double p = rt::jointReading(q, gain, bias);
  check(std::abs(p - (-0.65)) < 1e-15, "jointReading");
  check(std::abs(rt::jointAngle(p, gain, bias) - q) < 1e-15, "jointAngle");
  const rt::LinearSensor<float> pot = {2.0f, -0.5f};
  check(std::abs(pot.value(pot.reading(0.25f)) - 0.25f) < 1e-6f, "LinearSensor<float>");

  // Tendon coupling: L = Σ c_j q_j, p = gain L + bias.
  const Eigen::Vector2d c(0.009, 0.012), qc(0.5, -0.25);
  const double L = rt::couplingLength(c, qc);
  check(std::abs(L - 0.0015) < 1e-15, "couplingLength");
  const double cs[2] = {0.009, 0.012}, qs[2] = {0.5, -0.25};
  check(std::abs(rt::couplingLength(cs, qs, 2) - L) < 1e-15, "couplingLength(arrays)");
  check(std::abs(rt::tendonLength(rt::tendonReading(L, 30.0, -1.0), 30.0, -1.0) - L) < 1e-15,
        "tendonLength");

  // Path: 3-4-5 then 12 more along z.
  const Eigen::Vector3d pts[3] = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, 4, 0),
                                  Eigen::Vector3d(3, 4, 12)};
  check(std::abs(rt::pathLength(pts, 3) - 17.0) < 1e-12, "pathLength");
  Eigen::Matrix<double, 3, 3> cols;
  cols << 0, 3, 3, 0, 4, 4, 0, 0, 12;
  check(std::abs(rt::pathLength(cols) - 17.0) < 1e-12, "pathLength(matrix)");

  // Marker: x = R (T d) + t and back.
  rt::MocapFrame<double> frame = {
      Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(0.1, 0.2, 0.3)};
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(Eigen::Vector3d(0, 0, 1));
  const Eigen::Vector3d d(1, 0, 0);
  const Eigen::Vector3d x = rt::markerPosition(frame, T, d);
  check((x - Eigen::Vector3d(0.1 + std::cos(0.5), 0.2 + std::sin(0.5), 1.3)).norm() < 1e-12,
        "markerPosition");
  check((rt::markerInLink(frame, T, x) - d).norm() < 1e-12, "markerInLink");

  if (failures) return 1;
  std::printf("stac::runtime consumer: all maps agree\n");
  return 0;
}
