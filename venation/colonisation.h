// Space-colonisation leaf venation (Runions et al. 2005): auxin sources, vein nodes, open and closed patterns.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "core/types.h"
#include "venation/leaf_shape.h"
#include "venation/point_tree.h"

namespace cellform::venation {

/// What may differ when a colonisation checkpoint is continued.
inline constexpr const char* kContinueMayDiffer =
    "the thread count, colonisation.max_steps, colonisation.max_nodes and colonisation.max_sources may differ when "
    "continuing it (and the widths, colonisation.tip_radius, murray_exponent and node_flow, computed at the end)";

/// Thrown when a checkpoint is loaded with other colonisation parameters (or another seed) than it was saved with.
class ParametersChanged : public core::InvalidInput {
 public:
  using core::InvalidInput::InvalidInput;
};

/// Thrown when a checkpoint is loaded for another source domain (leaf, volume or surface) than it was saved for.
class DomainChanged : public core::InvalidInput {
 public:
  using core::InvalidInput::InvalidInput;
};

/// Open (tree-like, Section 3) or closed (with anastomoses, Section 4) venation.
enum class VenationType { open, closed };

/// How closed patterns find the vein nodes a source influences (Section 5.2).
enum class Neighbourhood {
  exact,     ///< the relative neighbourhood of Eq. 2, exactly (up to exact distance ties), kept per source
             ///< between steps and updated with each step's new nodes only
  urquhart,  ///< Urquhart's approximation: Delaunay neighbours tested only against each other; the Delaunay
             ///< neighbours come from the source's Voronoi cell clipped by its 48 nearest nodes inside a
             ///< square of half-side 2 (nearest distance) + 4 D, then kept and clipped by each step's new
             ///< nodes. Slower than exact here (2 to 8 times in the presets): clipping a cell costs more
             ///< than merging the new nodes into the six sector bests exact keeps per source
};

/// Leaf blade growth (Section 3.3). The growth scale sigma goes from initial_scale to final_scale by
/// scale_step per step (sigma_{t+1} = sigma_t + delta sigma); Table 1's L_i, L_f, Delta L are these
/// with an outline of length 1.
enum class GrowthMode {
  none,      ///< the blade keeps its initial size
  marginal,  ///< the margin is scaled about the petiole; sources and veins stay where they are. Sources
             ///< are precomputed once over the final blade and appear as the margin reaches them
             ///< (marginal_sources.h), not thrown over the whole blade every step. No node is added outside
             ///< the grown blade: where the outline is not star-shaped about the petiole (a lobe's sinus, a
             ///< barb), a young blade reaches where the grown one does not
  uniform,   ///< isogonic: the whole leaf scales; computed by shrinking the unit distance lambda_t = lambda_0 sigma_0 /
             ///< sigma_t
  nonuniform,  ///< anisotropic, Appendix A: rates of growth in x and y depend on the initial height y_0
};

/// A relative elementary rate of growth per step as a function of the initial height y_0 above the
/// petiole (Figure 5: REG = 1 + g), as a lookup table: piecewise linear between samples, constant
/// beyond the ends. Appendix A: x_t = x_0 REG_x(y_0)^t and y_t = integral_0^{y_0} REG_y(y)^t dy (Eq. 4).
struct GrowthFunction {
  std::vector<double> y;     ///< model units (initial leaf, relative to the petiole), strictly increasing
  std::vector<double> rate;  ///< REG per step at each y (> 0; > 1 grows, 1 keeps, < 1 shrinks)
  double operator()(double y0) const;
};

/// Parameters of space colonisation. Distances are model units of the actual leaf, whose outline is the
/// Leaf outline scaled by sigma about the petiole (Table 1: an outline of length 1, sigma = L, D = 1).
struct ColonisationParams {
  double source_birth_distance = 10;  ///< b_s: a new source must be farther than this from every source
  double vein_birth_distance = 10;    ///< b_v: a new source must be farther than this from every vein node
  double kill_distance = 1;           ///< d_k: a vein node closer than this reaches (open: removes) a source
  double node_distance = 1;           ///< D: length of a vein segment, Eq. 1
  double darts_per_area = 2e-4;       ///< rho: darts thrown per unit leaf area per step (Table 1 lists rho x 1e6);
                                      ///< marginal growth throws all steps' darts at once (marginal_sources.h)
  /// open (trees) or closed (loops)
  VenationType type = VenationType::closed;
  /// closed: exact relative neighbourhoods (Eq. 2) or the Urquhart approximation
  Neighbourhood neighbourhood = Neighbourhood::exact;
  /// how the leaf grows while the veins do
  GrowthMode growth = GrowthMode::none;
  double initial_scale = 1;      ///< sigma_0: outline scale factor at step 0 (about the petiole)
  double final_scale = 1;        ///< sigma at which growth stops
  double scale_step = 0;         ///< Delta sigma per step (>= 0; > 0 for marginal and uniform growth)
  GrowthFunction growth_x;       ///< nonuniform: REG_x(y_0)
  GrowthFunction growth_y;       ///< nonuniform: REG_y(y_0)
  std::size_t growth_steps = 0;  ///< nonuniform: steps during which the leaf grows
  std::uint64_t seed = 1;        ///< all randomness (dart positions) derives from this
  int threads = 1;  ///< threads for the per-source neighbourhoods (0 = all cores); same result for any count
  std::size_t max_steps = 100000;     ///< stop (report.hit_max_steps) after this many steps
  std::size_t max_nodes = 5000000;    ///< stop (report.hit_max_nodes) once this many vein nodes exist
  std::size_t max_sources = 5000000;  ///< stop (report.hit_max_sources) after a step that leaves this many
                                      ///< auxin sources waiting (a leaf growing faster than its veins fill it),
                                      ///< or before a step whose darts would make more wait (not taken)
  std::size_t settle_steps = 5;       ///< after growth ends: stop when this many steps in a row added no
                                      ///< node and left as many sources waiting (a source born within reach of
                                      ///< the veins goes at once), and their darts were at least as many as the
                                      ///< domain holds b_v discs (balls), up to 1,000 (none under marginal
                                      ///< growth) (finished if no source is left, else stalled)
  /// Closed, exact, planar, nodes that never move (not nonuniform growth): a source whose nearest node
  /// provably excludes every other node from V(s) follows only that node until the proof runs out,
  /// instead of updating its six sector bests every step. The same result either way (false: to test
  /// that, and to measure the gain); not part of a saved state's parameters.
  bool lazy_sectors = true;
};

/// Throws core::InvalidInput naming "colonisation.<field>" and what is allowed. Must hold: every distance
/// positive and finite; d_k >= D / 2 (otherwise a vein tip can step over a lone source and oscillate
/// around it). d_k may exceed b_s and b_v (Table 1: ginkgo d_k = 100, b_s = 1; Figure 9a closed with
/// d_k = 40, b_s = 10): a source born that close to a vein is reached at once.
void validate(const ColonisationParams& params);

/// The leaf: its outline at scale 1, the petiole (growth centre), the seed vein nodes.
struct Leaf {
  Outline outline;                  ///< blade outline at growth scale 1, model units
  Vec2 petiole = Vec2::Zero();      ///< model units at scale 1: attachment of blade to petiole; growth scales about it
  std::vector<Vec2> initial_nodes;  ///< model units at scale 1: seed vein nodes (empty = the petiole); grasses: several
  std::vector<Vec2> initial_sources;  ///< model units at scale 1: sources at step 0 (no birth-distance test)
};

/// Positions in Leaf are in outline units at growth scale 1; they are scaled with the outline about the
/// petiole to initial_scale.
/// Throws core::InvalidInput naming "leaf.<field>": bad outline, petiole, seed node or source outside the blade
/// (more than 1e-6 of the leaf size outside its closed outline).
void validate(const Leaf& leaf);

struct Domain;  // venation/domain.h: a leaf, a volume or a surface

/// The vein graph. Nodes are in creation order, so a parent always precedes its children.
struct VeinTree {
  std::vector<Vec3> positions;                       ///< model units (z = 0 for leaves), in the grown leaf's frame
  std::vector<Index> parent;                         ///< kNoIndex for the seed nodes (roots); edges point base -> tip
  std::vector<std::uint32_t> birth_step;             ///< simulation step that created the node (0 = seed)
  std::vector<std::pair<Index, Index>> anastomoses;  ///< closing edges of closed patterns (loops)
  // Filled by compute_widths():
  std::vector<double> flow;          ///< Murray flow r^n carried by the node's segment (sum over what it drains)
  std::vector<double> radius;        ///< model units: vein radius at the node (segment node -> parent)
  std::vector<std::uint32_t> order;  ///< 1 = primary; a branch that is not the largest at its node gets +1

