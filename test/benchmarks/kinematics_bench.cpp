// Issue 2's figure: time per frame of "all link poses + the point Jacobians
// of 24 markers" on humanoid38, our one-pass sweep against the naive way
// (one KDL chain FK + one KDL chain Jacobian per marker).
//   build/test/kinematics_bench [--benchmark_repetitions=9]
#include <benchmark/benchmark.h>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <memory>
#include <random>

#include "stac/kinematics.hpp"
#include "stac/robot_model.hpp"
#include "support/test_util.hpp"

namespace {

using namespace stac;

struct Fixture {
  RobotModel robot = RobotModel::fromFile(test::dataPath("humanoid38.urdf"));
  std::vector<int> marker_links;  // 24 links spread over the tree
  Eigen::VectorXd q;
  Fixture() {
    std::mt19937 rng(1);
    q = test::randomQ(robot, rng);
    // Every other link that has a movable joint, counting from the base.
    int k = 0;
    for (int l = 1; l < robot.numLinks() && marker_links.size() < 24; ++l)
      if (robot.links()[l].movable_joint >= 0 && (k++ % 2 == 1)) marker_links.push_back(l);
    for (int l = robot.numLinks() - 1; marker_links.size() < 24 && l > 0; --l)
      marker_links.push_back(l);
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void BM_OnePassSweep(benchmark::State& state) {
  Fixture& f = fixture();
  KinematicsWorkspace ws(f.robot);
  Eigen::MatrixXd J(3, f.robot.dof());
  const Eigen::Vector3d d(0.02, 0.01, 0.03);
  for (auto _ : state) {
    forwardKinematics(f.robot, f.q, &ws);
    for (int l : f.marker_links) {
      pointJacobian(f.robot, ws, l, ws.link_pose[l] * d, J);
      benchmark::DoNotOptimize(J.data());
    }
  }
}
BENCHMARK(BM_OnePassSweep);

void BM_NaiveKdlChains(benchmark::State& state) {
  Fixture& f = fixture();
  const KDL::Tree& tree = f.robot.kdlTree();
  const std::string root = f.robot.links()[0].name;
  struct PerMarker {
    KDL::Chain chain;
    std::unique_ptr<KDL::ChainFkSolverPos_recursive> fk;
    std::unique_ptr<KDL::ChainJntToJacSolver> jac;
    KDL::JntArray q;
    KDL::Jacobian J;
  };
  std::vector<PerMarker> markers(f.marker_links.size());
  KinematicsWorkspace ws(f.robot);
  f.robot.expand(f.q, &ws.movable_q);
  for (size_t i = 0; i < markers.size(); ++i) {
    PerMarker& m = markers[i];
    tree.getChain(root, f.robot.links()[f.marker_links[i]].name, m.chain);
    m.fk = std::make_unique<KDL::ChainFkSolverPos_recursive>(m.chain);
    m.jac = std::make_unique<KDL::ChainJntToJacSolver>(m.chain);
    m.q.resize(m.chain.getNrOfJoints());
    m.J.resize(m.chain.getNrOfJoints());
    int k = 0;
    for (const KDL::Segment& s : m.chain.segments)
      if (s.getJoint().getType() != KDL::Joint::Fixed)
        m.q(k++) = ws.movable_q[*f.robot.movableJointIndex(s.getJoint().getName())];
  }
  KDL::Frame F;
  for (auto _ : state) {
    for (PerMarker& m : markers) {
      m.fk->JntToCart(m.q, F);
      m.jac->JntToJac(m.q, m.J);
      m.J.changeRefPoint(F.M * KDL::Vector(0.02, 0.01, 0.03));
      benchmark::DoNotOptimize(m.J.data.data());
    }
  }
}
BENCHMARK(BM_NaiveKdlChains);

}  // namespace

BENCHMARK_MAIN();
