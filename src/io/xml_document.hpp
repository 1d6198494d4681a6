// XmlDocument: a strict XML reader that keeps where everything is in the text.
//
// It exists for the URDF (urdf_document.hpp): the loader and the URDF writer
// must read one text the same way, and the writer edits bytes in place, so
// it needs the byte range of every element and attribute value. It accepts a
// subset of XML 1.0 on which TinyXML (what urdfdom reads with) cannot read a
// different tree: well-nested elements, quoted attributes without
// duplicates, only the predefined entities and ASCII character references,
// no control characters, one root element, no DOCTYPE internal subset.
// Everything else is an InputError naming the file and line.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace stac::io {

struct XmlAttribute {
  std::string name;
  std::string value;  // character references resolved
  size_t value_begin = 0, value_end = 0;  // the raw value, quotes excluded
};

struct XmlElement {
  std::string name;
  size_t begin = 0;     // the '<'
  size_t name_end = 0;  // just past the element name
  size_t tag_end = 0;   // just past the '>' of the start tag
  bool self_closing = false;
  int line = 0;
  int parent = -1;            // index into XmlDocument::elements(), -1: root
  std::vector<int> children;  // element children, in document order
  std::vector<XmlAttribute> attributes;

  // nullptr if the element has no such attribute.
  const XmlAttribute* attribute(const std::string& name) const;
};

class XmlDocument {
 public:
  // Throws InputError(source, line, 0, "malformed XML: ...").
  XmlDocument(std::string text, std::string source);

  const std::string& text() const { return text_; }
  const std::string& source() const { return source_; }
  // Elements in document order; the root is element 0.
  const std::vector<XmlElement>& elements() const { return elements_; }
  const XmlElement& root() const { return elements_.front(); }
  // The first element child of `element` named `name`, or -1.
  int firstChild(int element, const std::string& name) const;
  // The 1-based line of a byte offset.
  int lineAt(size_t pos) const;

 private:
  class Reader;
  std::string text_, source_;
  std::vector<size_t> line_starts_;
  std::vector<XmlElement> elements_;
};

}  // namespace stac::io
