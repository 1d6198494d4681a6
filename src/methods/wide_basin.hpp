// Wide-basin initialisation of θ and q from the paper's seeding (internal).
//
// The steps, each usable (and tested) on its own:
//  - pot guesses: each one-joint sensor's readings mapped onto its joint's
//    range (makePotGuesses); a Candidate holds one such map per guess, as
//    values, and the candidate transforms below build new ones from old;
//  - WideBasin scores a candidate by how well the markers then fit on a
//    subsample (score, a const function of the candidate and where its
//    search stands) and searches the candidates by sweeps (mirror patterns
//    at a few coverage scales, the seed's own maps, sign moves, rescales);
//  - then a marker-led alternation on every frame (alternate), a coupled
//    re-check of the signs (recheckSigns) and a last fit of the pots.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "solve/q_phase.hpp"

namespace stac {

// Frames used for initialising: at most this many, spread over the log.
constexpr int kInitFrames = 1000;
// Two configurations fit alike when their costs differ by less than this
// share (an exact symmetry differs by rounding; the wrong minima of the
// basin test by 15% and more).
constexpr double kSameFit = 1e-3;
// A jump whose closed-form fit is within this factor of the estimate's is
// refined before it is judged (WideBasin::equivalentMoves): an unseen
// Kinova Jaco's shoulder mirror, inexact by the arm's 1.6 and 11 mm
// offsets, fit 1.13x so and, refined, 0.06% below the estimate.
constexpr double kNearMirror = 2.0;
// A jump to another minimum is taken when its cost, after a few steps only,
// is below the converged one's by more than kSameFit: it can only fall
// further. Not by more: under gross outliers the robust loss's linear tails
// dominate the cost, and a pot's map a whole turn off, 35% of the frames
// held at a limit, costs less than 1% more (the run then goes on from the
// jump and keeps its end only if it fits better, so a false jump costs
// time, not accuracy).
constexpr double kBetterMinimum = 1.0 - kSameFit;
// An equivalent move (WideBasin::equivalentMoves) is taken where, refined,
// it fits below the estimate's refined cost by more than this share: above
// the refinements' rounding, far below kSameFit (an unseen planar double
// pendulum on partial swings ended with joint 2 mirrored, the mirror listed
// undetermined while the truth it led to fitted 0.09% better).
constexpr double kBetterEquivalent = 1e-5;
// Jumps whose refined costs lie within this share of the lowest reached
// one minimum by different paths (a few coupled steps from each leave them
// up to 6e-7 apart), and the one whose start fits clearly best is taken:
// the whole log goes on from the unrefined start, and from a start farther
// from its end a longer path can end elsewhere (an unseen Go2 on partial
// swings, seed 19 truth 9: its thigh pot's map a whole turn off; the whole
// turn, exact, and a mirror with the hip placed both refined to 2879.85,
// the mirror 6e-7 lower, and the run from it on the whole log ended with
// the calf a turn off; not kept, flagged). Below the 6e-5 by which a start
// still on its way can end above the minimum (the arm's wrist flip about
// its motion's mean, against the exact flip).
constexpr double kSameRefinedFit = 1e-5;
// Starts whose costs differ by less than this share are alike (exact jumps
// of the same fit start at the same cost but for rounding): of those, the
// first listed, the simplest, is taken.
constexpr double kSameStart = 1e-6;

// Where the verdict would flag a motion beyond its limits, a jump that
// relieves them goes on to the whole log if it fits the subsample within
// this share (not kSameFit), and the whole log's run decides
// (goOnIfBetter): 150 frames cannot tell a near-exact mirror from the
// truth (an unseen Hextilt on partial swings, seed 29 truth 4: the wrist's
// mirror, exact to 0.5 mm, fitted the subsample 0.17% better than the
// truth and the whole log 0.002% worse; flagged). A run the verdict would
// not flag is not sent on such runs.
constexpr double kFlaggedSameFit = 0.01;

// The choice among jumps scored one after another from a converged cost
// `base` (jumpToBetterMinimum): those that fit better than
// kBetterMinimum·base, else those that relieve the joints' limits and fit
// within `as_well` (a share) of it; of them, the lowest refined cost, or
// of those alike to it (kSameRefinedFit) the one whose start fits clearly
// best (kSameStart), else the first listed.
class JumpChoice {
 public:
  explicit JumpChoice(double base, double as_well = kSameFit) : base_(base), as_well_(as_well) {}
  // Jump `index`: its cost refined and at its start, whether it relieves
  // the limits.
  void consider(int index, double cost, double start, bool relieves);
  // The jump taken; -1: none.
  int chosen() const;

