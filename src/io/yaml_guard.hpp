// A guard in front of yaml-cpp 0.7. Its parser never returns (it loops,
// allocating until the process dies) when a document starts with a ','
// outside any flow collection: the two-byte file ",]", ", 1", " ,", "[1], 2",
// "'x' ,", "- [1]\n,", "---\n," and "&a ," all hang it (checked one by one
// under `timeout`). Any typo can produce one, so the text is scanned for
// flow indicators first and what yaml-cpp cannot survive never reaches it.
#pragma once

#include <string>

namespace stac {

// Throws InputError(source_name, line, column, "malformed YAML: ...") for a
// ',' outside any [ ] or { } collection, or a ']' or '}' that closes no
// bracket or the wrong one (yaml-cpp survives those two, but the message
// is clearer). Quoted scalars,
// comments, plain scalars (where ',' and brackets are text in block
// context) and block scalars (| and >) are skipped. Conservative on one
// point: a line of block context that starts with ',' is refused even where
// YAML would read it as the continuation of a plain scalar; no sensors file
// holds such a value.
void checkYamlFlowIndicators(const std::string& text, const std::string& source_name);

}  // namespace stac
