#include "model/prediction_errors.hpp"

#include <cmath>
#include <vector>

#include "solve/parallel.hpp"

namespace stac {

void visitPredictionErrors(const MeasurementModel& model, const SensorParameters& theta,
                           const Observations& obs, const RowMatrix& q, int threads,
                           const PredictionErrorVisitor& visit) {
  const SensorSet& s = model.sensors();
  const int M = static_cast<int>(s.markers.size());
  const int J = static_cast<int>(s.joint_sensors.size());
  const int N = static_cast<int>(s.tendon_sensors.size());
  const int T = obs.num_frames;
  threads = resolveThreads(threads);
  std::vector<KinematicsWorkspace> kin(threads, KinematicsWorkspace(model.robot()));
  parallelFor(numChunks(T), threads, [&](int chunk, int tid) {
    Eigen::VectorXd qt(model.dof()), pm(3 * M), pj(J), pt(N);
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = q.row(t).transpose();
      predictFrame(model, theta, qt, &kin[tid], pm.data(), pj.data(), pt.data());
      for (int m = 0; m < M; ++m) {
        const double* x = obs.marker.row(t).data() + 3 * m;
        if (std::isnan(x[0])) continue;
        visit(chunk, t, SensorGroup::kMarker, m,
              (pm.segment<3>(3 * m) - Eigen::Vector3d(x[0], x[1], x[2])).norm());
      }
      for (int j = 0; j < J; ++j)
        if (!std::isnan(obs.joint(t, j)))
          visit(chunk, t, SensorGroup::kJoint, j, std::abs(pj[j] - obs.joint(t, j)));
      for (int k = 0; k < N; ++k)
        if (!std::isnan(obs.tendon(t, k)))
          visit(chunk, t, SensorGroup::kTendon, k, std::abs(pt[k] - obs.tendon(t, k)));
    }
  });
}

}  // namespace stac