 private:
  struct Scored {
    int index;
    double cost, start;
  };
  static int pick(const std::vector<Scored>& jumps);
  double base_, as_well_;
  std::vector<Scored> better_, within_;
};

// A jump whose start, refined, fits within this factor of the converged
// cost is a near miss: its exact form (jumpToBetterMinimum) is worth a try
// even where no joint it moves is at its limits.
constexpr double kNearMiss = 1.05;

// Returns θ initialised from `theta` (the seed) on obs; state->q (one row per
// frame of obs, neutral on entry) receives the initial joint angles.
SensorParameters wideBasinInitialisation(const MeasurementModel& model, const Observations& obs,
                                         const NoiseModel& noise, const RobustLoss& loss,
                                         int threads, std::vector<FrameWorkspace>* ws,
                                         SensorParameters theta, QState* state,
                                         bool coupled_steps);

// A map from a pot's reading to its joint's angle: q = alpha (p - pivot) + mid.
struct PotMap {
  double alpha = 0, mid = 0;
};

// One one-joint sensor whose joint the initialisation guesses from it.
struct PotGuess {
  int sensor = -1;     // joint sensor index
  int column = -1;     // q index
  double pivot = 0;         // the reading the map turns about: the mean reading,
                            // or the held bias (q = alpha (p - bias), mid 0)
  bool fixed = false;       // the gain is held: alpha is its exact inverse, never
                            // swept (with the bias held too, the whole map)
  bool bias_held = false;   // the bias is held: adopting a map keeps it
  PotMap map;               // the guess (below)
};

// The joint angle a one-joint sensor implies if the log spans 80% of the
// joint's range: q = alpha (p - mean p) + mid. Such a guess has the right
// time course; alpha's sign and scale are unknown, and greedy sweeps pick
// each by how well the markers then fit. A held gain makes alpha known
// (1/gain), a held bias the map q = alpha (p - bias), both the exact
// inverse. One guess per joint (the first of its sensors), none for mimic
// joints or sensors with fewer than two readings. With `gross_readings`
// (the user chose a robust loss) the span is the readings' 5-95% quantile
// range and the pivot their median: a few gross readings otherwise set the
// extremes, and the map's scale, alone (5% at 50-200 σ sent every hand24
// truth of the basin test to a wrong minimum). On clean smooth motion the
// quantiles cost about 1% of the span, which the scale sweep takes back.
std::vector<PotGuess> makePotGuesses(const RobotModel& robot, const SensorSet& sensors,
                                     const SensorParameters& theta, const Observations& obs,
                                     bool gross_readings = false);

// A candidate initialisation of the pots: maps[i] for guesses[i].
struct Candidate {
  std::vector<PotMap> maps;
};

// The guesses' own maps.
Candidate guessedMaps(const std::vector<PotGuess>& guesses);
// Writes each guessed joint's column of q (frames of obs) from its map; a
// frame without a reading keeps the previous frame's angle (mid before the
// first reading).
void applyCandidate(const std::vector<PotGuess>& guesses, const Candidate& candidate,
                    const Observations& obs, RowMatrix* q);

// Candidate transforms: each returns a new candidate.
// The signs of alpha flipped where flip[i], but for fixed guesses.
Candidate withSigns(const Candidate& c, const std::vector<PotGuess>& guesses,
                    const std::vector<bool>& flip);
// Every alpha but the fixed guesses' times s.
Candidate scaled(const Candidate& c, const std::vector<PotGuess>& guesses, double s);
// The seed's maps inverted where it has a finite non-zero gain (for a fixed
// guess, the map it has already).
Candidate seededMaps(const Candidate& c, const std::vector<PotGuess>& guesses,
                     const SensorParameters& seed);
// A sign move: the signs of the listed guesses flipped together. The
// sweeps skip a move that touchesFixed.
Candidate flipped(const Candidate& c, const std::vector<int>& move);
bool touchesFixed(const std::vector<PotGuess>& guesses, const std::vector<int>& move);
// Guess i's alpha times s (the sweeps skip fixed guesses).
Candidate rescaled(const Candidate& c, int i, double s);

// The likeliest wrong answers are mirror images of the whole motion: the
// world turned half a turn about a base axis a flips the sign of every joint
// whose axis (at the neutral pose) is perpendicular to a. Returns the four
// patterns to flip: all signs, then those of the base's x, y and z axes.
std::vector<std::vector<bool>> mirrorPatterns(const RobotModel& robot,
                                              const std::vector<PotGuess>& guesses);
// The sign moves of the greedy sweeps: each guess alone, then each guess
// together with the nearest guessed joint above it in the tree.
std::vector<std::vector<int>> signMoves(const RobotModel& robot,
                                        const std::vector<PotGuess>& guesses);

// Mirrors joint angle column `g.column` about its mean (about 0 where the
// bias is held) and flips the sign of its pot's map so that the pot's
// predictions stay the same.
void flipSign(const PotGuess& g, SensorParameters* theta, RowMatrix* q);
// Mirrors column g.column about c and flips its pot's map to match.
void mirrorAbout(const PotGuess& g, double c, SensorParameters* theta, RowMatrix* q);
// Moves joint angle column `g.column` half a turn (toward the middle of the
// joint's limits) and shifts its pot's bias so that the pot's predictions
// stay the same.
void halfTurn(const RobotModel& robot, const PotGuess& g, SensorParameters* theta, RowMatrix* q);

// A discrete jump between minima of the pots' maps: the guesses `flip`
// mirrored (flipSign), the guesses `half_turn` moved half a turn, the
// guesses `whole_turn` a whole turn (both toward the middle of the limits).
// The guesses `wrap`: each frame's angle moved by whole turns into the one
// turn cut in the widest arc the angles leave empty (wrapMoves), the pots' maps then
// re-fitted (WideBasin::moveTo). The guesses `recentre`: the joint's motion
// shifted so that it lies within the limits, its middle `place` of the way
// from the lowest such middle to the highest (0.5: the limits' middle;
// recentreMoves), θ then re-fitted to the moved angles.
struct MinimumMove {
  std::vector<int> flip, half_turn, whole_turn;
  bool flip_about_zero = false;  // its mirrors about the exact centres (applyMove)
  std::vector<int> wrap = {};  // (a default: the other moves' braces leave it out)
  std::vector<int> recentre = {};
  double place = 0.5;
  // Guesses below `recentre` placed in their limits' middle (after `flip`).
  std::vector<int> recentre_below = {};
  // Where given (one per flip), each flip about its centre instead, the
  // half turns of flipped joints absorbed in it (where the tendons spanning
  // them are symmetric: WideBasin::tendonCentred).
  std::vector<double> flip_centres = {};
  // The mocap frame re-fitted in closed form to the moved motion, as a
  // flip about zero has it (world_turn.hpp: the world's half turn).
  bool world_turn = false;
};
// The jumps a converged calibration is checked against: each sign move
// (signMoves); each joint half a turn; each joint half a turn with the
// guessed joint below it mirrored, a mirrored joint with the ones above
// and below it half a turn, and two mirrored neighbours with the ones above
// and below them half a turn (the "wrist" and "shoulder flips" of a serial
// chain: its links then pass through the same places, so markers on or
// beyond them barely tell the two apart, or not at all); and both joints of
// a pair half a turn. Also the long chain flips: 3-4 mirrored joints,
// those over the top and those to the chain's end (pot_guesses.cpp), where
// the first mirrored joint's axis is perpendicular to the half-turned
// one's; with `through`, only those that turn or mirror a joint (q column)
// it marks. None that changes a held gain or bias.
std::vector<MinimumMove> minimumMoves(const RobotModel& robot, const std::vector<PotGuess>& guesses,
                                      const std::vector<std::vector<int>>& sign_moves,
                                      const std::vector<bool>* through = nullptr);
// Whether `move` mirrors or turns a joint (q column) that `joints` marks.
bool turnsAny(const std::vector<PotGuess>& guesses, const MinimumMove& move,
              const std::vector<bool>& joints);
// Each guess on a revolute joint with limits, a whole turn: the same
// kinematics and pot predictions, but a log's motion placed a turn off
// runs into the limits. Offered where the limits span more than a turn (a
// UR arm's ±2π), or where most of q's angles are at or beyond them
// (arm4's ±1.5: a pot map a turn off put all the motion a turn above them,
// a minimum of exactly the truth's cost). None that changes a held bias.
// First, where several motions are mostly at their limits, their whole
// turns at once: each is exact, and one a jump round took an unseen UR10
// (partial swings, seed 23 truth 6: five pots' maps a whole turn off)
// beyond the rounds' budget, flagged with its wrist a turn off. Listed
// first, it is the one taken where it fits as well as any single turn
// (JumpChoice: exact turns start alike).
std::vector<MinimumMove> wholeTurnMoves(const RobotModel& robot,
                                        const std::vector<PotGuess>& guesses, const RowMatrix& q);
// Each guess on a joint that turns freely (continuous, or limits spanning
// more than a turn) whose angles in q span more than a turn: all of them
// into one turn. The markers see such a joint only modulo a turn, so a pot
// map at a wrong scale (the initialisation's guess of how much of a turn
// the log sweeps) can hold the frames' angles several turns apart, each
// where the markers fit it best, and no local step brings them together:
// an unseen TIAGo's wheel on partial swings converged with its pot's gain
// at 0.32 (truth 2.53), the motion 7.8 times the truth's, the wheel's
// marker at 8.4 times its σ. A log that sweeps more than a turn has no
// such move that fits better.
std::vector<MinimumMove> wrapMoves(const RobotModel& robot, const std::vector<PotGuess>& guesses,
                                   const RowMatrix& q);
// Each guess on a joint with finite limits whose angles in q lie beyond
// the URDF's limits in most frames, or whose column is `flagged`: its
// motion shifted, the pot's bias with it, into the limits, its middle at
// kPlacements places spread over the middles that keep it within them; and
// the guessed joint above it placed so, with it mirrored and in its
// limits' middle. The jumps flag what the verdict would
// (jointsOftenBeyondLimits at kSuspectShareAtLimit): an unseen Unitree
// B1's calf, mirrored at half scale below the knee's limit in 169 of 600
// frames, lay beyond them in too few frames for "most", was flagged, and
// from the placements reaches the truth. Where nothing but a
// marker on the joint's own link sees its absolute angle, a constant shift
// of the angle is taken up by that marker's position, and a fit can end
// with the whole motion beyond a limit at the truth's cost: the bundled
// hand on partial swings (basin truth 4 of noise draw 2), its ring
// finger's last joint beyond its limit in 498 of 500 frames, 1.4 rad off,
// flagged. Where a short swing of the joint below is all that sees it (an
// unseen Unitree Z1's roll above its gripper, swung over 0.44 rad), the
// angle is weakly pinned and has several minima, the joint below's map
// mirrored and rescaled in the wrong ones: the roll ended 4.8 rad off and
// beyond its limits in most frames (fresh truth 9), or the gripper beyond
// its own in every frame (truth 8), at the truth's cost. From the limits'
// middle truth 9 (1.8 rad from it) was not reached; from the nearest of
// five places, the gripper mirrored, it is. No discrete jump brings any
// of them back. None that changes a held bias.
constexpr int kPlacements = 5;
std::vector<MinimumMove> recentreMoves(const RobotModel& robot,
                                       const std::vector<PotGuess>& guesses, const RowMatrix& q,
                                       const std::vector<int>& flagged = {});
// The move's mirrors are about each column's mean, or with
// `mirror_about_zero` about the centres where the chain's mirror is exact
// to a millimetre (exactMirrorCentres; zero where there are none: the
// Panda's axes 1 and 3 align at q2 = 0, the Kinova Jaco's 4 and 6 at
// q5 = π), modulo half turns, the half turns chosen to keep the mirrored
// motion nearest the middle of the limits.
void applyMove(const RobotModel& robot, const std::vector<PotGuess>& guesses,
               const MinimumMove& move, SensorParameters* theta, RowMatrix* q,
               bool mirror_about_zero = false);
// Whether some sensor fits clearly worse than its noise: its median
// residual over the frames of obs more than `factor` times what Gaussian
// noise of its σ gives; a tendon more than `tendon_factor` times (0: the
// tendons not checked, e.g. where the marker-led steps of the
// initialisation left them at the seed).
bool someSensorMisfits(const MeasurementModel& model, const SensorParameters& theta,
                       const NoiseModel& noise, const Observations& obs, const RowMatrix& q,
                       double factor = 2.0, double tendon_factor = 2.0);
// The sensor whose median residual over the frames of obs is the most
// times what Gaussian noise of its σ gives (ratio 0: no readings); a
// tendon's ratio divided by tendon_factor (0: the tendons not checked).
struct SensorMisfit {
  SensorGroup group = SensorGroup::kMarker;
  int sensor = -1;
  double ratio = 0;
};
SensorMisfit worstMisfit(const MeasurementModel& model, const SensorParameters& theta,
                         const NoiseModel& noise, const Observations& obs, const RowMatrix& q,
                         double tendon_factor = 1.0);

// A candidate's score and the subsample state it left.
struct ScoredCandidate {
  double cost = 0;
  QState state;
};

// Where a candidate search stands: the best candidate so far, its score,
// the subsample's q it left (the free joints of the next score start there:
// one sign or scale change moves them little, so a few LM steps re-converge
// them) and the per-frame LM damping of the last score, kept or not.
struct SearchState {
  Candidate best;
  double cost = 0;
  RowMatrix warm_q;
  Eigen::VectorXd damping;
};

// The estimate the alternation refines: θ, q of every frame, and the
// coupled steps' damping, carried from one alternation to the next.
struct Estimate {
  SensorParameters theta;
  QState state;
  double coupled_lambda = 1e-3;
};

// The initialisation of one log (obs: the frames used for initialising).
// Holds references to its arguments, which must outlive it; the workspaces
// (one per thread) are scratch, written by every step.
class WideBasin {
 public:
  WideBasin(const MeasurementModel& model, const Observations& obs, const NoiseModel& noise,
            const RobustLoss& loss, int threads, std::vector<FrameWorkspace>* ws,
            const SensorParameters& seed, bool coupled_steps);

