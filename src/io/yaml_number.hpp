// A YAML plain scalar as a number, the way both YAML 1.1 and 1.2 readers
// see one (the sensors file is written for both).
#pragma once

#include <optional>
#include <string>

namespace stac {

// Decimal and exponent forms ("1", "1.0", "1e-05", "1.0e-05", "+2."), and
// .inf/.nan in their three spellings; nothing for any other text.
std::optional<double> parseYamlNumber(const std::string& s);

}  // namespace stac
