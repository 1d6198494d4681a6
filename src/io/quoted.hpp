// Strings in double quotes for the two text formats we write: JSON
// (stac_eval --json) and YAML (the sensors file). Both escape \" \\ \n \r \t
// alike; they differ only in how another control character is written.
#pragma once

#include <string>

namespace stac {

enum class QuoteStyle {
  kJson,  // other characters below 0x20 as \u00xx
  kYaml,  // other characters below 0x20, and DEL, as \xXX
};

std::string doubleQuoted(const std::string& s, QuoteStyle style);

}  // namespace stac
