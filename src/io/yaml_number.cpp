#include "io/yaml_number.hpp"

#include <cctype>
#include <charconv>
#include <cstdlib>
#include <limits>
#include <string_view>

namespace stac {

std::optional<double> parseYamlNumber(const std::string& s) {
  std::string_view v(s);
  bool negative = false;
  if (!v.empty() && (v.front() == '+' || v.front() == '-')) {
    negative = v.front() == '-';
    v.remove_prefix(1);
  }
  if (v == ".inf" || v == ".Inf" || v == ".INF")
    return negative ? -std::numeric_limits<double>::infinity()
                    : std::numeric_limits<double>::infinity();
  if (v == ".nan" || v == ".NaN" || v == ".NAN") return std::numeric_limits<double>::quiet_NaN();
  if (v.empty() || !(std::isdigit(static_cast<unsigned char>(v.front())) || v.front() == '.'))
    return std::nullopt;
  double x = 0;
  const auto res = std::from_chars(v.data(), v.data() + v.size(), x);
  if (res.ptr != v.data() + v.size()) return std::nullopt;
  if (res.ec == std::errc::result_out_of_range)  // underflow -> 0 or subnormal, overflow -> inf
    x = std::strtod(std::string(v).c_str(), nullptr);
  else if (res.ec != std::errc())
    return std::nullopt;
  return negative ? -x : x;
}

}  // namespace stac
