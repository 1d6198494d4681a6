#include "methods/settled_run.hpp"

namespace stac {

bool settled(double decrement, double scale_change) {
  return decrement >= 0 && decrement <= 0.5 * kSettledStd * kSettledStd &&
         scale_change < kSettledScale;
}

}  // namespace stac
