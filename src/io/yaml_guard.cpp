// The scan in front of yaml-cpp (see yaml_guard.hpp): a small YAML lexer
// that knows only what decides whether a ',', '[', ']', '{' or '}' is a flow
// indicator or text.
#include "io/yaml_guard.hpp"

#include <string_view>
#include <vector>

#include "stac/error.hpp"

namespace stac {
namespace {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }
bool isFlowIndicator(char c) { return c == ',' || c == '[' || c == ']' || c == '{' || c == '}'; }

class FlowScanner {
 public:
  FlowScanner(const std::string& text, const std::string& source)
      : text_(text), source_(source) {}

  void run() {
    size_t begin = text_.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;  // a byte order mark
    while (begin <= text_.size()) {
      size_t end = text_.find('\n', begin);
      if (end == std::string::npos) end = text_.size();
      ++line_;
      scanLine(std::string_view(text_).substr(begin, end - begin));
      begin = end + 1;
    }
    // A '[' or '{' never closed is left to yaml-cpp: it reports it, at the
    // end of the text, and does not hang.
  }

 private:
  struct Open {
    char bracket;
    int line, column;
  };

  [[noreturn]] void fail(int line, int column, const std::string& what) const {
    throw InputError(source_, line, column, "malformed YAML: " + what);
  }

  static size_t indentation(std::string_view s) {
    size_t i = 0;
    while (i < s.size() && isBlank(s[i])) ++i;
    return i;
  }

  void scanLine(std::string_view s) {
    const size_t indent = indentation(s);
    if (block_scalar_indent_ >= 0) {
      // A block scalar's text: blank lines and lines indented deeper than
      // the line that opened it.
      if (indent == s.size() || static_cast<int>(indent) > block_scalar_indent_) return;
      block_scalar_indent_ = -1;
    }
    size_t i = 0;
    if (quote_) {
      i = skipQuoted(s, 0);
      if (quote_) return;
    } else if (open_.empty() && !s.empty() && s[0] == '%') {
      return;  // a directive
    } else if (isDocumentMarker(s)) {
      i = 3;
    }
    scanTokens(s, i, indent);
  }

  static bool isDocumentMarker(std::string_view s) {
    return (s.substr(0, 3) == "---" || s.substr(0, 3) == "...") &&
           (s.size() == 3 || isBlank(s[3]));
  }

  // The line from i on, outside any quoted scalar at i.
  void scanTokens(std::string_view s, size_t i, size_t indent) {
    bool in_plain = false;  // inside a plain (unquoted) scalar
    for (; i < s.size(); ++i) {
      const char c = s[i];
      const bool blank_before = i == 0 || isBlank(s[i - 1]);
      const bool blank_after = i + 1 == s.size() || isBlank(s[i + 1]);
      if (isBlank(c)) continue;
      if (c == '#' && blank_before) return;  // a comment
      if (in_plain) {
        // A plain scalar ends at ": ", and in a flow collection at a flow
        // indicator too; in block context ",[]{}" are part of its text.
        if (c == ':' && (blank_after || (!open_.empty() && isFlowIndicator(s[i + 1]))))
          in_plain = false;
        else if (open_.empty() || !isFlowIndicator(c))
          continue;
        else
          in_plain = false;
      }
      if (!token(s, &i, indent, blank_after)) in_plain = true;
      if (quote_ || block_scalar_indent_ >= 0) return;
    }
  }

  // The token at s[*i] (not inside a scalar); false if it starts a plain
  // scalar. Leaves *i on the token's last character.
  bool token(std::string_view s, size_t* i, size_t indent, bool blank_after) {
    const char c = s[*i];
    const int column = static_cast<int>(*i) + 1;
    switch (c) {
      case '\'':
      case '"':
        quote_ = c;
        *i = skipQuoted(s, *i + 1) - 1;
        return true;
      case '[':
      case '{':
        open_.push_back({c, line_, column});
        return true;
      case ']':
      case '}':
        close(c, column);
        return true;
      case ',':
        if (open_.empty())
          fail(line_, column,
               "a ',' outside any [ ] or { } collection (a comma separates the items of a "
               "[list] or a {map} only)");
        return true;
      case '|':
      case '>':
        if (!open_.empty()) return false;
        block_scalar_indent_ = static_cast<int>(indent);
        return true;
      case '&':
      case '!':
      case '*':
        // An anchor, a tag or an alias: one word, up to a blank (or a flow
        // indicator inside a collection).
        while (*i + 1 < s.size() && !isBlank(s[*i + 1]) &&
               (open_.empty() || !isFlowIndicator(s[*i + 1])))
          ++*i;
        return true;
      case '-':
      case '?':
      case ':':
        return blank_after || (c == ':' && !open_.empty() && isFlowIndicator(s[*i + 1]));
      default:
        return false;
    }
  }

  void close(char c, int column) {
    const char opener = c == ']' ? '[' : '{';
    if (open_.empty())
      fail(line_, column, std::string("'") + c + "' closes no '" + opener + "'");
    const Open o = open_.back();
    if (o.bracket != opener)
      fail(line_, column,
           std::string("'") + c + "' does not close the '" + o.bracket + "' of line " +
               std::to_string(o.line) + " column " + std::to_string(o.column));
    open_.pop_back();
  }

  // Skips the inside of the quoted scalar quote_ from s[i]: returns the
  // index past its closing quote (quote_ cleared), or s.size() when it goes
  // on to the next line.
  size_t skipQuoted(std::string_view s, size_t i) {
    for (; i < s.size(); ++i) {
      if (quote_ == '"' && s[i] == '\\') {
        ++i;  // an escape: the next character is text
      } else if (s[i] == quote_) {
        if (quote_ == '\'' && i + 1 < s.size() && s[i + 1] == '\'') {
          ++i;  // '' is a quote inside a single-quoted scalar
          continue;
        }
        quote_ = 0;
        return i + 1;
      }
    }
    return s.size();
  }

  const std::string& text_;
  const std::string& source_;
  int line_ = 0;
  std::vector<Open> open_;       // the flow collections open here
  char quote_ = 0;               // the quote of a scalar open here, or 0
  int block_scalar_indent_ = -1;  // the indentation of the line opening a | or > scalar
};

}  // namespace

void checkYamlFlowIndicators(const std::string& text, const std::string& source_name) {
  FlowScanner(text, source_name).run();
}

}  // namespace stac
