// The spike screen (solve/spike_screen.hpp): in a log of smooth motion it
// sets aside exactly the gross readings, whole markers at a time; it leaves
// a log of independent postures and quantised encoders alone; and
// calibrate() applies it under a robust loss only, reporting the count.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "solve/spike_screen.hpp"
#include "stac/calibrate.hpp"
#include "support/arm_fixture.hpp"

namespace stac {
namespace {

constexpr double kSigma = 0.01;

// A smooth swing sampled at 100 Hz with noise σ, and 5% of its readings
// moved by 50-200 σ; returns the moved frames.
std::set<int> smoothWithSpikes(int n, unsigned seed, Eigen::VectorXd* x) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, kSigma);
  std::uniform_real_distribution<double> u(0, 1);
  x->resize(n);
  std::set<int> spikes;
  for (int t = 0; t < n; ++t) {
    const double s = t / 100.0;
    (*x)[t] = 1.2 * std::sin(1.3 * s) + 0.4 * std::sin(3.1 * s + 1) + noise(rng);
    if (u(rng) < 0.05) {
      (*x)[t] += (u(rng) < 0.5 ? -1 : 1) * (50 + 150 * u(rng)) * kSigma;
      spikes.insert(t);
    }
  }
  return spikes;
}

std::set<int> flagged(const std::vector<bool>& spike) {
  std::set<int> out;
  for (size_t t = 0; t < spike.size(); ++t)
    if (spike[t]) out.insert(static_cast<int>(t));
  return out;
}

TEST(SpikeScreen, FindsExactlyTheGrossReadingsOfASmoothLog) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    Eigen::VectorXd x;
    const std::set<int> spikes = smoothWithSpikes(600, seed, &x);
    ASSERT_GT(spikes.size(), 15u);
    EXPECT_EQ(flagged(columnSpikes(x, kSigma)), spikes) << "seed " << seed;
  }
}

TEST(SpikeScreen, MissingReadingsAreNeitherFlaggedNorInTheWay) {
  Eigen::VectorXd x;
  std::set<int> spikes = smoothWithSpikes(600, 7, &x);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0, 1);
  for (int t = 0; t < x.size(); ++t)
    if (u(rng) < 0.3) x[t] = std::nan(""), spikes.erase(t);
  const std::vector<bool> spike = columnSpikes(x, kSigma);
  for (int t = 0; t < x.size(); ++t)
    if (std::isnan(x[t])) {
      EXPECT_FALSE(spike[t]) << t;
    }
  // A spike whose neighbours are mostly missing has no verdict; the rest are
  // found, and nothing else is.
  const std::set<int> found = flagged(spike);
  for (int t : found) EXPECT_TRUE(spikes.count(t)) << t;
  EXPECT_GE(found.size(), spikes.size() * 8 / 10);
}

TEST(SpikeScreen, LeavesALogOfIndependentPosturesAlone) {
  // Static postures in random order: no reading predicts its neighbours,
  // so even a reading far out is a posture, not a spike.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  Eigen::VectorXd x(300);
  for (int t = 0; t < x.size(); ++t) x[t] = u(rng);
  x[100] = 9.0;
  EXPECT_TRUE(flagged(columnSpikes(x, kSigma)).empty());
}

TEST(SpikeScreen, AStillSensorsSpikesAreFoundAndItsTicksAreNot) {
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0, kSigma);
  Eigen::VectorXd still(400), ticks(400);
  for (int t = 0; t < still.size(); ++t) {
    still[t] = 0.3 + noise(rng);
    // A quantised encoder creeping by one tick (σ) every 7 frames.
    ticks[t] = kSigma * std::floor(t / 7.0);
  }
  still[50] += 60 * kSigma;
  still[51] -= 80 * kSigma;  // two neighbours: the median of four still holds
  EXPECT_EQ(flagged(columnSpikes(still, kSigma)), (std::set<int>{50, 51}));
  EXPECT_TRUE(flagged(columnSpikes(ticks, kSigma)).empty());
}

// 20 frames of a fast swing dropped mid-log: by index the motion jumps
// there (4 good readings flagged); the log's time says how far apart the
// frames around the gap are.
TEST(SpikeScreen, AGapInTimeIsNoSpikeWhereTheLogHasTimes) {
  std::mt19937 rng(12);
  std::normal_distribution<double> noise(0, kSigma);
  Eigen::VectorXd x(600);
  std::vector<double> time;
  for (int t = 0, k = 0; t < 620; ++t) {
    if (t >= 300 && t < 320) continue;
    const double s = t / 100.0;
    x[k++] = 1.2 * std::sin(3.9 * s) + 0.4 * std::sin(9.3 * s + 1) + noise(rng);
    time.push_back(s);
  }
  EXPECT_FALSE(flagged(columnSpikes(x, kSigma)).empty());  // by index: the gap
  EXPECT_TRUE(flagged(columnSpikes(x, kSigma, framePositions(time, 600))).empty());
}

