#include "solve/marker_bodies.hpp"

#include <cmath>
#include <numeric>

#include <Eigen/SVD>

namespace stac {
namespace {

bool present(const Observations& obs, int t, int m) { return !std::isnan(obs.marker(t, 3 * m)); }

Eigen::Vector3d point(const Observations& obs, int t, int m) {
  return obs.marker.block<1, 3>(t, 3 * m).transpose();
}

// Whether markers a and b keep their distance to kBodyTolerance over the
// frames that read both (Welford's running variance).
bool rigidPair(const Observations& obs, int a, int b) {
  int n = 0;
  double mean = 0, m2 = 0;
  for (int t = 0; t < obs.num_frames; ++t) {
    if (!present(obs, t, a) || !present(obs, t, b)) continue;
    const double d = (point(obs, t, a) - point(obs, t, b)).norm();
    ++n;
    const double delta = d - mean;
    mean += delta / n;
    m2 += delta * (d - mean);
  }
  return n >= kBodyFrames && std::sqrt(m2 / n) < kBodyTolerance;
}

int root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// 5 for points on a line (a rotation about it moves none), else 6; from
// the frame that reads most of them.
int bodyRank(const Observations& obs, const std::vector<int>& markers) {
  int best_t = -1, best = 0;
  for (int t = 0; t < obs.num_frames && best < static_cast<int>(markers.size()); ++t) {
    int n = 0;
    for (int m : markers) n += present(obs, t, m);
    if (n > best) best = n, best_t = t;
  }
  if (best < 3) return 5;
  Eigen::Matrix3Xd p(3, best);
  int c = 0;
  for (int m : markers)
    if (present(obs, best_t, m)) p.col(c++) = point(obs, best_t, m);
  p.colwise() -= p.rowwise().mean();
  const Eigen::Vector3d s = Eigen::JacobiSVD<Eigen::Matrix3Xd>(p).singularValues();
  return s[1] > 1e-6 * s[0] ? 6 : 5;
}

}  // namespace

double MarkerBodies::rowsPerDim(int b, int present) const {
  if (present <= 1) return 1.0;
  const int dims = present == 2 ? 5 : rank[b];
  return 3.0 * present / dims;
}

MarkerBodies findMarkerBodies(const SensorSet& sensors, const Observations& obs) {
  const int n = static_cast<int>(sensors.markers.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      if (sensors.markers[a].link_name == sensors.markers[b].link_name && rigidPair(obs, a, b))
        parent[root(parent, b)] = root(parent, a);
  MarkerBodies out;
  out.body_of_marker.assign(n, -1);
  std::vector<int> body_of_root(n, -1);
  std::vector<std::vector<int>> members;
  for (int m = 0; m < n; ++m) {
    const int r = root(parent, m);
    if (body_of_root[r] < 0) {
      body_of_root[r] = static_cast<int>(members.size());
      members.emplace_back();
    }
    members[body_of_root[r]].push_back(m);
  }
  for (const std::vector<int>& body : members) {
    if (body.size() < 2) continue;
    const int b = static_cast<int>(out.rank.size());
    for (int m : body) out.body_of_marker[m] = b;
    out.rank.push_back(bodyRank(obs, body));
    out.size.push_back(static_cast<int>(body.size()));
  }
  return out;
}

}  // namespace stac
