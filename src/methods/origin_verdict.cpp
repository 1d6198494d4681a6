#include "methods/origin_verdict.hpp"

#include <cmath>
#include <cstdio>

namespace stac {
namespace {

// The component of v largest in magnitude.
double largest(const Eigen::Vector3d& v) {
  Eigen::Index k = 0;
  v.cwiseAbs().maxCoeff(&k);
  return v[k];
}

}  // namespace

void checkJointOrigins(const SensorSet& sensors, const SensorParameters& theta,
                       std::vector<std::string>* why) {
  const OriginPrior& p = sensors.origin_prior;
  for (size_t c = 0; c < sensors.joint_origins.size(); ++c) {
    const JointOriginConfig& jc = sensors.joint_origins[c];
    const OriginCorrection& o = theta.joint_origin[c];
    struct Part {
      bool free;
      const Eigen::Vector3d& v;
      double prior, plain;
      const char* name;
      double unit;
      const char* unit_name;
    } parts[2] = {{!jc.fixed.xyz, o.xyz, p.xyz, kSuspectOriginXyz, "translation", 1e3, "mm"},
                  {!jc.fixed.rpy, o.rpy, p.rpy, kSuspectOriginRpy, "rotation", 180 / M_PI, "deg"}};
    for (const Part& part : parts) {
      if (!part.free) continue;
      const bool has_prior = part.prior > 0;
      const double limit = has_prior ? kSuspectOriginPriorStd * part.prior : part.plain;
      const double value = largest(part.v);
      if (std::abs(value) <= limit) continue;
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "the origin %s correction of %s (%.3g %s) is %s: a likely wrong minimum or "
                    "a wrong URDF",
                    part.name, jc.joint_name.c_str(), value * part.unit, part.unit_name,
                    has_prior ? "beyond 5 prior std" : "implausibly large for machining errors");
      why->push_back(buf);
    }
  }
}

}  // namespace stac
