// Where a chain flip's mirrors are exact: the centres, found from the
// kinematics, about which a serial chain's mirrored joints put its links
// below the flip back in the same places.
#pragma once

#include <optional>
#include <vector>

#include "stac/robot_model.hpp"

namespace stac {

// A chain flip turns the columns `half_turn` half a turn and mirrors the
// columns `flip` about centres c (q -> 2c - q, a column in both lists
// mirrored then turned). Where they lie on one path from the root and the
// deepest of them is turned, the flip can leave that joint's link, and so
// everything below it, exactly where it was for every configuration: the
// half turn at the top, carried down the chain, is a half turn about a line
// that each mirror rotates about its joint's axis by its centre, and the
// turn at the bottom undoes it once that line is the bottom joint's axis.
// The centres where that happens are zero where the links' offsets keep
// the axes aligned at zero (a Jaco's shoulder flip); elsewhere they are
// where the offsets align them (an unseen Z1's arm mirror, q1 + π and
// q6 + π, its three pitches and wrist yaw mirrored about π/2, 0.256,
// −0.256 and 0: about zero it refined to 3200 times the truth's cost, and
// the run ended flagged in the mirror). Returns each flip column's
// centre modulo π (the mirrors about c and c + π differ by a whole turn),
// solved on a few fixed configurations within the limits from a few starts
// (0 and π/2 each), or nothing where the columns form no such chain or no
// centres make the flip exact (to a millimetre: a URDF's rounding or a
// sub-millimetre offset leaves it as good a start for a jump).
std::optional<std::vector<double>> exactMirrorCentres(const RobotModel& robot,
                                                      const std::vector<int>& flip,
                                                      const std::vector<int>& half_turn);

}  // namespace stac