  std::size_t size() const { return positions.size(); }
  /// All edges: (parent, child) pairs then the anastomoses.
  std::vector<std::pair<Index, Index>> edges() const;
};

/// What a run (or one step) did.
struct ColonisationReport {
  std::size_t steps = 0;            ///< steps simulated
  std::size_t nodes = 0;            ///< vein nodes at the end
  std::size_t sources = 0;          ///< auxin sources still alive at the end
  std::size_t sources_born = 0;     ///< sources accepted by dart throwing
  std::size_t sources_removed = 0;  ///< sources removed (reached)
  std::size_t darts = 0;            ///< darts thrown (marginal growth: precomputed sources the margin reached)
  std::size_t marginal_darts = 0;   ///< marginal growth: darts thrown at the start over the grown blade's box
  std::size_t loops = 0;            ///< anastomosis edges added (a join of two seeds' trees closes no cycle)
  double scale = 1;                 ///< growth scale sigma at the end (nonuniform: steps of growth done)
  bool finished = false;            ///< growth over and no source left: the pattern is complete
  bool stalled = false;             ///< growth over, sources remain, but the settling steps changed nothing
  bool hit_max_steps = false;       ///< stopped by max_steps
  bool hit_max_nodes = false;       ///< stopped by max_nodes
  bool hit_max_sources = false;     ///< stopped by max_sources
  /// With hit_max_sources: the darts of the step after `steps` would have made more than max_sources wait,
  /// so it was not taken (nothing of it kept; a higher limit takes it as it would have been). At most this
  /// many sources would have waited after it (the waiting ones and the darts that passed the distance
  /// tests). 0: the limit stopped the run after a step. Not saved in checkpoints.
  std::size_t sources_wanted = 0;
};

/// Progress callback: (steps so far, vein nodes); return false to cancel (core::Cancelled).
using ColonisationProgress = std::function<bool(std::size_t, std::size_t)>;

/// The simulation as a stepping object, for animation and scripting; colonise() runs it to the end.
class Colonisation {
 public:
  /// Validates both arguments (core::InvalidInput) and places the seed nodes.
  Colonisation(const Leaf& leaf, const ColonisationParams& params);
  /// Any source domain (domain.h): a leaf as above, or sources in a volume or on a surface in 3-D.
  /// Validates the domain, the parameters and their combination (core::InvalidInput).
  Colonisation(const Domain& domain, const ColonisationParams& params);
  ~Colonisation();
  Colonisation(Colonisation&&) noexcept;
  Colonisation& operator=(Colonisation&&) noexcept;

