// The strict XML reader (xml_document.hpp).
//
// Where TinyXML is lenient it reads some texts differently from what they
// say: a stray end tag or `< x>` becomes an "unknown" node and is skipped, a
// DOCTYPE ends at its first '>' even inside an internal subset, `&#233;`
// becomes one raw byte without an XML declaration, an unknown `&name;` is
// kept literally. Each of those is an error here, so that any text accepted
// here reads as the same tree in TinyXML (and so in urdfdom).
#include "io/xml_document.hpp"

#include <algorithm>
#include <cstring>

#include "stac/error.hpp"

namespace stac::io {
namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

bool isNameStart(char c) {
  const unsigned char u = static_cast<unsigned char>(c);
  return (u >= 'a' && u <= 'z') || (u >= 'A' && u <= 'Z') || u == '_' || u >= 0x80;
}

bool isNameChar(char c) {
  return isNameStart(c) || (c >= '0' && c <= '9') || c == '-' || c == '.' || c == ':';
}

std::string hexByte(unsigned char c) {
  const char* digits = "0123456789abcdef";
  return std::string("0x") + digits[c >> 4] + digits[c & 15];
}

}  // namespace

const XmlAttribute* XmlElement::attribute(const std::string& name) const {
  for (const XmlAttribute& a : attributes)
    if (a.name == name) return &a;
  return nullptr;
}

// One pass over the text, building XmlDocument::elements_.
class XmlDocument::Reader {
 public:
  explicit Reader(XmlDocument& doc) : doc_(doc), t_(doc.text_) {}

  void read() {
    size_t i = t_.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;  // UTF-8 BOM
    checkCharacters(i);
    while (i < t_.size()) {
      const size_t lt = std::min(t_.find('<', i), t_.size());
      if (open_.empty()) {
        for (size_t k = i; k < lt; ++k)
          if (!isSpace(t_[k])) fail(k, "text outside the root element");
      }
      if (lt == t_.size()) break;
      i = readMarkup(lt);
    }
    if (!open_.empty()) {
      const XmlElement& e = doc_.elements_[open_.back()];
      fail(e.begin, "<" + e.name + "> is never closed");
    }
    if (doc_.elements_.empty()) fail(t_.size(), "no root element");
  }

 private:
  [[noreturn]] void fail(size_t pos, const std::string& what) const {
    throw InputError(doc_.source_, doc_.lineAt(pos), 0, "malformed XML: " + what);
  }

  bool at(size_t i, const char* s) const { return t_.compare(i, std::strlen(s), s) == 0; }

  // Past the `end` that closes the construct opened at `start`.
  size_t skipTo(size_t from, const char* end, size_t start, const char* what) const {
    const size_t e = t_.find(end, from);
    if (e == std::string::npos) fail(start, std::string("unterminated ") + what);
    return e + std::strlen(end);
  }

  // XML forbids control characters other than tab and line breaks; TinyXML
  // lets them through, so a name could hold bytes no one can see.
  void checkCharacters(size_t from) const {
    for (size_t k = from; k < t_.size(); ++k) {
      const unsigned char c = static_cast<unsigned char>(t_[k]);
      if (c < 0x20 && c != '\t' && c != '\n' && c != '\r')
        fail(k, "control character " + hexByte(c) + " (not allowed in XML)");
    }
  }

  size_t nameEnd(size_t i, const std::string& what) const {
    if (i >= t_.size() || !isNameStart(t_[i])) fail(i, what);
    while (i < t_.size() && isNameChar(t_[i])) ++i;
    return i;
  }

  size_t skipSpace(size_t i) const {
    while (i < t_.size() && isSpace(t_[i])) ++i;
    return i;
  }

  // Reads the construct starting at the '<' at `i`; returns the offset past it.
  size_t readMarkup(size_t i) {
    if (at(i, "<!--")) return skipTo(i + 4, "-->", i, "comment");
    if (at(i, "<![CDATA[")) {
      if (open_.empty()) fail(i, "CDATA section outside the root element");
      return skipTo(i + 9, "]]>", i, "CDATA section");
    }
    if (at(i, "<?")) {
      const size_t end = skipTo(i + 2, "?>", i, "processing instruction");
      if (t_.find('>', i) != end - 1) fail(i, "'>' inside a processing instruction");
      return end;
    }
    if (at(i, "<!")) {
      if (!at(i, "<!DOCTYPE") || !doc_.elements_.empty())
        fail(i, "unexpected '<!' (only comments, CDATA and a DOCTYPE before the root)");
      const size_t end = t_.find('>', i);
      if (end == std::string::npos) fail(i, "unterminated <!DOCTYPE");
      if (t_.find('[', i) < end) fail(i, "a DOCTYPE with an internal subset is not supported");
      return end + 1;
    }
    if (at(i, "</")) return readEndTag(i);
    return readStartTag(i);
  }

  size_t readEndTag(size_t i) {
    const size_t ne = nameEnd(i + 2, "'</' without an element name");
    const std::string name = t_.substr(i + 2, ne - i - 2);
    const size_t close = skipSpace(ne);
    if (close >= t_.size() || t_[close] != '>') fail(i, "malformed end tag </" + name);
    if (open_.empty()) fail(i, "</" + name + "> closes nothing");
    const XmlElement& top = doc_.elements_[open_.back()];
    if (top.name != name)
      fail(i, "</" + name + "> closes <" + top.name + "> (opened at line " +
                  std::to_string(top.line) + ")");
    open_.pop_back();
    return close + 1;
  }

