// Private to venation/: the state of a Colonisation (Colonisation::Impl), shared by colonisation.cpp,
// which defines its longer members (the step and its parts), and colonisation_state.cpp (checkpoints:
// save() and load()). Not installed, not for users.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "core/errors.h"
#include "core/parallel.h"
#include "core/random.h"
#include "venation/colonisation.h"
#include "venation/dart_grid.h"
#include "venation/domain.h"
#include "venation/marginal_sources.h"

namespace cellform::venation {

namespace detail {

inline Vec3 lift(const Vec2& p) { return Vec3(p.x(), p.y(), 0.0); }

/// Lazy sector mode (Sectors below): the margin bound after a step. Before it, every node v but the
/// anchor a had |v - s| - |v - a| >= slack. The step placed nodes at most `placed` from an older node,
/// and the nearest node to s is now a' at distance r0, `moved` from a. Then every node w but a' has
/// |w - s| - |w - a'| >= the result (model units), less `tol` for rounding:
///  - an older node: its margin falls by at most `moved` (|w - a'| <= |w - a| + moved);
///  - a node placed from an older v other than a: at most `placed` nearer s and `placed` farther from a',
///    so slack - 2 placed - moved;
///  - a itself and a node placed from a: at least r0 from s (a' is the nearest) and at most
///    placed + moved from a', so r0 - placed - moved. (Never the smaller while slack <= |a - s|, which
///    holds for any margin by the triangle inequality, since r0 >= |a - s| - placed; kept as the direct
///    bound.) tests/venation/colonisation_test.cpp checks the result against brute force.
inline double lazy_slack_after(double slack, double r0, double placed, double moved, double tol) {
  return std::min(slack - 2 * placed - moved, r0 - placed - moved) - tol;
}

/// Alive sources hashed by grid cell, for the birth-distance test of new darts.
class SourceGrid {
 public:
  void reset(double cell) {
    cell_ = cell;
    cells_.clear();
  }
  double cell() const { return cell_; }
  void insert(Index i, const Vec3& p) {
    planar_ = planar_ && p.z() == 0;
    cells_[key(cx(p.x()), cx(p.y()), cx(p.z()))].push_back(i);
  }
  void erase(Index i, const Vec3& p) {
    auto it = cells_.find(key(cx(p.x()), cx(p.y()), cx(p.z())));
    auto& v = it->second;
    v.erase(std::find(v.begin(), v.end(), i));
    if (v.empty()) cells_.erase(it);
  }
  /// Any source within squared distance r2 (r <= cell size) of p.
  bool any_within(const Vec3& p, double r2, const std::vector<Vec3>& pos) const {
    const long x = cx(p.x()), y = cx(p.y()), z = cx(p.z());
    const long dz_max = planar_ && p.z() == 0 ? 0 : 1;  // leaves: every point has z = 0
    for (long dz = -dz_max; dz <= dz_max; ++dz)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dx = -1; dx <= 1; ++dx) {
          auto it = cells_.find(key(x + dx, y + dy, z + dz));
          if (it == cells_.end()) continue;
          for (Index i : it->second)
            if ((pos[i] - p).squaredNorm() <= r2) return true;
        }
    return false;
  }

