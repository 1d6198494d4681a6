// In-place joint origin edits (urdf_edit.hpp).
#include "io/urdf_edit.hpp"

#include <algorithm>
#include <charconv>
#include <set>
#include <stdexcept>

namespace stac::io {
namespace {

struct Edit {
  size_t begin = 0, end = 0;  // the replaced range (empty: an insertion)
  std::string text;
};

std::string formatVector(const Eigen::Vector3d& v) {
  return formatCoordinate(v.x()) + " " + formatCoordinate(v.y()) + " " + formatCoordinate(v.z());
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// A new <origin> as the joint's first child, laid out like its siblings.
Edit insertOrigin(const UrdfDocument& doc, const XmlElement& joint, const std::string& attrs) {
  const std::string& text = doc.text();
  size_t j = joint.tag_end;
  while (j < text.size() && isSpace(text[j])) ++j;
  const std::string gap = text.substr(joint.tag_end, j - joint.tag_end);
  const size_t nl = gap.rfind('\n');
  std::string element = "<origin" + attrs + "/>";
  if (nl != std::string::npos) {
    const std::string newline = nl > 0 && gap[nl - 1] == '\r' ? "\r\n" : "\n";
    element = newline + gap.substr(nl + 1) + element;
  }
  return {joint.tag_end, joint.tag_end, element};
}

}  // namespace

std::string formatCoordinate(double v) {
  if (v == 0.0) return "0";
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

std::string withJointOrigins(const UrdfDocument& doc, const std::vector<OriginEdit>& edits) {
  const std::vector<XmlElement>& elements = doc.xml().elements();
  std::vector<Edit> out;
  std::set<std::string> done;
  for (const OriginEdit& e : edits) {
    const UrdfJoint* joint = doc.joint(e.joint);
    if (!joint) throw std::invalid_argument("withJointOrigins: no joint '" + e.joint + "'");
    if (!done.insert(e.joint).second)
      throw std::invalid_argument("withJointOrigins: joint '" + e.joint + "' edited twice");
    // rpy first: two insertions at one offset end up in reverse order.
    const std::vector<std::pair<const char*, const std::optional<Eigen::Vector3d>*>> values = {
        {"rpy", &e.rpy}, {"xyz", &e.xyz}};
    if (joint->origin < 0) {
      std::string attrs;
      for (auto it = values.rbegin(); it != values.rend(); ++it)
        if (it->second->has_value())
          attrs += " " + std::string(it->first) + "=\"" + formatVector(**it->second) + "\"";
      if (!attrs.empty()) out.push_back(insertOrigin(doc, elements[joint->element], attrs));
      continue;
    }
    const XmlElement& origin = elements[joint->origin];
    for (const auto& [key, v] : values) {
      if (!v->has_value()) continue;
      const std::string value = formatVector(**v);
      if (const XmlAttribute* a = origin.attribute(key))
        out.push_back({a->value_begin, a->value_end, value});
      else
        out.push_back({origin.name_end, origin.name_end, " " + std::string(key) + "=\"" + value + "\""});
    }
  }
  // From the end backwards, so that the recorded offsets stay valid.
  std::stable_sort(out.begin(), out.end(),
                   [](const Edit& a, const Edit& b) { return a.begin > b.begin; });
  std::string text = doc.text();
  for (const Edit& e : out) text.replace(e.begin, e.end - e.begin, e.text);
  return text;
}

}  // namespace stac::io
