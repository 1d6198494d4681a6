#include "io/quoted.hpp"

#include <cstdio>

namespace stac {

std::string doubleQuoted(const std::string& s, QuoteStyle style) {
  std::string out = "\"";
  for (const char ch : s) {
    const unsigned char c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default: {
        const bool yaml = style == QuoteStyle::kYaml;
        if (c >= 0x20 && !(yaml && c == 0x7f)) {
          out += ch;
          break;
        }
        char buf[8];
        std::snprintf(buf, sizeof buf, yaml ? "\\x%02X" : "\\u%04x", c);
        out += buf;
      }
    }
  }
  return out + "\"";
}

}  // namespace stac