  /// One step of Section 3.3 / 4: throw darts (b_s, b_v; marginal growth: reveal the precomputed sources
  /// the blade now reaches, with the same tests), find the nodes each source influences (open:
  /// nearest node, ties by index; closed: relative neighbourhood, Eq. 2/3), add one node per influenced
  /// node at distance D along the normalised mean direction (Eq. 1), remove (open) or tag and later
  /// remove (closed) sources reached within d_k, grow the blade. A node whose new segment would run
  /// within 5 degrees of one of its segments (to a child or its parent) steps towards its nearest
  /// influencing source instead, and does not grow if that fails too: Eq. 1 then only repeats a node (pulls
  /// that cancel but for a remainder pointing back along the vein) or lays one on a segment that growth
  /// stretched, and drawing that segment twice is no progress. Returns the cumulative report.
  const ColonisationReport& step();
  /// True once the report says finished, stalled or hit a limit.
  bool done() const;
  /// Steps until done(). Throws core::Cancelled if `progress` returns false.
  const ColonisationReport& run(const ColonisationProgress& progress = {});

  /// The vein graph in the grown leaf's frame (copies and scales the nodes for uniform growth).
  VeinTree tree() const;
  /// Alive sources, same frame.
  std::vector<Vec3> sources() const;
  /// The current blade outline, same frame (empty for a 3-D domain).
  Outline outline() const;
  const ColonisationReport& report() const;
  /// Alive sources whose neighbourhood is followed lazily (ColonisationParams::lazy_sectors): for tests
  /// and benchmarks.
  std::size_t lazy_sources() const;

