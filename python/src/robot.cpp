// stac.RobotModel: the library's immutable RobotModel, loaded from URDF.
#include <pybind11/stl.h>

#include "bindings.hpp"

namespace stac::python {

namespace {
std::vector<std::string> jointNames(const RobotModel& r) {
  std::vector<std::string> names;
  for (int i = 0; i < r.dof(); ++i) names.push_back(r.qName(i));
  return names;
}

std::vector<std::string> linkNames(const RobotModel& r) {
  std::vector<std::string> names;
  for (const Link& l : r.links()) names.push_back(l.name);
  return names;
}
}  // namespace

void bindRobot(py::module_& m) {
  py::class_<RobotModel, std::shared_ptr<RobotModel>>(
      m, "RobotModel",
      "A robot's kinematics from a URDF (SPEC §1), never changed once loaded.\n\n"
      "q, the joint vector, holds every revolute, continuous and prismatic joint that is "
      "not a mimic follower, in the order the joints appear in the URDF.")
      .def_static(
          "from_urdf", [](const Path& path) { return RobotModel::fromFile(path.string()); },
          py::arg("path"),
                  "Loads a URDF file. Raises InputError naming the file and the problem.")
      .def_static("from_urdf_string", &RobotModel::fromString, py::arg("urdf"),
                  py::arg("source") = "<string>",
                  "Loads URDF text; `source` names it in errors.")
      .def_property_readonly("name", &RobotModel::name, "The URDF's robot name.")
      .def_property_readonly("source", &RobotModel::sourceName,
                             "The file (or source name) it was loaded from.")
      .def_property_readonly("dof", &RobotModel::dof, "Length of q.")
      .def_property_readonly("joint_names", &jointNames, "The joints of q, in q order.")
      .def_property_readonly("link_names", &linkNames, "Every link, parents before children.")
      .def_property_readonly(
          "lower_limits", [](const RobotModel& r) { return vectorCopy(r.lowerLimits()); },
          "Lower limit of each joint of q (-inf where it has none); a new array.")
      .def_property_readonly(
          "upper_limits", [](const RobotModel& r) { return vectorCopy(r.upperLimits()); },
          "Upper limit of each joint of q (+inf where it has none); a new array.")
      .def_property_readonly("urdf", &RobotModel::urdfText,
                             "The URDF text, byte for byte as loaded.")
      .def("__repr__", [](const RobotModel& r) {
        return "<stac.RobotModel '" + r.name() + "' from " + r.sourceName() + ": " +
               std::to_string(r.dof()) + " joints>";
      });
}

}  // namespace stac::python