  // The whole initialisation: θ from the seed; state->q as for
  // wideBasinInitialisation.
  SensorParameters run(QState* state) const;
  // The tree-order search's start alone (tree_search.hpp) and its estimate,
  // as run() takes it where the sweeps' start misfits; none where it does
  // not apply (no free marker group, no pot guessed, no marker or mocap
  // part held, too few frames).
  std::optional<SensorParameters> runTreeOrder(QState* state) const;

  const std::vector<PotGuess>& guesses() const { return guesses_; }
  const RobotModel& robot() const { return model_.robot(); }
  const std::vector<std::vector<int>>& moves() const { return moves_; }
  const Observations& subsample() const { return sub_; }
  bool markerGroupFree() const { return marker_group_free_; }

  // ---- Candidate search on the subsample (markers only) ----
  // How well the markers fit with candidate c, once the mocap frame and
  // markers are re-solved in closed form from the seed and the joints no
  // pot covers follow the markers from `from`'s q and damping.
  ScoredCandidate score(const Candidate& c, const SearchState& from) const;
  // A search whose best is c, scored from the neutral pose.
  SearchState startSearch(const Candidate& c) const;
  // Scores c; it becomes the best if its cost < factor * the best's.
  bool offer(const Candidate& c, double factor, SearchState* s) const;
  // Mirror patterns of the guessed maps at every coverage scale.
  void mirrorSweep(SearchState* s) const;
  // The seed's own maps.
  void seedCheck(SearchState* s) const;
  // Sign moves until none helps (at most 3 sweeps).
  bool signSweeps(SearchState* s) const;
  // Each guess's scale halved or doubled while the fit improves clearly.
  bool rescaleSweep(SearchState* s) const;
  // All of the above in order: the pots' initial maps.
  Candidate searchPotMaps() const;

