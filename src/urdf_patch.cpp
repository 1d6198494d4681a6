// A calibrated URDF by editing the text (urdf_patch.hpp).
//
// A DOM round trip (TinyXML, urdfdom) would lose comments, attribute order,
// quoting and number formatting, and users diff their URDFs. So a small
// scanner finds the byte ranges of elements and attribute values, and only
// the `xyz` values of the chosen joints' <origin> elements are rewritten.
#include "stac/urdf_patch.hpp"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <map>
#include <optional>
#include <stdexcept>
#include <unordered_map>

#include "stac/error.hpp"

namespace stac {
namespace {

struct XmlAttribute {
  std::string name;
  size_t value_begin = 0, value_end = 0;  // the value, quotes excluded
};

struct XmlElement {
  std::string name;
  size_t begin = 0;     // the '<'
  size_t name_end = 0;  // just past the element name
  size_t tag_end = 0;   // just past the '>' of the start tag
  bool self_closing = false;
  int parent = -1;
  std::vector<XmlAttribute> attributes;
};

int lineAt(const std::string& text, size_t pos) {
  int line = 1;
  for (size_t i = 0; i < pos && i < text.size(); ++i)
    if (text[i] == '\n') ++line;
  return line;
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// The elements of a well-formed XML text in document order, with their
// positions. Comments, CDATA, processing instructions and the DOCTYPE are
// skipped whole, so a commented-out <joint> is never seen.
std::vector<XmlElement> scanElements(const std::string& text, const std::string& source) {
  auto fail = [&](size_t pos, const std::string& what) -> void {
    throw InputError(source, lineAt(text, pos), 0, "malformed XML: " + what);
  };
  auto startsWith = [&](size_t i, const char* s) { return text.compare(i, std::strlen(s), s) == 0; };
  auto skipTo = [&](size_t from, const char* end, size_t start, const char* what) {
    const size_t e = text.find(end, from);
    if (e == std::string::npos) fail(start, std::string("unterminated ") + what);
    return e + std::strlen(end);
  };
  auto nameEnd = [&](size_t j) {
    while (j < text.size() && !isSpace(text[j]) && text[j] != '>' && text[j] != '/' &&
           text[j] != '=')
      ++j;
    return j;
  };
  std::vector<XmlElement> elements;
  std::vector<int> open;
  size_t i = 0;
  while ((i = text.find('<', i)) != std::string::npos) {
    if (startsWith(i, "<!--")) {
      i = skipTo(i + 4, "-->", i, "comment");
    } else if (startsWith(i, "<![CDATA[")) {
      i = skipTo(i + 9, "]]>", i, "CDATA section");
    } else if (startsWith(i, "<?")) {
      i = skipTo(i + 2, "?>", i, "processing instruction");
    } else if (startsWith(i, "<!")) {
      // <!DOCTYPE ...> with an optional [internal subset].
      size_t j = i + 2;
      int brackets = 0;
      while (j < text.size() && !(text[j] == '>' && brackets == 0)) {
        if (text[j] == '[') ++brackets;
        if (text[j] == ']') --brackets;
        ++j;
      }
      if (j >= text.size()) fail(i, "unterminated <!...> declaration");
      i = j + 1;
    } else if (startsWith(i, "</")) {
      const size_t ne = nameEnd(i + 2);
      const std::string name = text.substr(i + 2, ne - i - 2);
      const size_t close = text.find('>', ne);
      if (close == std::string::npos) fail(i, "unterminated </" + name + ">");
      if (open.empty() || elements[open.back()].name != name)
        fail(i, "</" + name + "> closes " +
                    (open.empty() ? "nothing" : "<" + elements[open.back()].name + ">"));
      open.pop_back();
      i = close + 1;
    } else {
      XmlElement el;
      el.begin = i;
      el.name_end = nameEnd(i + 1);
      el.name = text.substr(i + 1, el.name_end - i - 1);
      if (el.name.empty()) fail(i, "'<' without an element name");
      size_t j = el.name_end;
      for (;;) {
        while (j < text.size() && isSpace(text[j])) ++j;
        if (j >= text.size()) fail(i, "unterminated <" + el.name + ">");
        if (text[j] == '>') {
          el.tag_end = j + 1;
          break;
        }
        if (startsWith(j, "/>")) {
          el.self_closing = true;
          el.tag_end = j + 2;
          break;
        }
        XmlAttribute a;
        const size_t an = nameEnd(j);
        a.name = text.substr(j, an - j);
        j = an;
        while (j < text.size() && isSpace(text[j])) ++j;
        if (a.name.empty() || j >= text.size() || text[j] != '=')
          fail(j, "attribute without a value in <" + el.name + ">");
        ++j;
        while (j < text.size() && isSpace(text[j])) ++j;
        if (j >= text.size() || (text[j] != '"' && text[j] != '\''))
          fail(j, "unquoted attribute '" + a.name + "' in <" + el.name + ">");
        const size_t close = text.find(text[j], j + 1);
        if (close == std::string::npos) fail(j, "unterminated value of '" + a.name + "'");
        a.value_begin = j + 1;
        a.value_end = close;
        el.attributes.push_back(a);
        j = close + 1;
      }
      el.parent = open.empty() ? -1 : open.back();
      elements.push_back(el);
      if (!el.self_closing) open.push_back(static_cast<int>(elements.size()) - 1);
      i = el.tag_end;
    }
  }
  if (!open.empty()) fail(elements[open.back()].begin, "<" + elements[open.back()].name + "> is never closed");
  return elements;
}

// An attribute value with XML's character references resolved (names in the
// model are the parsed ones).
std::string decodeValue(const std::string& v) {
  static const std::map<std::string, std::string> kEntities = {
      {"amp", "&"}, {"lt", "<"}, {"gt", ">"}, {"quot", "\""}, {"apos", "'"}};
  std::string out;
  for (size_t i = 0; i < v.size(); ++i) {
    const size_t semi = v[i] == '&' ? v.find(';', i) : std::string::npos;
    if (semi == std::string::npos) {
      out += v[i];
      continue;
    }
    const std::string ref = v.substr(i + 1, semi - i - 1);
    if (auto it = kEntities.find(ref); it != kEntities.end()) {
      out += it->second;
    } else if (!ref.empty() && ref[0] == '#') {
      const long c = ref.size() > 1 && (ref[1] == 'x' || ref[1] == 'X')
                         ? std::strtol(ref.c_str() + 2, nullptr, 16)
                         : std::strtol(ref.c_str() + 1, nullptr, 10);
      if (c < 0x80) {
        out += static_cast<char>(c);
      } else {  // UTF-8
        char buf[4];
        int n = c < 0x800 ? 2 : c < 0x10000 ? 3 : 4;
        for (int k = n - 1; k > 0; --k) buf[k] = static_cast<char>(0x80 | ((c >> (6 * (n - 1 - k))) & 0x3f));
        buf[0] = static_cast<char>((n == 2 ? 0xc0 : n == 3 ? 0xe0 : 0xf0) | (c >> (6 * (n - 1))));
        out.append(buf, n);
      }
    } else {
      out += v.substr(i, semi - i + 1);
    }
    i = semi;
  }
  return out;
}

const XmlAttribute* findAttribute(const XmlElement& e, const char* name) {
  for (const XmlAttribute& a : e.attributes)
    if (a.name == name) return &a;
  return nullptr;
}

// Fewest digits that read back as exactly v; "0" for ±0.
std::string formatCoordinate(double v) {
  if (v == 0.0) return "0";
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

struct Edit {
  size_t begin = 0, end = 0;  // replaced range (empty: an insertion)
  std::string text;
};

}  // namespace

UrdfPatch patchUrdfMarkers(const std::string& urdf_text, const RobotModel& robot,
                           const SensorSet& sensors, const SensorParameters& theta,
                           const std::string& source_name) {
  const int M = static_cast<int>(sensors.markers.size());
  if (static_cast<int>(theta.marker_position.size()) != M)
    throw std::invalid_argument("patchUrdfMarkers: theta has " +
                                std::to_string(theta.marker_position.size()) +
                                " marker positions for " + std::to_string(M) + " markers");
  const std::vector<XmlElement> elements = scanElements(urdf_text, source_name);
  int root = -1;
  for (int e = 0; e < static_cast<int>(elements.size()) && root < 0; ++e)
    if (elements[e].parent == -1) root = e;
  if (root < 0 || elements[root].name != "robot")
    throw InputError(source_name, root < 0 ? 0 : lineAt(urdf_text, elements[root].begin), 0,
                     "not a URDF: the root element must be <robot>");
  // <joint> elements directly under <robot> (a <transmission> also has
  // <joint> children; those are not kinematic joints).
  std::unordered_map<std::string, int> joint_element;
  for (int e = 0; e < static_cast<int>(elements.size()); ++e) {
    if (elements[e].parent != root || elements[e].name != "joint") continue;
    if (const XmlAttribute* a = findAttribute(elements[e], "name"))
      joint_element.emplace(
          decodeValue(urdf_text.substr(a->value_begin, a->value_end - a->value_begin)), e);
  }

  // Every link's rigid body (the nearest link at or above it attached by a
  // movable joint, or the root) and its pose in that body's frame.
  const std::vector<Link>& links = robot.links();
  const int n = robot.numLinks();
  std::vector<int> body(n), children(n, 0);
  std::vector<Eigen::Isometry3d> in_body(n, Eigen::Isometry3d::Identity());
  for (int l = 0; l < n; ++l) {  // topological order: parents first
    const Link& link = links[l];
    if (link.parent >= 0) ++children[link.parent];
    if (link.parent < 0 || link.movable_joint >= 0) {
      body[l] = l;
    } else {
      body[l] = body[link.parent];
      in_body[l] = in_body[link.parent] * link.origin;
    }
  }
  std::vector<std::vector<int>> markers_on(n);
  for (int m = 0; m < M; ++m) markers_on[sensors.markers[m].link].push_back(m);
  std::vector<std::string> anchor_of(n);
  for (const TendonSensorConfig& t : sensors.tendon_sensors)
    for (const PathAnchor& a : t.path)
      if (anchor_of[a.link].empty()) anchor_of[a.link] = t.name;

  // Why link L cannot carry marker m ("" if it can).
  auto unsuitable = [&](int m, int L) -> std::string {
    const Link& link = links[L];
    const int k = sensors.markers[m].link;
    const std::string quoted = "link '" + link.name + "'";
    if (link.parent < 0) return quoted + " is the root";
    if (link.movable_joint >= 0)
      return quoted + " is attached by the movable joint '" + link.joint_name + "'";
    if (body[L] != body[k]) return quoted + " is not fixed to link '" + links[k].name + "'";
    if (children[L] > 0) return quoted + " has child links, which would move with it";
    for (int other : markers_on[L])
      if (other != m) return quoted + " also carries marker '" + sensors.markers[other].name + "'";
    if (!anchor_of[L].empty())
      return quoted + " carries an anchor of tendon sensor '" + anchor_of[L] + "'";
    return "";
  };

  UrdfPatch out;
  std::vector<int> carrier(M, -1);
  std::map<int, std::vector<int>> markers_of_carrier;
  for (int m = 0; m < M; ++m) {
    const MarkerConfig& mc = sensors.markers[m];
    const std::string own = unsuitable(m, mc.link);
    if (own.empty()) {
      carrier[m] = mc.link;
    } else {
      const std::optional<int> named = robot.linkIndex(mc.name);
      std::string why;
      if (!named)
        why = "the URDF has no link named '" + mc.name + "'";
      else if (*named != mc.link)
        why = unsuitable(m, *named);
      if (named && *named != mc.link && why.empty()) {
        carrier[m] = *named;
      } else {
        out.unplaced.push_back({mc.name, own + (why.empty() ? "" : ", and " + why)});
        continue;
      }
    }
    markers_of_carrier[carrier[m]].push_back(m);
  }
  // Two markers must not move the same link.
  for (const auto& [L, ms] : markers_of_carrier) {
    if (ms.size() < 2) continue;
    std::string names;
    for (int m : ms) names += (names.empty() ? "'" : ", '") + sensors.markers[m].name + "'";
    for (int m : ms) {
      carrier[m] = -1;
      out.unplaced.push_back({sensors.markers[m].name,
                              "markers " + names + " would all move link '" + links[L].name + "'"});
    }
  }

  std::vector<Edit> edits;
  std::vector<Eigen::Vector3d> target(M);  // the marker in its body's frame
  for (int m = 0; m < M; ++m) {
    const int L = carrier[m];
    if (L < 0) continue;
    const int k = sensors.markers[m].link;
    const Link& link = links[L];
    const Eigen::Vector3d& d = theta.marker_position[m];
    target[m] = in_body[k] * d;
    // The calibrated point in the frame of the joint's parent link. For the
    // marker's own link this is T_J d exactly (no detour through the body).
    const Eigen::Vector3d xyz =
        L == k ? Eigen::Vector3d(link.origin * d)
               : Eigen::Vector3d(in_body[link.parent].inverse() * target[m]);
    auto je = joint_element.find(link.joint_name);
    if (je == joint_element.end())
      throw InputError(source_name, "joint '" + link.joint_name +
                                        "' of the robot model is not in this URDF text");
    const XmlElement& joint = elements[je->second];
    out.placed.push_back(
        {sensors.markers[m].name, link.name, link.joint_name, lineAt(urdf_text, joint.begin)});
    if (xyz == link.origin.translation()) continue;
    const std::string value =
        formatCoordinate(xyz.x()) + " " + formatCoordinate(xyz.y()) + " " + formatCoordinate(xyz.z());
    const XmlElement* origin = nullptr;
    // Descendants of the joint follow it and have parents at or after it.
    for (size_t e = je->second + 1; e < elements.size() && elements[e].parent >= je->second; ++e) {
      if (elements[e].parent == je->second && elements[e].name == "origin") {
        origin = &elements[e];
        break;
      }
    }
    if (origin) {
      if (const XmlAttribute* a = findAttribute(*origin, "xyz"))
        edits.push_back({a->value_begin, a->value_end, value});
      else
        edits.push_back({origin->name_end, origin->name_end, " xyz=\"" + value + "\""});
    } else if (joint.self_closing) {
      throw InputError(source_name, lineAt(urdf_text, joint.begin), 0,
                       "joint '" + link.joint_name + "' has no <parent> or <child>");
    } else {
      // On its own line, indented like the joint's first child, when the
      // joint's children are on their own lines.
      size_t j = joint.tag_end;
      while (j < urdf_text.size() && isSpace(urdf_text[j])) ++j;
      const std::string gap = urdf_text.substr(joint.tag_end, j - joint.tag_end);
      const size_t nl = gap.rfind('\n');
      std::string element = "<origin xyz=\"" + value + "\"/>";
      if (nl != std::string::npos) {
        const std::string newline = nl > 0 && gap[nl - 1] == '\r' ? "\r\n" : "\n";
        element = newline + gap.substr(nl + 1) + element;
      }
      edits.push_back({joint.tag_end, joint.tag_end, element});
    }
  }
  std::sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.begin > b.begin; });
  out.urdf = urdf_text;
  for (const Edit& e : edits) out.urdf.replace(e.begin, e.end - e.begin, e.text);

  // The edit must do what it claims: every placed link's origin on its
  // marker, in the same body frame (an internal invariant, hence logic_error).
  if (!edits.empty()) {
    const RobotModel patched = RobotModel::fromString(out.urdf, source_name);
    for (int m = 0; m < M; ++m) {
      if (carrier[m] < 0) continue;
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      int l = *patched.linkIndex(links[carrier[m]].name);
      for (; patched.links()[l].parent >= 0 && patched.links()[l].movable_joint < 0;
           l = patched.links()[l].parent)
        T = patched.links()[l].origin * T;
      const double err = (T.translation() - target[m]).norm();
      if (patched.links()[l].name != links[body[carrier[m]]].name ||
          !(err <= 1e-9 * (1.0 + target[m].norm())))
        throw std::logic_error("patchUrdfMarkers: link '" + links[carrier[m]].name +
                               "' missed marker '" + sensors.markers[m].name + "' by " +
                               std::to_string(err) + " m");
    }
  }
  return out;
}

}  // namespace stac