 private:
  // clamped, so that no coordinate and cell size (a birth distance of 1e-300, say) overflows a long; far
  // points then share a cell, which costs time but not exactness (any_within compares distances)
  long cx(double v) const {
    constexpr double kMax = 0x1p40;
    const double f = std::floor(v / cell_);
    return f >= kMax    ? static_cast<long>(kMax)
           : f <= -kMax ? -static_cast<long>(kMax)
           : f == f     ? static_cast<long>(f)
                        : 0;
  }
  static std::uint64_t key(long x, long y, long z) {
    return core::mix64(static_cast<std::uint64_t>(x) * 0x9e3779b1ull ^ static_cast<std::uint64_t>(y) * 0x85ebca77ull ^
                       static_cast<std::uint64_t>(z) * 0xc2b2ae3dull);
  }
  double cell_ = 1;
  bool planar_ = true;
  std::unordered_map<std::uint64_t, std::vector<Index>> cells_;
};

// Absurd sizes are refused before they exhaust memory or overflow: a step's darts are held at once
// (about 60 bytes each), and a nonuniform growth factor beyond this makes coordinates meaningless.
inline constexpr double kMaxDartsPerStep = 2e7;
inline constexpr double kMaxNonuniformGrowth = 1e6;
/// cos 5 degrees: a new node whose segment runs closer than this to one of its parent's segments retraces it.
inline constexpr double kRetraceCos = 0.99619469809174553;

/// Throws naming colonisation.darts if `expected` darts (rho times `what`, at `step` if not 0) would be
/// thrown in one step.
inline void check_darts_per_step(double expected, const char* what, std::size_t step = 0) {
  if (!(expected <= kMaxDartsPerStep))
    throw core::InvalidInput(std::string("colonisation.darts: rho x ") + what +
                             (step ? " at step " + std::to_string(step) : std::string()) + " = " +
                             core::number_text(expected) +
                             " darts in one step, more than 2 x 10^7; use fewer darts (rho x 10^6 per unit " +
                             (std::string_view(what).find("volume") != std::string_view::npos ? "volume" : "area") +
                             ") or a smaller domain");
}

/// The nodes that reached one closed-pattern source (positions `at`, in index order) are joined where they lie
/// within `reach` of each other (model units), once: the pairs (j, i), j < i within reach, i then j ascending,
/// that join two groups not yet joined (a spanning forest of the "within reach" graph; when all lie within
/// reach of the first node, a star from it).
inline std::vector<std::pair<std::size_t, std::size_t>> closing_pairs(const std::vector<Vec3>& at, double reach) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  std::vector<std::size_t> group(at.size());
  for (std::size_t i = 0; i < at.size(); ++i) group[i] = i;
  for (std::size_t i = 1; i < at.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      if (group[i] == group[j] || (at[i] - at[j]).squaredNorm() > reach * reach) continue;
      out.emplace_back(j, i);
      const std::size_t from = group[i], to = group[j];
      for (std::size_t& g : group) g = g == from ? to : g;
    }
  return out;
}

}  // namespace detail

struct Colonisation::Impl {
  Leaf leaf;
  ColonisationParams p;
  OutlineIndex unit;  // outline at scale 1
  Vec3 petiole;