  // ---- Alternation on every frame ----
  // θ's pot maps from the candidate, each moved by the whole turns that
  // bring its joint's motion inside the limits (turnsIntoLimits); q's
  // guessed columns from the readings.
  void adoptPotMaps(const Candidate& c, Estimate* est) const;
  // Marker-led alternation until the relative change of the cost is at most
  // tol (at most 30 iterations); pot_weight multiplies the pots' whitened
  // residuals (0: off), tendons are off.
  void alternate(double pot_weight, double tol, Estimate* est) const;
  // The coupled re-check of the signs (see the .cpp); whether one changed.
  bool recheckSigns(Estimate* est) const;
  // est with sign move `move` applied (flipSign); for one pot on a joint
  // only tendons see, also with it mirrored about where they are symmetric
  // (tendon_mirror.hpp).
  std::vector<Estimate> signMoved(const Estimate& est, const std::vector<int>& move) const;
  // `move` with each flip about where the tendons spanning the flipped
  // joints are least changed by it at θ and angles q (the move's other
  // turns applied; tendon_mirror.hpp), where some flipped joint is seen
  // by tendons (with only_tendons: by tendons and no marker); else none.
  // The markers' exact centres (exactMirrorCentres) miss such a mirror: a
  // UR wrist's half turn with its last joint mirrored is exact for a
  // marker on the last link at any centre (the marker re-fitted), for a
  // tendon over the wrist only at one.
  std::optional<MinimumMove> tendonCentred(const MinimumMove& move, const SensorParameters& theta,
                                           const RowMatrix& q, bool only_tendons) const;
  // The estimate from the pots' maps (none: no pot guessed) and q on entry:
  // every step above after the search.
  Estimate estimateFrom(const Candidate* maps, QState state) const;
  // estimateFrom the tree-order search's maps and `neutral`, where that
  // search applies.
  std::optional<Estimate> treeOrderEstimate(const QState& neutral) const;
  // The pots' maps re-fitted to est's angles; θ returned, the angles in *state.
  SensorParameters finish(Estimate est, QState* state) const;

