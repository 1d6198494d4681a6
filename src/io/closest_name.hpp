// "Did you mean" for names typed by hand (log columns, joints, links): the
// closest candidate, offered only when it is close enough to be a typo.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace stac {

// Levenshtein distance (insertions, deletions, substitutions).
size_t editDistance(const std::string& a, const std::string& b);

// The candidate nearest to `name` (the first among equals), if its edit
// distance is at most a third of the name's length (at least 1): a typo,
// not a different word. Nothing when none is that close — a hint that
// points at an unrelated name ("x1" -> "base_link") misleads.
std::optional<std::string> closestName(const std::string& name,
                                       const std::vector<std::string>& candidates);

}  // namespace stac
