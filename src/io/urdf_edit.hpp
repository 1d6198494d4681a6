// Writing joint origins into a URDF text in place.
//
// A DOM round trip would lose comments, attribute order, quoting and number
// formatting, and users diff their URDFs. So the new values go exactly where
// the UrdfDocument recorded the old ones, and every other byte is kept.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "io/urdf_document.hpp"

namespace stac::io {

// New values for one joint's <origin>; a component left empty is kept.
struct OriginEdit {
  std::string joint;
  std::optional<Eigen::Vector3d> xyz, rpy;  // metres; radians, URDF convention
};

// The document's text with those joints' <origin> attributes replaced: a
// missing attribute is added to the <origin>, a missing <origin> is inserted
// as the joint's first child (on its own line, indented like the next child,
// when the joint's children are on their own lines). Throws
// std::invalid_argument for a joint the document does not have or one
// edited twice.
std::string withJointOrigins(const UrdfDocument& doc, const std::vector<OriginEdit>& edits);

// Fewest digits that read back as exactly v; "0" for ±0.
std::string formatCoordinate(double v);

}  // namespace stac::io