  // ---- After convergence ----
  // Each of minimumMoves and wholeTurnMoves from est, refined by a few
  // alternations and coupled steps on the subsample; the best, if its cost
  // is below kBetterMinimum times est's (refined alike), is applied to every
  // frame of est and returned. Failing that, a whole turn that fits as well
  // (within kSameFit) and leaves fewer frames at the joint's limits: true
  // angles lie within them, and a motion placed a turn off that runs only a
  // little past a limit costs hardly more. est is a converged calibration
  // of obs.
  // minimumMoves' long chain flips only through the joints (q columns)
  // `at_limits` names, those at or beyond their limits: a chain's mirror
  // moves its own joints there. Not for a misfit alone (a log noisier than
  // its seed σ says would pay for them in every run), nor through every
  // joint where one is at its limits (humanoid38 from a free seed: the
  // gauge joints at their limits, 257 moves and 70 s a round).
  // With `world_turns_only`, only the world's half turns with a limb's
  // first joint (world_turn.hpp), which no misfit may show.
  std::optional<MinimumMove> jumpToBetterMinimum(Estimate* est,
                                                 const std::vector<int>& at_limits = {},
                                                 bool world_turns_only = false) const;
  // The jumps of minimumMoves from est that keep every angle within the
  // q-phase's limits and fit the subsample as well as est (cost within
  // kSameFit) once refined, angles and θ (refine): other configurations
  // the data cannot tell from est's. Only jumps that fit within
  // kNearMirror of est with θ re-fitted in closed form at the moved angles
  // are refined: an exact mirror fits as well at once, one made inexact by
  // a small offset in the chain only once its angles follow. Each with its
  // refined θ; `refitted` (if given) gets est's own θ refined on the same
  // subsample, what the moved θ are to be compared with, and
  // `refitted_cost` its cost there.
  struct EquivalentMove {
    MinimumMove move;
    SensorParameters theta;
    double cost;  // refined, on the subsample
  };
  std::vector<EquivalentMove> equivalentMoves(const Estimate& est,
                                              SensorParameters* refitted = nullptr,
                                              double* refitted_cost = nullptr) const;
  // Of the equivalent moves, the one that fits the subsample best once
  // refined, if that is below est's own refined cost by more than
  // kBetterEquivalent, applied to est on the whole log; none otherwise.
  // The data hardly tell such minima apart, but a converged run takes no
  // jump that fits within kSameFit of it, so it can end in the one that
  // fits worse while the listing reports the other. `same` and `refitted`
  // get equivalentMoves' answer from est as it was.
  std::optional<MinimumMove> jumpToBetterEquivalent(Estimate* est,
                                                    std::vector<EquivalentMove>* same,
                                                    SensorParameters* refitted) const;