  size_t readStartTag(size_t i) {
    XmlElement el;
    el.begin = i;
    el.line = doc_.lineAt(i);
    el.name_end = nameEnd(i + 1, "'<' without an element name");
    el.name = t_.substr(i + 1, el.name_end - i - 1);
    if (open_.empty() && !doc_.elements_.empty())
      fail(i, "a second root element <" + el.name + "> after <" + doc_.root().name + ">");
    size_t j = el.name_end;
    for (;;) {
      const size_t after = skipSpace(j);
      if (after >= t_.size()) fail(i, "unterminated <" + el.name + ">");
      if (t_[after] == '>' || at(after, "/>")) {
        el.self_closing = t_[after] == '/';
        el.tag_end = after + (el.self_closing ? 2 : 1);
        break;
      }
      if (after == j) fail(j, "expected a space, '>' or '/>' in <" + el.name + ">");
      j = readAttribute(after, &el);
    }
    el.parent = open_.empty() ? -1 : open_.back();
    const int index = static_cast<int>(doc_.elements_.size());
    if (el.parent >= 0) doc_.elements_[el.parent].children.push_back(index);
    if (!el.self_closing) open_.push_back(index);
    const size_t next = el.tag_end;
    doc_.elements_.push_back(std::move(el));
    return next;
  }

  size_t readAttribute(size_t j, XmlElement* el) const {
    const size_t an = nameEnd(j, "expected an attribute name in <" + el->name + ">");
    XmlAttribute a;
    a.name = t_.substr(j, an - j);
    if (el->attribute(a.name))
      fail(j, "attribute '" + a.name + "' given twice in <" + el->name + ">");
    size_t k = skipSpace(an);
    if (k >= t_.size() || t_[k] != '=')
      fail(k, "attribute '" + a.name + "' without a value in <" + el->name + ">");
    k = skipSpace(k + 1);
    if (k >= t_.size() || (t_[k] != '"' && t_[k] != '\''))
      fail(k, "unquoted value of attribute '" + a.name + "' in <" + el->name + ">");
    const size_t close = t_.find(t_[k], k + 1);
    if (close == std::string::npos) fail(k, "unterminated value of attribute '" + a.name + "'");
    a.value_begin = k + 1;
    a.value_end = close;
    a.value = decode(a.value_begin, a.value_end);
    el->attributes.push_back(std::move(a));
    return close + 1;
  }

  // An attribute value with its references resolved. Only what TinyXML
  // resolves the same way in every encoding is accepted.
  std::string decode(size_t begin, size_t end) const {
    std::string out;
    for (size_t i = begin; i < end; ++i) {
      if (t_[i] == '<') fail(i, "'<' inside an attribute value (write &lt;)");
      if (t_[i] != '&') {
        out += t_[i];
        continue;
      }
      const size_t semi = t_.find(';', i);
      if (semi == std::string::npos || semi >= end)
        fail(i, "'&' that starts no reference (write &amp;)");
      const std::string ref = t_.substr(i + 1, semi - i - 1);
      out += resolve(ref, i);
      i = semi;
    }
    return out;
  }

  char resolve(const std::string& ref, size_t pos) const {
    if (ref == "amp") return '&';
    if (ref == "lt") return '<';
    if (ref == "gt") return '>';
    if (ref == "quot") return '"';
    if (ref == "apos") return '\'';
    if (ref.size() < 2 || ref[0] != '#') fail(pos, "unknown entity &" + ref + ";");
    const bool hex = ref[1] == 'x';
    const std::string digits = ref.substr(hex ? 2 : 1);
    const char* allowed = hex ? "0123456789abcdefABCDEF" : "0123456789";
    if (digits.empty() || digits.size() > 6 ||
        digits.find_first_not_of(allowed) != std::string::npos)
      fail(pos, "malformed character reference &" + ref + ";");
    const long c = std::stol(digits, nullptr, hex ? 16 : 10);
    if (c >= 0x80)
      fail(pos, "character reference &" + ref +
                    "; beyond ASCII: write the character itself (UTF-8)");
    if (c < 0x20 && c != '\t' && c != '\n' && c != '\r')
      fail(pos, "character reference &" + ref + "; to a control character");
    return static_cast<char>(c);
  }

  XmlDocument& doc_;
  const std::string& t_;
  std::vector<int> open_;  // elements whose end tag is still to come
};

XmlDocument::XmlDocument(std::string text, std::string source)
    : text_(std::move(text)), source_(std::move(source)) {
  line_starts_.push_back(0);
  for (size_t i = 0; i < text_.size(); ++i)
    if (text_[i] == '\n') line_starts_.push_back(i + 1);
  Reader(*this).read();
}

int XmlDocument::firstChild(int element, const std::string& name) const {
  for (int c : elements_[element].children)
    if (elements_[c].name == name) return c;
  return -1;
}

int XmlDocument::lineAt(size_t pos) const {
  return static_cast<int>(std::upper_bound(line_starts_.begin(), line_starts_.end(), pos) -
                          line_starts_.begin());
}

}  // namespace stac::io
