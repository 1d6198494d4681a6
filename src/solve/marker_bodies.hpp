// Virtual points of one tracked rigid body. A mocap system that tracks a
// rigid body (Qualisys, Vicon, OptiTrack) can export points of it computed
// from the one 6-DoF pose it measured: their mutual distances are constant
// to far below any marker noise (under 0.1 µm on the real TIAGo recording,
// where the noise of one physical marker moves a distance by 10 µm or
// more), and their errors are that pose's error. k such points give 3k rows
// a frame but at most 6 independent error dims (5 for points on a line).
//
// The variance adaptation counts the dof the q_t take from those rows
// (their leverage, at most 6) against 3k rows: as if the rows were
// independent, 3k - 6 would be left, where in truth the q_t can take the
// whole pose error (TIAGo: 8 joints for the hand's 6). The marker σ then
// shrank to a third of the residual the points can show, the joint σ grew
// 4x, the pots' readings counted for little, and the held-out error rose
// from 2.5 mm with one point to 4.1 mm with four.
#pragma once

#include <vector>

#include "stac/log.hpp"
#include "stac/sensors.hpp"

namespace stac {

struct MarkerBodies {
  std::vector<int> body_of_marker;  // per marker: its body, or -1
  std::vector<int> rank;            // per body: its points' independent error dims
  std::vector<int> size;            // per body: its points

  bool empty() const { return rank.empty(); }
  // How many rows of `present` of body b's points carry one independent
  // error dim (1 for a lone point).
  double rowsPerDim(int b, int present) const;
};

// The bodies of virtual points among the markers: two markers of one link
// belong to one body when, over the at least kBodyFrames frames that read
// both, their distance varies by less than kBodyTolerance metres (standard
// deviation); a body is closed under that relation.
constexpr int kBodyFrames = 3;
constexpr double kBodyTolerance = 1e-6;
MarkerBodies findMarkerBodies(const SensorSet& sensors, const Observations& obs);

}  // namespace stac