 private:
  // How refinedCost's coupled steps move the pots' maps. The escape's
  // scoring of jumps steps dominated pots in their inverse chart
  // (pot_chart.hpp); the sign re-check keeps (gain, bias): in the chart its
  // few steps carry either sign to the same place (schur.hpp
  // CoupledStepOptions::inverse_charts). The initial alternation keeps
  // (gain, bias) too: in the chart it sent a ur5 with continuous joints
  // (basin truth 1) to a wrong minimum, the wrist_2 pot's gain 0.58 off.
  enum class PotSteps { kGainBias, kInverseCharts };
  // The cost after a few alternations and coupled steps on the subsample;
  // refine leaves the refined θ and angles in place.
  double refinedCost(SensorParameters theta, QState state,
                     PotSteps pots = PotSteps::kGainBias) const {
    return refine(&theta, &state, pots);
  }
  double refine(SensorParameters* theta, QState* state, PotSteps pots = PotSteps::kGainBias) const;
  // Rows sub_frames_ of q (every frame of obs).
  RowMatrix subsampleAngles(const RowMatrix& q) const;
  // applyMove on `state` (frames of `obs`: the subsample's or the log's);
  // after a whole-robot mirror the marker group (mocap frame and markers)
  // is found anew in closed form, and after a wrap every map (θ-phase): the
  // other moves carry the pots' maps along exactly.
  void moveTo(const MinimumMove& move, bool mirror_about_zero, const Observations& obs,
              SensorParameters* theta, QState* state) const;
  // The cost of every sensor over obs at est, the tendons fitted first.
  double fullCost(const Estimate& est) const;
  // theta with the tendons (which the marker-led steps leave at the seed)
  // fitted in closed form to q of `state` (frames of obs).
  SensorParameters withTendonsFitted(SensorParameters theta, const Observations& obs,
                                     const QState& state) const;
  // The pots' group weight once they carry their guessed maps.
  double potWeight() const { return guesses_.empty() ? 0.0 : 1.0; }

  const MeasurementModel& model_;
  const Observations& obs_;
  const NoiseModel& noise_;
  const RobustLoss& loss_;
  const int threads_;
  std::vector<FrameWorkspace>* ws_;
  const SensorParameters seed_;
  const bool coupled_steps_;
  const bool marker_group_free_;
  const std::vector<PotGuess> guesses_;
  const std::vector<std::vector<int>> moves_;  // sign changes tried: guess indices
  const std::vector<int> sub_frames_;          // frames of obs_ in sub_
  const Observations sub_;                     // the search's subsample
  QPhaseOptions free_only_;                    // the score's q-phase of the free joints
  bool any_free_ = false;                      // some joint no pot covers
};

}  // namespace stac