  PointTree nodes;
  std::vector<Index> parent;
  std::vector<Index> first_child, next_sibling;  // children lists, to refuse retracing nodes
  std::vector<std::uint32_t> birth;
  std::vector<std::pair<Index, Index>> anastomoses;
  std::unordered_set<std::uint64_t> loop_keys;  // anastomoses as loop_key(a, b): each joins a pair once
  static std::uint64_t loop_key(Index a, Index b) {
    return static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b);
  }

  std::vector<Vec3> src;
  std::vector<char> alive, tagged;
  std::vector<Index> active;  // alive sources, increasing index
  std::vector<Index> near;    // per source: nearest vein node so far (a cache: nodes never move)
  std::vector<double> near_d2;
  std::vector<std::vector<Index>> tags, reached;  // closed: tagged veins, veins that reached
  detail::SourceGrid grid;

  core::Rng rng;
  double sigma;
  // nonuniform growth (Appendix A): material coordinates (relative to the petiole at t_0), the number
  // of growth steps applied, a table of Eq. 4 on a uniform grid of y_0, the current blade
  bool nonuniform = false;
  std::size_t grown = 0;
  std::vector<Vec2> node_mat, src_mat;
  double table_y0 = 0, table_dy = 1;
  std::vector<double> table_y;  // y_t(y_0) at the grid heights
  OutlineIndex current;
  // marginal growth (Section 3.3): sources precomputed once over the final blade, revealed at the step
  // whose blade first contains them (the step number says which have been: nothing else to save)
  bool marginal = false;
  MarginalSources precomputed;
  std::size_t quiet = 0;        // steps in a row, growth over, that changed nothing
  std::size_t quiet_darts = 0;  // darts thrown over those steps
  ColonisationReport rep;

  // Closed, exact, in the plane: per source the nearest node of each 60-degree sector and whether its
  // lune is occupied. Nodes never move or vanish, so a node once excluded stays excluded, and V(s) of
  // the next step is found among these bests after merging in only the nodes added since (time
  // coherence, Section 5); the result equals a fresh PointTree::relative_neighbourhood().
  struct Sectors {
    Index best[6];
    double d2[6];
    bool blocked[6];
    bool ready = false;
    // Lazy mode (exact, closed, planar, nodes that never move): while every node other than the
    // nearest, `anchor`, is provably nearer to it than to the source (PointTree::min_margin > 0), the
    // anchor excludes them all and V(s) = {nearest}, so the bests above are left stale (ready = false)
    // and only the nearest is followed. `slack` is a lower bound of that margin, spent each step by
    // the anchor's move and by the nodes placed (each D from its parent); the mode ends when it runs out.
    bool lazy = false;
    std::uint8_t backoff = 0;  // failed tries to enter lazy mode in a row; the next try waits 2^backoff steps
    std::uint32_t retry = 0;   // step from which entering lazy mode is tried again
    Index anchor = kNoIndex;
    double slack = 0;  // model units
  };
  std::vector<Sectors> sectors;

  // Closed, Urquhart: per source its Voronoi cell among the nodes and the Urquhart neighbourhood that
  // cell gives. Like the sectors, a cell is kept and clipped only by the nodes added since.
  struct Urquhart {
    VoronoiCell cell;
    std::vector<Index> out;  // the Urquhart neighbourhood of the cell as it is
    double window = 0;       // half side of the square the cell was clipped from
    bool ready = false;
  };
  std::vector<Urquhart> urq;  // per source; empty unless closed Urquhart
  struct UrquhartScratch {
    std::vector<std::pair<double, Index>> hits;
    std::vector<VoronoiCell::Vertex> verts;
    std::vector<Index> dn;
  };
  Index synced = 0;      // nodes [0, synced) are merged into every ready Sectors and every near[s]
  double step_D = 0;     // the segment length of this step (model units)
  double last_D = 0;     // the segment length of the last node placement (model units)
  double lazy_tol = 0;   // rounding allowance for the lazy-mode margins (model units), set each step
  bool lazy_ok = false;  // lazy sector mode allowed this step
  PointBatch fresh;      // nodes [fresh_first, fresh_last), indexed once for all sources
  Index fresh_first = 0, fresh_last = 0;

  std::vector<std::vector<Index>> per_source;  // V(s) of the i-th active source this step
  std::vector<std::vector<Vec3>> per_dir;      // unit vectors from those nodes to the source (NaN: none)
  std::vector<Vec3> infl_dir;                  // per_dir flattened like infl
  std::vector<char> seen;                      // per node: already in `touched` this step
  std::vector<Index> nb, infl_start, infl, touched, child;
  std::vector<Vec3> acc;
  std::vector<Index> pull_source;  // per node (leaf): its nearest influencing source this step (kNoIndex: none)
  std::vector<double> pull_d2;     // its squared distance

  // 3-D domains (domain.h): darts from the domain, nodes kept in it, neighbourhoods found in 3-D
  std::optional<PreparedDomain> region;
  std::vector<Vec3> darts;

  // dart throwing scratch (kept across steps): blade candidates, their blade test, the dart tests
  std::vector<Vec3> cand;
  std::vector<std::uint8_t> cand_in, dart_ok, done;  // done: per active source, to be removed
  core::Rng rng_mark{0};
  // leaves: one vein node per grid cell, which rejects most darts of the b_v test without a tree query
  // (never changes an answer: see dart_grid.h); laid out anew when b_v shrinks, dropped when nodes move
  WitnessGrid witness;
  std::size_t witness_cap = 0;  // the cell budget of the last layout
  bool witness_capped = false;  // that budget made the cells coarser than asked
  double witness_cover = 0;     // model units: the radius of the last layout's map of covered cells (0: none)

  Impl(const Leaf& l, const ColonisationParams& params);

  /// A volume or surface: no blade, no growth; seed nodes and sources as given, in model units.
  Impl(const Domain& d, const ColonisationParams& params);

  /// 3-D: the nearest node (last step's is a valid start: nodes never move) and, closed, V(s) by the
  /// exact 3-D relative neighbourhood (the planar sectors do not apply).
  void influence_3d(Index s, std::vector<Index>& out, bool closed, PointTree::Scratch& scratch) {
    nodes.nearest(src[s], near[s], near_d2[s]);
    if (closed) nodes.relative_neighbourhood(src[s], out, scratch);
  }

  /// 3-D: moves the Eq. 1 node q of v into the domain. Where the pulls on v cancel (`cancelled`: Eq. 1 has
  /// no direction) or that node retraces one of v's segments (retraces(): usually sources pulling v apart
  /// made that node already, its child there is farther from each of them than v, so v stays their nearest
  /// node and the step would only repeat), v grows towards its nearest influencing source alone, which
  /// splits the set as in Figure 6k. False if v cannot advance (the projection undoes the step).
  bool place_3d(Index v, Vec3& q, double D, bool cancelled) const;

  /// Eq. 4 at t = grown: y_t(y_0) by the trapezoid rule from 0 (the petiole), on 4097 heights.
  void make_table();
  double table_at(double y0) const {  // linear, extrapolated with the end slopes
    const double u = (y0 - table_y0) / table_dy;
    const auto n = static_cast<double>(table_y.size() - 1);
    const double c = std::clamp(std::floor(u), 0.0, n - 1);
    const auto i = static_cast<std::size_t>(c);
    return table_y[i] + (u - c) * (table_y[i + 1] - table_y[i]);
  }
  double table_inverse(double y) const {
    const auto it = std::upper_bound(table_y.begin() + 1, table_y.end() - 1, y);
    const auto i = static_cast<std::size_t>(it - table_y.begin()) - 1;
    const double f = (y - table_y[i]) / (table_y[i + 1] - table_y[i]);
    return table_y0 + (static_cast<double>(i) + f) * table_dy;
  }
  Vec2 to_current(const Vec2& m) const {
    return leaf.petiole + Vec2(m.x() * std::pow(p.growth_x(m.y()), static_cast<double>(grown)), table_at(m.y()));
  }
  Vec2 to_material(const Vec3& q) const {
    const double y0 = table_inverse(q.y() - leaf.petiole.y());
    return {(q.x() - leaf.petiole.x()) / std::pow(p.growth_x(y0), static_cast<double>(grown)), y0};
  }
  /// One growth step of Appendix A: every node and source moves; indexes and neighbourhoods restart.
  void grow_nonuniform();

  // Uniform growth keeps the blade at sigma_0 and shrinks distances instead (Section 3.3).
  double dist_factor() const { return p.growth == GrowthMode::uniform ? p.initial_scale / sigma : 1.0; }
  // Scale of the outline in the simulation frame.
  double frame_scale() const { return p.growth == GrowthMode::uniform ? p.initial_scale : sigma; }
  bool in_blade(const Vec3& q) const {
    if (nonuniform) return current.contains(Vec2(q.x(), q.y()));
    const Vec3 u = petiole + (q - petiole) / frame_scale();
    return unit.contains(Vec2(u.x(), u.y()));
  }
  /// Whether the vein segment from node position `a` to `q` lies in the blade (under marginal growth the
  /// grown one): q inside, and no cut across a sinus or between teeth (OutlineIndex::segment_inside).
  bool segment_in_blade(const Vec3& a, const Vec3& q) const {
    if (nonuniform) return current.segment_inside(Vec2(a.x(), a.y()), Vec2(q.x(), q.y()));
    const double s = marginal ? std::max(frame_scale(), p.final_scale) : frame_scale();
    const Vec3 ua = petiole + (a - petiole) / s, uq = petiole + (q - petiole) / s;
    return unit.segment_inside(Vec2(ua.x(), ua.y()), Vec2(uq.x(), uq.y()));
  }
  /// Darts that must land in vain, besides settle_steps steps, before a run that grows nothing more ends:
  /// as many as the domain holds b_v discs (balls in a volume), up to kSettleDarts, however few darts a step
  /// throws. (Uncapped, the count kept a large leaf going while a rare dart still found a gap: the poplar at
  /// scale 0.7 ran past 100,000 steps instead of 15,238, for 7% more nodes.) None when no darts come
  /// (marginal growth after the margin has passed every precomputed source, rho = 0, b_v = 0).
  double settle_darts() const;
  bool growth_over() const {
    if (nonuniform) return grown >= p.growth_steps;
    return p.growth == GrowthMode::none || sigma >= p.final_scale;
  }

  Index add_node(const Vec3& q, Index par, std::uint32_t step_no);
  /// add_node for each q[k] with parent par[k], in order (the same indices), inserted as one batch.
  void add_nodes(std::span<const Vec3> q, std::span<const Index> par, std::uint32_t step_no);
  /// The bookkeeping of node id, just appended to `nodes`: witness, parent, birth, children lists.
  void link_node(Index id, Index par, std::uint32_t step_no);
  double reach_far2 = 0;      // reach(): squared distance beyond which no node of the step can be within d_k
  std::vector<Vec3> new_pos;  // step scratch: the nodes of this step, before they enter the tree
  std::vector<Index> new_parent;

  /// True if the segment v -> q would run along one of v's segments (to a child or to its parent),
  /// within kRetraceCos. Eq. 1 then gives a node the vein already has: its child again (the mean
  /// direction points away from the sources, so v stays their nearest node), or a point on a segment that
  /// growth has stretched or on the way back to v's parent. Adding it would loop without progress and
  /// draw that segment twice (a pen plotter or laser cutter goes over it again).
  bool retraces(Index v, const Vec3& q) const {
    const Vec3& from = nodes.point(v);
    const Vec3 u = (q - from).normalized();
    auto along = [&](Index w) { return (nodes.point(w) - from).normalized().dot(u) > detail::kRetraceCos; };
    for (Index c = first_child[v]; c != kNoIndex; c = next_sibling[c])
      if (along(c)) return true;
    return parent[v] != kNoIndex && along(parent[v]);
  }

  void remove_source(Index s) {
    alive[s] = 0;
    if (!urq.empty()) urq[s] = {};
    grid.erase(s, src[s]);
    ++rep.sources_removed;
  }

  /// Darts of this step (Section 3.1): drawn from the RNG in order, tested against the blade and the
  /// vein nodes in parallel (independent per dart), then against the sources one by one in draw order,
  /// so that a dart sees the darts accepted before it. Same bits for any thread count. False, with nothing
  /// changed (the RNG and the report as before), if more than max_sources would wait: each source holds
  /// about a kilobyte by the end of a step, and one step of a large blade that does not grow can accept
  /// millions of darts.
  bool throw_darts(double bs2, double bv2);

  /// Lays the witness grid out anew (cells of 0.7 b_v, all nodes offered in index order) when it is
  /// missing, does not cover the blade (with a margin of b_v) or its cells are coarser than b_v (isogonic
  /// growth shrinks b_v). At most 8 cells per node (at least 2^20): memory stays linear in nodes; a grid
  /// coarsened by that budget is laid out again once the budget has doubled. Leaves only.
  void update_witness(double bv);

  /// Blade darts: floor(rho A) (plus one with probability of the remainder) uniform points of the blade,
  /// each by rejection from its bounding box. The candidates cost two draws each whatever the blade test
  /// says, so they are drawn in batches, tested in parallel, and the RNG is then set to just after the
  /// last candidate used: the darts and the RNG state are those of drawing and testing one at a time.
  void draw_blade_darts();

  /// Marginal growth: the precomputed sources that the blade of this step first contains (Section 3.3),
  /// each kept if, like a dart (Figure 6i-j), it is farther than b_s from every source and than b_v from
  /// every vein node. A rejected one is dropped for good, as a dart is: nodes never go away, and the
  /// precomputed sources are b_s apart already. Tested in parallel, added in order: same bits for any
  /// thread count. Each counts as a dart.
  void reveal_sources(double bs2, double bv2);

  void add_source(const Vec3& q);
  /// Undoes add_source() for the sources from index `first` on (the last ones added, still alive): their
  /// state, grid entries and count born; `active` goes back to its first `active_before` entries.
  void drop_sources_from(std::size_t first, std::size_t active_before);

  bool urquhart() const { return p.type == VenationType::closed && p.neighbourhood == Neighbourhood::urquhart; }

  /// Closed, Urquhart: brings the Voronoi cell of source s up to date with nodes [synced, size) (indexed
  /// by `fresh`: only those within twice the cell's radius can clip it) and writes its Urquhart
  /// neighbourhood to `out`. A new cell is clipped from a square of half side `window` by at most the
  /// 48 nearest nodes. Touches only this source's state.
  void urquhart_update(Index s, std::vector<Index>& out, double window, PointTree::Scratch& scratch,
                       UrquhartScratch& us);

  bool influenced_by(std::size_t a, Index v) const {
    for (Index k = infl_start[a]; k < infl_start[a + 1]; ++k)
      if (infl[k] == v) return true;
    return false;
  }

  // Veins that reached s join (anastomose) if their tips met: within 3 D of each other. With a kill
  // distance much larger than D the tips stay apart and end free, as in Figure 9a.
  void close_source(Index s, double D);

  /// PointTree::lune_occupied(q, best[k]) of source state st, trying first the other sectors' bests
  /// (the blocker is usually one of them; same squared distances, so the same answer).
  bool lune_blocked(const Sectors& st, const Vec3& q, int k) const {
    const Vec3& v = nodes.point(st.best[k]);
    for (int j = 0; j < 6; ++j)
      if (j != k && st.best[j] != kNoIndex && st.d2[j] <= st.d2[k] &&
          (nodes.point(st.best[j]) - v).squaredNorm() <= st.d2[k])
        return true;
    return nodes.lune_occupied(q, st.best[k]);
  }

  /// Brings the sector state of source s up to date with nodes [synced, size) (indexed by `fresh`) and
  /// sets near[s]. Closed: writes V(s) (Eq. 2) to `out`, equal to PointTree::relative_neighbourhood().
  void sector_update(Index s, std::vector<Index>& out, bool closed, PointTree::Scratch& scratch);

  static constexpr double kSettleDarts = 1000;  // settle_darts() at most
  // Lazy mode proves a margin of kLazyMargin D (a step spends 2 D plus the nearest node's move, about 3 D) and proves
  // it again, for the nearest node then, when less than kLazyRenew D is left.
  static constexpr double kLazyMargin = 30;
  static constexpr double kLazyRenew = 6;

  /// The rounding allowance of lazy margins at source position q: differences of coordinates as large
  /// as q's round by about 1e-16 of them (model units).
  double tolerance(const Vec3& q) const { return lazy_tol + 1e-9 * q.cwiseAbs().maxCoeff(); }

  /// Puts source s, whose V(s) is {near[s]}, into lazy mode if the margin holds; else waits before the
  /// next try (twice as long after each failure, at most 64 steps).
  void try_lazy(Index s, Sectors& st);

  /// Lazy mode, one step: follows the nearest node through the nodes added since (ties detected) and
  /// spends the margin. For a node v other than the anchor n: |v - n'| <= |v - n| + |n - n'|, and a node
  /// placed D from its parent u has |p - s| >= |u - s| - D and |p - n'| <= |u - n'| + D; a child of n
  /// itself has |p - s| >= r0' and |p - n'| <= D + |n - n'|. True if V(s) is still {near[s]}.
  bool lazy_step(Index s, Sectors& st);

  /// Indexes the nodes [synced, size) in `fresh` unless it holds them already.
  void sync_fresh() {
    const auto n = static_cast<Index>(nodes.size());
    if (fresh_first == synced && fresh_last == n) return;
    fresh.assign(std::span<const Vec3>(nodes.points()).subspan(synced), synced);
    fresh_first = synced;
    fresh_last = n;
  }

  /// Open and Urquhart patterns need only near[s]: the last nearest node is the candidate, so only the
  /// nodes added since are searched.
  void nearest_update(Index s) {
    if (near[s] == kNoIndex)
      nodes.nearest(src[s], near[s], near_d2[s]);
    else
      fresh.nearest(src[s], near[s], near_d2[s]);
  }

  /// Step 4 for the a-th active source after the new nodes are in: its nearest node, and, closed, its
  /// tags passed on or turned into reached veins. True if the source is to be removed (open: reached;
  /// closed: every tag reached or gone). Touches only this source's state.
  bool reach(std::size_t a, bool closed, double dk2);

  void step();

  Vec3 to_output(const Vec3& q) const {
    return p.growth == GrowthMode::uniform ? Vec3(petiole + (q - petiole) * (sigma / p.initial_scale)) : q;
  }
};

}  // namespace cellform::venation