  /// The state after the steps so far, for checkpoints: vein nodes, anastomoses, sources (with their
  /// tags and material coordinates), the per-source neighbourhood state, the random-number state, the
  /// growth (sigma, growth steps), the settle counter and the report, as a chunk file (core/chunk_file.h,
  /// kind "COLO") with a checksum and fingerprints of the parameters and the domain.
  std::string save() const;
  /// Continues a state from save(): the steps that follow are bit-identical to those of the run that
  /// saved it, for any thread count. `params` and `domain` must be those it was saved with, except
  /// threads, max_steps, max_nodes and max_sources (the limits are applied anew: a run stopped by max_steps goes on
  /// under a larger one). Throws core::InvalidInput naming what differs (wrong domain or parameters)
  /// and core::FileError naming `what` for bytes that are not such a state or are corrupt.
  static Colonisation load(const Domain& domain, const ColonisationParams& params, const std::string& bytes,
                           const std::string& what = "colonisation state");
  /// As above, for a state saved by a Colonisation made from a Leaf.
  static Colonisation load(const Leaf& leaf, const ColonisationParams& params, const std::string& bytes,
                           const std::string& what = "colonisation state");

 private:
  void restore(const std::string& bytes, const std::string& what);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-off run: a Colonisation stepped until done. Returns the tree and the report.
std::pair<VeinTree, ColonisationReport> colonise(const Leaf& leaf, const ColonisationParams& params,
                                                 const ColonisationProgress& progress = {});

/// One-off run in any source domain (domain.h).
std::pair<VeinTree, ColonisationReport> colonise(const Domain& domain, const ColonisationParams& params,
                                                 const ColonisationProgress& progress = {});

/// Vein widths by Murray's law (Section 3.5).
struct WidthParams {
  double exponent = 2;       ///< n in r_parent^n = sum r_child^n (Table 1: 2, developmental model 3)
  double tip_radius = 0.1;   ///< model units: radius of a free vein end (veinlet)
  double per_node_flow = 0;  ///< extra r^n each node adds, in units of tip_radius^n: widens low orders
                             ///< to stand in for veinlets not modelled (Section 3.5); 0 = pure Murray
};

/// Fills tree.flow, tree.radius and tree.order once, from the tips to the base: flow(v) = tip flow at a
/// tip, else sum of the children's flows (+ per_node_flow), radius = flow^(1/n) * tip_radius, so
/// r_parent^n = sum r_child^n holds at every branching. Every child entering a node contributes equally
/// by its own flow (closed patterns); anastomosis edges carry no flow (the files draw and print them at the
/// radius of the finer vein they join). Order: seeds
/// start at 1, at each node the child with the largest flow (ties: smaller index) keeps the order, the
/// others get order + 1. Throws core::InvalidInput for exponent or tip_radius not positive.
void compute_widths(VeinTree& tree, const WidthParams& params);

/// Independent cycles of the vein graph (its cyclomatic number, edges - nodes + components): the loops a
/// closed pattern made, not counting anastomoses that joined the trees of two seeds into one.
std::size_t independent_cycles(const VeinTree& tree);

/// `tree` with a stem to each root from its anchor (anchors[k] for the k-th root in index order, that is
/// the k-th seed) where they lie more than `min_length` (model units) apart: a seed moved onto a surface
/// from where it stands (a support cell off the grown sheet) is joined to it. The stems' nodes come first
/// (parents before children, as compute_widths needs), seed step 0; widths are computed after. Throws
/// core::InvalidInput when the anchors are not one per root.
VeinTree with_stems(const VeinTree& tree, const std::vector<Vec3>& anchors, double min_length);

}  // namespace cellform::venation