TEST(SpikeScreen, TooShortALogIsLeftAlone) {
  Eigen::VectorXd x;
  smoothWithSpikes(600, 1, &x);
  const Eigen::VectorXd head = x.head(kMinScreenedFrames - 1);
  EXPECT_TRUE(flagged(columnSpikes(head, kSigma)).empty());
}

// The arm (300 frames at 100 Hz, fast swings: the distal markers' noise is
// no longer the neighbours' main disagreement) with 5% gross readings of
// every kind, 20-60 σ and 5-20 cm: the screen sets aside nearly all of them
// and nearly nothing else, a marker's three coordinates at once.
TEST(SpikeScreen, SetsAsideTheArmsGrossReadingsPerGroup) {
  test::ArmProblem p = test::makeArmProblem(300, 5);
  const Observations clean = p.obs;
  const auto injected = test::addOutliers(p.sensors, 0.05, 9, &p.obs);
  int markers = 0;  // injected marker readings
  for (const auto& injection : injected)
    for (const auto& m : p.sensors.markers) markers += m.name == injection.second;
  const SpikeScreen s = screenSpikes(p.obs, NoiseModel::fromSeeds(p.sensors));
  // Every reading set aside was injected, and every injected one is set
  // aside: the kept log equals the clean one but for NaN where injected.
  int kept_gross = 0, lost_good = 0;
  auto compare = [&](const RowMatrix& kept, const RowMatrix& was, const RowMatrix& gross) {
    for (int t = 0; t < kept.rows(); ++t)
      for (int c = 0; c < kept.cols(); ++c) {
        if (std::isnan(was(t, c))) continue;
        const bool moved = gross(t, c) != was(t, c);
        if (std::isnan(kept(t, c))) lost_good += !moved;
        else kept_gross += moved;
      }
  };
  compare(s.kept.marker, clean.marker, p.obs.marker);
  compare(s.kept.joint, clean.joint, p.obs.joint);
  compare(s.kept.tendon, clean.tendon, p.obs.tendon);
  // Counted per column: a marker reading is 3. Of 151 gross readings and
  // 5,700 good ones (columns); measured: 5 gross kept, 3 good lost.
  EXPECT_LE(kept_gross, 9);
  EXPECT_LE(lost_good, 6);
  EXPECT_NEAR(s.set_aside[0] + s.set_aside[1] + s.set_aside[2],
              static_cast<double>(injected.size()), 5);
  EXPECT_NEAR(s.set_aside[0], markers, 2);
}

TEST(SpikeScreen, CalibrateScreensUnderARobustLossOnly) {
  test::ArmProblem p = test::makeArmProblem(300, 5);
  const auto injected = test::addOutliers(p.sensors, 0.05, 9, &p.obs);
  CalibrationOptions o;
  o.threads = 1;
  auto total = [](const CalibrationResult& r) {
    const int* s = r.summary.spikes_set_aside;
    return s[0] + s[1] + s[2];
  };
  const CalibrationResult plain = calibrate(p.robot, p.sensors, p.seed, p.obs, o);
  EXPECT_EQ(total(plain), 0);
  o.loss = LossKind::kHuber;
  const CalibrationResult huber = calibrate(p.robot, p.sensors, p.seed, p.obs, o);
  const SpikeScreen screen = screenSpikes(p.obs, NoiseModel::fromSeeds(p.sensors));
  const int* screened = screen.set_aside;
  EXPECT_EQ(total(huber), screened[0] + screened[1] + screened[2]);
  EXPECT_GT(total(huber), static_cast<int>(injected.size()) * 9 / 10);
  o.screen_spikes = false;
  EXPECT_EQ(total(calibrate(p.robot, p.sensors, p.seed, p.obs, o)), 0);
}

}  // namespace
}  // namespace stac

namespace stac {
namespace {

// Without a robust loss the gross readings make a group misfit; the
// verdict's reason counts those the screen would set aside and names the
// loss that does.
TEST(SpikeScreen, AMisfitWithoutALossCountsTheSpikesAndNamesHuber) {
  test::ArmProblem p = test::makeArmProblem(300, 5);
  test::addOutliers(p.sensors, 0.05, 9, &p.obs);
  CalibrationOptions o;
  o.threads = 1;
  const CalibrationResult r = calibrate(p.robot, p.sensors, p.seed, p.obs, o);
  ASSERT_TRUE(r.summary.suspect());
  const SpikeScreen screen = screenSpikes(p.obs, NoiseModel::fromSeeds(p.sensors));
  const int* spikes = screen.set_aside;
  int named = 0;
  for (const std::string& reason : r.summary.verdict)
    for (int g = 0; g < kNumSensorGroups; ++g)
      named += reason.find(std::to_string(spikes[g]) +
                           " of them stand out of their neighbours in time as gross readings, "
                           "which --loss huber sets aside") != std::string::npos;
  EXPECT_GE(named, 1) << r.summary.verdict[0];
}

}  // namespace
}  // namespace stac
