#include "model/frame_jacobian.hpp"

namespace stac {

void denseFrame(const MeasurementModel& model, const FrameWorkspace& ws,
                const std::vector<bool>* skip_joint, DenseFrame* out) {
  auto skipped = [&](const ReadingJacobian& rj) {
    return skip_joint && rj.group == SensorGroup::kJoint && (*skip_joint)[rj.sensor];
  };
  int rows = 0;
  for (int i = 0; i < ws.count; ++i)
    if (!skipped(ws.readings[i])) rows += ws.readings[i].rows;
  out->rows = rows;
  out->r.resize(rows);
  out->Jtheta.setZero(rows, model.thetaSpace().size());
  out->Jq.setZero(rows, model.dof());
  int row = 0;
  for (int i = 0; i < ws.count; ++i) {
    const ReadingJacobian& rj = ws.readings[i];
    if (skipped(rj)) continue;
    out->r.segment(row, rj.rows) = rj.r.head(rj.rows);
    const std::vector<int>& cols = *rj.q_cols;
    for (size_t c = 0; c < cols.size(); ++c)
      out->Jq.block(row, cols[c], rj.rows, 1) = rj.Jq.block(0, c, rj.rows, 1);
    for (int b = 0; b < rj.theta_count; ++b)
      out->Jtheta.block(row, rj.theta_index[b], rj.rows, 1) = rj.Jtheta.block(0, b, rj.rows, 1);
    row += rj.rows;
  }
}

}  // namespace stac
