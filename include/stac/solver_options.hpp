// Choices a user makes about the solvers (SPEC §4: --loss, --q-phase).
#pragma once

namespace stac {

// A robust loss on each reading's squared whitened residual.
enum class LossKind { kNone, kHuber, kCauchy };

// How the q-phase refines each frame's joint angles (paper §III-D, §VI-A).
enum class QPhaseMethod {
  kLmIter,   // one accepted Levenberg-Marquardt step per frame (paper LM-iter)
  kLmBatch,  // LM to convergence per frame (paper LM-batch)
  kBfgs,     // BFGS per frame, Gauss-Newton-scaled start (paper §VI-A)
};
const char* qPhaseName(QPhaseMethod m);  // "lm-iter", "lm-batch", "bfgs"

}  // namespace stac
