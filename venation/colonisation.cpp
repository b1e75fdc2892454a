// Space-colonisation venation (Runions et al. 2005): dart throwing, Eq. 1 growth, open and closed removal.
#include "venation/colonisation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>

#include "core/chunk_file.h"
#include "core/errors.h"
#include "core/parallel.h"
#include "core/random.h"
#include "venation/dart_grid.h"
#include "venation/domain.h"
#include "venation/marginal_sources.h"

namespace cellform::venation {

using core::InvalidInput;

namespace {

void require_distance(double v, const char* name) {
  if (!(v > 0 && std::isfinite(v)))
    throw InvalidInput(std::string("colonisation.") + name +
                       " must be a positive, finite distance in model units, got " + std::to_string(v));
}

Vec3 lift(const Vec2& p) { return Vec3(p.x(), p.y(), 0.0); }

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
  long cx(double v) const { return static_cast<long>(std::floor(v / cell_)); }
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
constexpr double kMaxDartsPerStep = 2e7;
constexpr double kMaxNonuniformGrowth = 1e6;

using core::number_text;

/// Throws naming colonisation.darts if `expected` darts (rho times `what`, at `step` if not 0) would be
/// thrown in one step.
void check_darts_per_step(double expected, const char* what, std::size_t step = 0) {
  if (!(expected <= kMaxDartsPerStep))
    throw InvalidInput(std::string("colonisation.darts: rho x ") + what +
                       (step ? " at step " + std::to_string(step) : std::string()) + " = " + number_text(expected) +
                       " darts in one step, more than 2 x 10^7; use fewer darts (rho x 10^6 per unit area) or a "
                       "smaller domain");
}

}  // namespace

void validate(const ColonisationParams& p) {
  require_distance(p.source_birth_distance, "source_birth_distance");
  require_distance(p.vein_birth_distance, "vein_birth_distance");
  require_distance(p.kill_distance, "kill_distance");
  require_distance(p.node_distance, "node_distance");
  if (!(p.darts_per_area >= 0 && std::isfinite(p.darts_per_area)))
    throw InvalidInput("colonisation.darts_per_area must be a finite number >= 0 of darts per unit area per step");
  if (p.kill_distance < 0.5 * p.node_distance)
    throw InvalidInput("colonisation.kill_distance (" + number_text(p.kill_distance) +
                       ") must be at least half of colonisation.node_distance (" + number_text(p.node_distance) +
                       "): otherwise a vein tip can step over a source and circle around it forever");
  if (!(p.initial_scale > 0 && std::isfinite(p.initial_scale)))
    throw InvalidInput("colonisation.initial_scale must be a positive, finite scale factor");
  if (p.growth == GrowthMode::nonuniform) {
    if (p.growth_steps == 0) throw InvalidInput("colonisation.growth_steps must be at least 1 for nonuniform growth");
    for (const auto& [f, name] : {std::pair{&p.growth_x, "growth_x"}, std::pair{&p.growth_y, "growth_y"}}) {
      const std::string n = std::string("colonisation.") + name;
      if (f->y.empty() || f->y.size() != f->rate.size())
        throw InvalidInput(n + " needs as many rates as heights, at least one (a lookup table y -> REG)");
      for (std::size_t i = 0; i < f->y.size(); ++i) {
        if (!std::isfinite(f->y[i]) || !(f->rate[i] > 0 && std::isfinite(f->rate[i])))
          throw InvalidInput(n + ": entry " + std::to_string(i + 1) + " needs a finite height and a finite rate > 0");
        if (i > 0 && !(f->y[i] > f->y[i - 1]))
          throw InvalidInput(n + ".y must increase strictly (entry " + std::to_string(i + 1) +
                             " is not above the one before): the lookup table must be monotone in y");
      }
      const double top = *std::max_element(f->rate.begin(), f->rate.end());
      if (std::log(top) * static_cast<double>(p.growth_steps) > std::log(kMaxNonuniformGrowth))
        throw InvalidInput(n + ": a rate of " + number_text(top) +
                           " per step over colonisation.growth_steps = " + std::to_string(p.growth_steps) +
                           " would grow the leaf more than a millionfold along that axis; use rates nearer 1 or "
                           "fewer steps");
    }
  } else if (p.growth != GrowthMode::none) {
    if (!(p.final_scale >= p.initial_scale && std::isfinite(p.final_scale)))
      throw InvalidInput("colonisation.final_scale must be finite and at least colonisation.initial_scale");
    if (!(p.scale_step > 0 && std::isfinite(p.scale_step)))
      throw InvalidInput(
          "colonisation.scale_step must be a positive increase of the leaf size per step when the leaf grows");
  }
  if (p.max_steps == 0) throw InvalidInput("colonisation.max_steps must be at least 1");
  if (p.threads < 0) throw InvalidInput("colonisation.threads must be >= 0 (0 = all cores)");
  if (p.settle_steps == 0) throw InvalidInput("colonisation.settle_steps must be at least 1");
}

double GrowthFunction::operator()(double y0) const {
  if (y0 <= y.front()) return rate.front();
  if (y0 >= y.back()) return rate.back();
  const auto i = static_cast<std::size_t>(std::upper_bound(y.begin(), y.end(), y0) - y.begin());
  const double t = (y0 - y[i - 1]) / (y[i] - y[i - 1]);
  return rate[i - 1] + t * (rate[i] - rate[i - 1]);
}

void validate(const Leaf& leaf) {
  validate_outline(leaf.outline, "leaf.outline");
  const OutlineIndex index(leaf.outline);
  const double size = (index.hi() - index.lo()).norm();
  auto inside = [&](const Vec2& q) {
    return index.contains(q) || distance_to_boundary(leaf.outline, q) <= 1e-6 * size;
  };
  if (!leaf.petiole.allFinite() || !inside(leaf.petiole))
    throw InvalidInput("leaf.petiole (" + std::to_string(leaf.petiole.x()) + ", " + std::to_string(leaf.petiole.y()) +
                       ") lies outside the blade outline; it must be inside or on it");
  for (std::size_t i = 0; i < leaf.initial_nodes.size(); ++i)
    if (!leaf.initial_nodes[i].allFinite() || !inside(leaf.initial_nodes[i]))
      throw InvalidInput("leaf.initial_nodes[" + std::to_string(i + 1) + "] lies outside the blade outline");
  for (std::size_t i = 0; i < leaf.initial_sources.size(); ++i)
    if (!leaf.initial_sources[i].allFinite() || !inside(leaf.initial_sources[i]))
      throw InvalidInput("leaf.initial_sources[" + std::to_string(i + 1) + "] lies outside the blade outline");
}

std::vector<std::pair<Index, Index>> VeinTree::edges() const {
  std::vector<std::pair<Index, Index>> e;
  for (Index i = 0; i < parent.size(); ++i)
    if (parent[i] != kNoIndex) e.emplace_back(parent[i], i);
  e.insert(e.end(), anastomoses.begin(), anastomoses.end());
  return e;
}

struct Colonisation::Impl {
  Leaf leaf;
  ColonisationParams p;
  OutlineIndex unit;  // outline at scale 1
  Vec3 petiole;

  PointTree nodes;
  std::vector<Index> parent;
  std::vector<Index> first_child, next_sibling;  // children lists, to refuse duplicate nodes
  std::vector<std::uint32_t> birth;
  std::vector<std::pair<Index, Index>> anastomoses;

  std::vector<Vec3> src;
  std::vector<char> alive, tagged;
  std::vector<Index> active;  // alive sources, increasing index
  std::vector<Index> near;    // per source: nearest vein node so far (a cache: nodes never move)
  std::vector<double> near_d2;
  std::vector<std::vector<Index>> tags, reached;  // closed: tagged veins, veins that reached
  SourceGrid grid;

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
  std::size_t quiet = 0;
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

  Impl(const Leaf& l, const ColonisationParams& params) : leaf(l), p(params), unit(l.outline), rng(params.seed) {
    petiole = lift(leaf.petiole);
    sigma = p.initial_scale;
    nonuniform = p.growth == GrowthMode::nonuniform;
    if (p.growth == GrowthMode::none || p.growth == GrowthMode::uniform) {  // the largest blade is known now
      const double top = std::max(p.initial_scale, p.growth == GrowthMode::none ? 0.0 : p.final_scale);
      check_darts_per_step(p.darts_per_area * unit.area() * top * top, "the blade's area");
    }
    if (nonuniform) {
      table_y0 = (unit.lo().y() - leaf.petiole.y()) * p.initial_scale;
      const double extent = (unit.hi().y() - unit.lo().y()) * p.initial_scale;
      table_y0 -= 0.25 * extent;  // veins may stray a little outside the blade
      table_dy = 1.5 * extent / 4096;
      make_table();
    }
    marginal = p.growth == GrowthMode::marginal;
    if (marginal)
      precomputed = precompute_marginal_sources(leaf.outline, leaf.petiole,
                                                marginal_scales(p.initial_scale, p.final_scale, p.scale_step),
                                                {.birth_distance = p.source_birth_distance,
                                                 .darts_per_area = p.darts_per_area,
                                                 .seed = p.seed,
                                                 .threads = p.threads});
    std::vector<Vec2> seeds = leaf.initial_nodes;
    if (seeds.empty()) seeds.push_back(leaf.petiole);
    for (const Vec2& s : seeds) add_node(petiole + p.initial_scale * (lift(s) - petiole), kNoIndex, 0);
    grid.reset(p.source_birth_distance * dist_factor());
    for (const Vec2& s : leaf.initial_sources) add_source(petiole + p.initial_scale * (lift(s) - petiole));
    rep.scale = sigma;
    rep.nodes = nodes.size();
  }

  /// A volume or surface: no blade, no growth; seed nodes and sources as given, in model units.
  Impl(const Domain& d, const ColonisationParams& params) : p(params), rng(params.seed), region(std::in_place, d) {
    petiole = Vec3::Zero();
    sigma = 1;
    check_darts_per_step(p.darts_per_area * region->dart_measure(),
                         d.kind == DomainKind::surface ? "the surface's area" : "the volume of the domain's box");
    for (const Vec3& s : d.initial_nodes) add_node(s, kNoIndex, 0);
    grid.reset(p.source_birth_distance);
    for (const Vec3& s : d.initial_sources) add_source(s);
    rep.nodes = nodes.size();
  }

  /// 3-D: the nearest node (last step's is a valid start: nodes never move) and, closed, V(s) by the
  /// exact 3-D relative neighbourhood (the planar sectors do not apply).
  void influence_3d(Index s, std::vector<Index>& out, bool closed, PointTree::Scratch& scratch) {
    nodes.nearest(src[s], near[s], near_d2[s]);
    if (closed) nodes.relative_neighbourhood(src[s], out, scratch);
  }

  /// 3-D: moves the Eq. 1 node q of v into the domain. Where sources pulling v apart made that node
  /// already (its child there is farther from each of them than v, so v stays their nearest node and
  /// the step would only repeat), v grows towards its nearest influencing source alone, which splits
  /// the set as in Figure 6k. False if v cannot advance (the projection undoes the step).
  bool place_3d(Index v, Vec3& q, double D) const {
    const Vec3& from = nodes.point(v);
    q = region->project(q);
    if (has_child_at(v, q, D)) {
      Index best = kNoIndex;
      double best_d2 = 0;
      for (std::size_t a = 0; a < active.size(); ++a) {
        const Index s = active[a];
        const double d2 = (src[s] - from).squaredNorm();
        if (influenced_by(a, v) && (best == kNoIndex || d2 < best_d2)) {
          best = s;
          best_d2 = d2;
        }
      }
      if (best == kNoIndex) return false;
      q = region->project(from + D * (src[best] - from) / std::sqrt(best_d2));
    }
    return (q - from).squaredNorm() >= 0.01 * D * D;
  }

  /// Eq. 4 at t = grown: y_t(y_0) by the trapezoid rule from 0 (the petiole), on 4097 heights.
  void make_table() {
    const auto t = static_cast<double>(grown);
    table_y.assign(4097, 0.0);
    for (std::size_t i = 1; i < table_y.size(); ++i) {
      const double a = table_y0 + static_cast<double>(i - 1) * table_dy, b = a + table_dy;
      table_y[i] = table_y[i - 1] + 0.5 * table_dy * (std::pow(p.growth_y(a), t) + std::pow(p.growth_y(b), t));
    }
    const double zero = table_at(0.0);
    for (double& v : table_y) v -= zero;
    Outline o = leaf.outline;
    for (Vec2& q : o.points) q = to_current(p.initial_scale * (q - leaf.petiole));
    current = OutlineIndex(o);
  }
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
  void grow_nonuniform() {
    ++grown;
    make_table();
    std::vector<Vec3> moved(nodes.size());
    for (std::size_t i = 0; i < moved.size(); ++i) moved[i] = lift(to_current(node_mat[i]));
    nodes.assign(moved);
    witness.clear();  // laid out again, with the nodes where they are now, by the next darts
    synced = static_cast<Index>(nodes.size());
    fresh.assign({}, synced);
    fresh_first = fresh_last = synced;
    grid.reset(grid.cell());
    for (Index s : active) {
      src[s] = lift(to_current(src_mat[s]));
      grid.insert(s, src[s]);
      near[s] = kNoIndex;
      sectors[s].ready = false;
      sectors[s].lazy = false;
      if (!urq.empty()) urq[s].ready = false;
    }
  }

  // Uniform growth keeps the blade at sigma_0 and shrinks distances instead (Section 3.3).
  double dist_factor() const { return p.growth == GrowthMode::uniform ? p.initial_scale / sigma : 1.0; }
  // Scale of the outline in the simulation frame.
  double frame_scale() const { return p.growth == GrowthMode::uniform ? p.initial_scale : sigma; }
  bool in_blade(const Vec3& q) const {
    if (nonuniform) return current.contains(Vec2(q.x(), q.y()));
    const Vec3 u = petiole + (q - petiole) / frame_scale();
    return unit.contains(Vec2(u.x(), u.y()));
  }
  bool growth_over() const {
    if (nonuniform) return grown >= p.growth_steps;
    return p.growth == GrowthMode::none || sigma >= p.final_scale;
  }

  Index add_node(const Vec3& q, Index par, std::uint32_t step_no) {
    const Index id = nodes.insert(q);
    witness.insert(id, q);
    if (nonuniform) node_mat.push_back(to_material(q));
    parent.push_back(par);
    birth.push_back(step_no);
    first_child.push_back(kNoIndex);
    next_sibling.push_back(kNoIndex);
    if (par != kNoIndex) {
      next_sibling[id] = first_child[par];
      first_child[par] = id;
    }
    return id;
  }

  /// True if v already has a child at q: Eq. 1 then gives the same node again (the mean direction points
  /// away from the sources, so v stays their nearest node), and adding it would loop without progress.
  bool has_child_at(Index v, const Vec3& q, double D) const {
    for (Index c = first_child[v]; c != kNoIndex; c = next_sibling[c])
      if ((nodes.point(c) - q).squaredNorm() < 1e-12 * D * D) return true;
    return false;
  }

  void remove_source(Index s) {
    alive[s] = 0;
    if (!urq.empty()) urq[s] = {};
    grid.erase(s, src[s]);
    ++rep.sources_removed;
  }

  /// Darts of this step (Section 3.1): drawn from the RNG in order, tested against the blade and the
  /// vein nodes in parallel (independent per dart), then against the sources one by one in draw order,
  /// so that a dart sees the darts accepted before it. Same bits for any thread count.
  void throw_darts(double bs2, double bv2) {
    darts.clear();
    if (region)
      region->throw_darts(p.darts_per_area, rng, darts);
    else
      draw_blade_darts();
    dart_ok.resize(darts.size());
    update_witness(std::sqrt(bv2));
    // b_v against every node and b_s against the sources of earlier steps; all pure queries, and a
    // witness node within b_v settles the b_v test as the tree would
    core::parallel_for(
        darts.size(), p.threads,
        [&](std::size_t first, std::size_t last) {
          for (std::size_t d = first; d < last; ++d)
            dart_ok[d] = !witness.witness(darts[d], bv2, nodes.points()) && !grid.any_within(darts[d], bs2, src) &&
                         !nodes.any_within(darts[d], bv2);
        },
        256);
    const std::size_t sources_before = src.size();
    for (std::size_t d = 0; d < darts.size(); ++d) {
      ++rep.darts;
      // a survivor can only be too close to a dart accepted earlier in this step
      if (!dart_ok[d] || (src.size() > sources_before && grid.any_within(darts[d], bs2, src))) continue;
      add_source(darts[d]);
    }
  }

  /// Lays the witness grid out anew (cells of 0.7 b_v, all nodes offered in index order) when it is
  /// missing, does not cover the blade (with a margin of b_v) or its cells are coarser than b_v (isogonic
  /// growth shrinks b_v). At most 8 cells per node (at least 2^20): memory stays linear in nodes; a grid
  /// coarsened by that budget is laid out again once the budget has doubled. Leaves only.
  void update_witness(double bv) {
    if (region || !(bv > 0)) return;  // no b_v test to speed up
    const double fs = p.growth == GrowthMode::marginal ? std::max(frame_scale(), p.final_scale) : frame_scale();
    Vec3 lo = nonuniform ? lift(current.lo()) : Vec3(petiole + fs * (lift(unit.lo()) - petiole));
    Vec3 hi = nonuniform ? lift(current.hi()) : Vec3(petiole + fs * (lift(unit.hi()) - petiole));
    lo -= Vec3(bv, bv, 0);
    hi += Vec3(bv, bv, 0);
    const std::size_t cap = std::max<std::size_t>(std::size_t{1} << 20, 8 * nodes.size());
    bool relayout = !witness.covers(lo, hi);
    if (!relayout && witness.cell() > bv) relayout = !witness_capped || cap >= 2 * witness_cap;
    if (!relayout) return;
    witness.reset(lo, hi, 0.7 * bv, cap);
    witness_cap = cap;
    witness_capped = witness.cell() > 0.7 * bv;
    if (witness.empty()) return;  // no grid could be laid (a blade beyond double range)
    for (Index i = 0; i < nodes.size(); ++i) witness.insert(i, nodes.point(i));
  }

  /// Blade darts: floor(rho A) (plus one with probability of the remainder) uniform points of the blade,
  /// each by rejection from its bounding box. The candidates cost two draws each whatever the blade test
  /// says, so they are drawn in batches, tested in parallel, and the RNG is then set to just after the
  /// last candidate used: the darts and the RNG state are those of drawing and testing one at a time.
  void draw_blade_darts() {
    const double area = nonuniform ? current.area() : unit.area() * sigma * sigma;  // of the actual leaf
    const double expected = p.darts_per_area * area;
    check_darts_per_step(expected, "the blade's area", rep.steps + 1);
    auto count = static_cast<std::size_t>(std::floor(expected));
    if (rng.uniform() < expected - std::floor(expected)) ++count;
    const double fs = frame_scale();
    const Vec3 lo = nonuniform ? lift(current.lo()) : Vec3(petiole + fs * (lift(unit.lo()) - petiole));
    const Vec3 hi = nonuniform ? lift(current.hi()) : Vec3(petiole + fs * (lift(unit.hi()) - petiole));
    if (p.threads == 1) {  // one at a time: nothing drawn in vain, nothing to rewind
      for (std::size_t d = 0; d < count; ++d) {
        Vec3 q;
        do q = Vec3(rng.uniform(lo.x(), hi.x()), rng.uniform(lo.y(), hi.y()), 0.0);
        while (!in_blade(q));
        darts.push_back(q);
      }
      return;
    }
    const double box = (hi.x() - lo.x()) * (hi.y() - lo.y());
    const double inside = box > 0 ? std::clamp(area / box, 0.05, 1.0) : 1.0;  // expected share of candidates kept
    // the first batch is a little short of the expected need (a rewind replays its draws), the rest small
    for (bool opening = true; darts.size() < count; opening = false) {
      const auto need = static_cast<double>(count - darts.size());
      const auto batch = static_cast<std::size_t>(opening ? 0.9 * need / inside : 1.1 * need / inside + 16) + 1;
      rng_mark = rng;
      cand.resize(batch);
      for (Vec3& q : cand) q = Vec3(rng.uniform(lo.x(), hi.x()), rng.uniform(lo.y(), hi.y()), 0.0);
      cand_in.resize(batch);
      core::parallel_for(
          batch, p.threads,
          [&](std::size_t first, std::size_t last) {
            for (std::size_t c = first; c < last; ++c) cand_in[c] = in_blade(cand[c]);
          },
          256);
      std::size_t used = 0;
      while (used < batch && darts.size() < count)
        if (cand_in[used++]) darts.push_back(cand[used - 1]);
      if (used < batch) {  // rewind to just after candidate `used`
        rng = rng_mark;
        for (std::size_t k = 0; k < 2 * used; ++k) rng.next();
      }
    }
  }

  /// Marginal growth: the precomputed sources that the blade of this step first contains (Section 3.3),
  /// each kept if, like a dart (Figure 6i-j), it is farther than b_s from every source and than b_v from
  /// every vein node. A rejected one is dropped for good, as a dart is: nodes never go away, and the
  /// precomputed sources are b_s apart already. Tested in parallel, added in order: same bits for any
  /// thread count. Each counts as a dart.
  void reveal_sources(double bs2, double bv2) {
    const std::span<const Vec2> entering = precomputed.entering(rep.steps);
    darts.clear();
    for (const Vec2& q : entering) darts.push_back(lift(q));
    dart_ok.resize(darts.size());
    core::parallel_for(
        darts.size(), p.threads,
        [&](std::size_t first, std::size_t last) {
          for (std::size_t d = first; d < last; ++d)
            dart_ok[d] = in_blade(darts[d]) && !grid.any_within(darts[d], bs2, src) && !nodes.any_within(darts[d], bv2);
        },
        256);
    for (std::size_t d = 0; d < darts.size(); ++d) {
      ++rep.darts;
      if (dart_ok[d]) add_source(darts[d]);
    }
  }

  void add_source(const Vec3& q) {
    const auto id = static_cast<Index>(src.size());
    src.push_back(q);
    if (nonuniform) src_mat.push_back(to_material(q));
    alive.push_back(1);
    tagged.push_back(0);
    near.push_back(kNoIndex);
    near_d2.push_back(0);
    sectors.emplace_back();
    if (urquhart()) urq.emplace_back();
    if (p.type == VenationType::closed) {
      tags.emplace_back();
      reached.emplace_back();
    }
    grid.insert(id, q);
    active.push_back(id);
    ++rep.sources_born;
  }

  bool urquhart() const { return p.type == VenationType::closed && p.neighbourhood == Neighbourhood::urquhart; }

  /// Closed, Urquhart: brings the Voronoi cell of source s up to date with nodes [synced, size) (indexed
  /// by `fresh`: only those within twice the cell's radius can clip it) and writes its Urquhart
  /// neighbourhood to `out`. A new cell is clipped from a square of half side `window` by at most the
  /// 48 nearest nodes. Touches only this source's state.
  void urquhart_update(Index s, std::vector<Index>& out, double window, PointTree::Scratch& scratch,
                       UrquhartScratch& us) {
    Urquhart& u = urq[s];
    const Vec3& q = src[s];
    bool changed = !u.ready;
    if (!u.ready) {
      nodes.voronoi_cell(q, window, u.cell, scratch, 48);
      u.window = window;
      u.ready = true;
    } else if (fresh.size() > 0 && u.cell.poly.size() >= 3) {
      us.hits.clear();
      fresh.clippers(q, u.cell, us.hits);
      std::sort(us.hits.begin(), us.hits.end());  // by distance, ties by index: as a fresh clipping would
      for (const auto& [d2, v] : us.hits) {
        if (!(d2 > 0)) continue;
        changed |= u.cell.clip(q, nodes.point(v), v, us.verts);
        if (u.cell.poly.size() < 3) break;
      }
    }
    if (changed) {
      u.cell.neighbours(1e-12 * u.window, us.dn);
      nodes.urquhart_filter(q, us.dn, u.out);
    }
    out = u.out;
  }

  bool influenced_by(std::size_t a, Index v) const {
    for (Index k = infl_start[a]; k < infl_start[a + 1]; ++k)
      if (infl[k] == v) return true;
    return false;
  }

  // Veins that reached s join (anastomose) if their tips met: within 3 D of each other. With a kill
  // distance much larger than D the tips stay apart and end free, as in Figure 9a.
  void close_source(Index s, double D) {
    auto& r = reached[s];
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    for (std::size_t i = 1; i < r.size(); ++i) {
      const Index a = r[0], b = r[i];
      if (parent[a] == b || parent[b] == a || (nodes.point(a) - nodes.point(b)).squaredNorm() > 9 * D * D) continue;
      anastomoses.emplace_back(a, b);
      ++rep.loops;
    }
    tags[s].clear();
    tags[s].shrink_to_fit();
    r.clear();
    r.shrink_to_fit();
    remove_source(s);
  }

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
  void sector_update(Index s, std::vector<Index>& out, bool closed, PointTree::Scratch& scratch) {
    if (region) {  // 3-D: no planar sectors
      influence_3d(s, out, closed, scratch);
      return;
    }
    Sectors& st = sectors[s];
    const Vec3& q = src[s];
    if (st.lazy) {
      if (lazy_ok && lazy_step(s, st)) {
        out.assign(1, near[s]);
        return;
      }
      st.lazy = false;  // the margin is spent: a fresh search of the six sectors
      st.ready = false;
    }
    if (!st.ready) {
      nodes.sector_nearest(q, st.best, st.d2, scratch);
      for (int k = 0; k < 6; ++k) st.blocked[k] = st.best[k] == kNoIndex || (closed && lune_blocked(st, q, k));
      st.ready = true;
    } else if (fresh.size() > 0) {
      Index old[6];
      for (int k = 0; k < 6; ++k) old[k] = st.best[k];
      unsigned ties = 0;
      fresh.sector_merge(q, st.best, st.d2, &ties);
      for (int k = 0; k < 6; ++k) {
        if (st.best[k] == kNoIndex || !closed) continue;
        if (st.best[k] != old[k]) {
          // a node in the lune is nearer to s than the new best, or as near (then a new node of the
          // same sector at exactly that distance: `ties`), and the nearest node is the best of its
          // sector: if no other sector has a best that near and there is no tie, the lune is empty
          // without a search. (An old node cannot tie: old nodes of sector k are at least as far as
          // the old best, which a new node replaces only when strictly nearer, new indices being larger.)
          bool maybe = (ties >> k & 1u) != 0;
          for (int j = 1; j <= 5 && !maybe; ++j) maybe = st.d2[(k + j) % 6] <= st.d2[k];
          st.blocked[k] = maybe && lune_blocked(st, q, k);
        } else if (!st.blocked[k])  // only a new node can newly occupy the lune
          st.blocked[k] = fresh.any_in_lune(q, nodes.point(st.best[k]));
      }
    }
    near[s] = kNoIndex;
    for (int k = 0; k < 6; ++k)
      if (st.best[k] != kNoIndex &&
          (near[s] == kNoIndex || st.d2[k] < near_d2[s] || (st.d2[k] == near_d2[s] && st.best[k] < near[s]))) {
        near[s] = st.best[k];
        near_d2[s] = st.d2[k];
      }
    if (!closed) return;
    out.clear();
    for (int k = 0; k < 6; ++k)
      if (!st.blocked[k]) out.push_back(st.best[k]);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    if (lazy_ok && out.size() == 1 && out[0] == near[s] && rep.steps >= st.retry) try_lazy(s, st);
  }

  // Lazy mode proves a margin of kLazyMargin D (each step spends at most 3 D of it) and proves it
  // again, for the nearest node then, when less than kLazyRenew D is left.
  static constexpr double kLazyMargin = 30;
  static constexpr double kLazyRenew = 6;

  /// The rounding allowance of lazy margins at source position q: differences of coordinates as large
  /// as q's round by about 1e-16 of them (model units).
  double tolerance(const Vec3& q) const { return lazy_tol + 1e-9 * q.cwiseAbs().maxCoeff(); }

  /// Puts source s, whose V(s) is {near[s]}, into lazy mode if the margin holds; else waits before the
  /// next try (twice as long after each failure, at most 64 steps).
  void try_lazy(Index s, Sectors& st) {
    const double t = kLazyMargin * step_D;
    if (near_d2[s] > t * t && nodes.margin_at_least(src[s], near[s], t + tolerance(src[s]))) {
      st.lazy = true;
      st.ready = false;
      st.anchor = near[s];
      st.slack = t;
      st.backoff = 0;
    } else {
      st.backoff = static_cast<std::uint8_t>(std::min(st.backoff + 1, 6));
      st.retry = static_cast<std::uint32_t>(rep.steps + (std::size_t{1} << st.backoff));
    }
  }

  /// Lazy mode, one step: follows the nearest node through the nodes added since (ties detected) and
  /// spends the margin. For a node v other than the anchor n: |v - n'| <= |v - n| + |n - n'|, and a node
  /// placed D from its parent u has |p - s| >= |u - s| - D and |p - n'| <= |u - n'| + D; a child of n
  /// itself has |p - s| >= r0' and |p - n'| <= D + |n - n'|. True if V(s) is still {near[s]}.
  bool lazy_step(Index s, Sectors& st) {
    const Vec3& q = src[s];
    near[s] = st.anchor;  // the nearest of the nodes before `fresh` (a removal test may have looked ahead)
    near_d2[s] = (nodes.point(st.anchor) - q).squaredNorm();
    bool tie = false;
    fresh.nearest(q, near[s], near_d2[s], &tie);
    const double moved = (nodes.point(near[s]) - nodes.point(st.anchor)).norm() * (1 + 1e-12);
    const double r0 = std::sqrt(near_d2[s]);
    const double tol = tolerance(q);
    st.slack = std::min(st.slack - 2 * last_D - moved, r0 - last_D - moved) - tol;
    st.anchor = near[s];
    if (tie) return false;
    if (st.slack < kLazyRenew * step_D) {
      const double t = kLazyMargin * step_D;
      if (!(near_d2[s] > t * t && nodes.margin_at_least(q, near[s], t + tol))) return false;
      st.slack = t;
    }
    return st.slack > tol;
  }

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
  bool reach(std::size_t a, bool closed, double dk2) {
    const Index s = active[a];
    if (fresh.any_within(src[s], dk2) || (near[s] != kNoIndex && near_d2[s] <= dk2))
      nodes.nearest(src[s], near[s], near_d2[s]);
    if (!closed) return near_d2[s] < dk2;
    auto reached_now = [&](Index t) { return (nodes.point(t) - src[s]).squaredNorm() < dk2; };
    std::vector<Index>& T = tags[s];
    if (tagged[s]) {
      std::size_t w = 0;
      for (Index t : T) {
        if (reached_now(t)) {
          reached[s].push_back(t);
        } else if (influenced_by(a, t) && child[t] != kNoIndex) {  // the tag passes to the descendant
          if (reached_now(child[t]))
            reached[s].push_back(child[t]);
          else
            T[w++] = child[t];
        }  // else: the vein left the zone of influence of s
      }
      T.resize(w);
    } else if (near_d2[s] < dk2) {
      tagged[s] = 1;
      reached[s].push_back(near[s]);
      for (Index k2 = infl_start[a]; k2 < infl_start[a + 1]; ++k2) {
        const Index v = infl[k2];
        const Index t = child[v] != kNoIndex ? child[v] : v;
        if (reached_now(t))
          reached[s].push_back(t);
        else
          T.push_back(t);
      }
    }
    return tagged[s] && T.empty();
  }

  void step() {
    const double k = dist_factor();
    const double bs = p.source_birth_distance * k;
    if (bs < grid.cell() / 3) {  // uniform growth shrinks b_s: re-hash so queries stay 3 x 3 x 3 cells
      grid.reset(bs);
      for (Index s : active) grid.insert(s, src[s]);
    }
    const double sc = k;  // distances are model units of the actual leaf
    const double bs2 = bs * bs, bv2 = std::pow(p.vein_birth_distance * sc, 2), dk2 = std::pow(p.kill_distance * sc, 2);
    const double D = p.node_distance * sc;
    step_D = D;
    const std::size_t born_before = rep.sources_born, removed_before = rep.sources_removed, nodes_before = nodes.size();

    if (marginal)
      reveal_sources(bs2, bv2);
    else
      throw_darts(bs2, bv2);

    // influence: S(v) for every vein node (Eq. 1 input); open: nearest node; closed: V(s), Eq. 2 and 3
    const bool closed = p.type == VenationType::closed;
    const double half_extent = 4 * ((lift(unit.hi()) - lift(unit.lo())).norm() + 1) * frame_scale();
    // lazy sectors: squared distances of nodes up to 2 half_extent apart round by far less than lazy_tol
    // times the smallest margin accepted (kLazyRenew D)
    lazy_tol = 1e-9 * half_extent;
    lazy_ok = p.lazy_sectors && !nonuniform && !region && D > 1e-5 * half_extent;
    infl_start.assign(1, 0);
    infl.clear();
    sync_fresh();
    const bool exact = closed && p.neighbourhood == Neighbourhood::exact;
    // each source updates only its own state and result slot: any thread count gives the same bits
    if (per_source.size() < active.size()) per_source.resize(active.size());
    if (per_dir.size() < active.size()) per_dir.resize(active.size());
    core::parallel_for(
        active.size(), p.threads,
        [&](std::size_t first, std::size_t last) {
          PointTree::Scratch local;
          UrquhartScratch us;
          for (std::size_t a = first; a < last; ++a) {
            const Index s = active[a];
            std::vector<Index>& out = per_source[a];
            if (exact)
              sector_update(s, out, true, local);
            else
              nearest_update(s);
            if (closed && p.neighbourhood == Neighbourhood::urquhart)
              urquhart_update(s, out, std::min(half_extent, 2 * std::sqrt(near_d2[s]) + 4 * D), local, us);
            // S(v) membership and the unit vector towards s (Eq. 1 terms), here in parallel; NaN: none
            if (!closed)
              out.assign(1, near[s]);
            else  // reached veins stop
              std::erase_if(out, [&](Index v) { return !((nodes.point(v) - src[s]).squaredNorm() >= dk2); });
            std::vector<Vec3>& dir = per_dir[a];
            dir.clear();
            for (Index v : out) {
              const Vec3 d = src[s] - nodes.point(v);
              const double len = d.norm();
              dir.push_back(len > 0 ? Vec3(d / len) : Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
            }
          }
        },
        64);
    infl_dir.clear();
    for (std::size_t a = 0; a < active.size(); ++a) {
      infl.insert(infl.end(), per_source[a].begin(), per_source[a].end());
      infl_dir.insert(infl_dir.end(), per_dir[a].begin(), per_dir[a].end());
      infl_start.push_back(static_cast<Index>(infl.size()));
    }
    synced = static_cast<Index>(nodes.size());
    acc.resize(nodes.size(), Vec3::Zero());
    child.resize(nodes.size(), kNoIndex);
    seen.resize(nodes.size(), 0);
    touched.clear();
    // sums in source order (the same bits for any thread count); each node listed once, then sorted
    for (std::size_t k2 = 0; k2 < infl.size(); ++k2) {
      const Index v = infl[k2];
      if (std::isnan(infl_dir[k2].x())) continue;  // the source sits on the node: no direction
      if (!seen[v]) {
        seen[v] = 1;
        touched.push_back(v);
      }
      acc[v] += infl_dir[k2];
    }
    std::sort(touched.begin(), touched.end());
    for (Index v : touched) seen[v] = 0;
    for (Index v : touched) {
      const Vec3 n = acc[v];
      acc[v].setZero();
      const double len = n.norm();
      if (!(len > 1e-9)) continue;  // opposite sources cancel: no direction (Eq. 1 undefined)
      Vec3 q = nodes.point(v) + D * n / len;
      if (region && !place_3d(v, q, D)) continue;
      if (has_child_at(v, q, D)) continue;
      child[v] = add_node(q, v, static_cast<std::uint32_t>(rep.steps + 1));
    }
    last_D = D;

    // removal (open) or tagging and removal (closed), with the nodes just added. near[s] is the nearest of
    // the nodes [0, synced), so only the new ones are searched for one within d_k; if there is one, the
    // nearest node is taken over all nodes (the last word on distance ties, by index), in a small disc.
    // Each source updates only its own near, tags and reached (in parallel); the removals, which touch
    // the source grid and the anastomoses, follow in source order.
    sync_fresh();
    done.resize(active.size());
    core::parallel_for(
        active.size(), p.threads,
        [&](std::size_t first, std::size_t last) {
          for (std::size_t a = first; a < last; ++a) done[a] = reach(a, closed, dk2);
        },
        256);
    for (std::size_t a = 0; a < active.size(); ++a) {
      if (!done[a]) continue;
      if (closed)
        close_source(active[a], D);
      else
        remove_source(active[a]);
    }
    for (Index v : touched) child[v] = kNoIndex;
    std::erase_if(active, [&](Index s) { return !alive[s]; });

    if (nonuniform) {
      if (grown < p.growth_steps) grow_nonuniform();
    } else if (p.growth != GrowthMode::none && sigma < p.final_scale) {
      sigma = std::min(p.final_scale, sigma + p.scale_step);
    }
    ++rep.steps;
    rep.scale = nonuniform ? static_cast<double>(grown) : sigma;
    rep.nodes = nodes.size();
    rep.sources = active.size();
    const bool changed =
        rep.sources_born != born_before || rep.sources_removed != removed_before || nodes.size() != nodes_before;
    quiet = (growth_over() && !changed) ? quiet + 1 : 0;
    if (quiet >= p.settle_steps) {
      if (active.empty())
        rep.finished = true;
      else
        rep.stalled = true;
    }
    if (rep.steps >= p.max_steps && !rep.finished && !rep.stalled) rep.hit_max_steps = true;
    if (nodes.size() >= p.max_nodes && !rep.finished && !rep.stalled) rep.hit_max_nodes = true;
  }

  Vec3 to_output(const Vec3& q) const {
    return p.growth == GrowthMode::uniform ? Vec3(petiole + (q - petiole) * (sigma / p.initial_scale)) : q;
  }
};

Colonisation::Colonisation(const Leaf& leaf, const ColonisationParams& params) {
  validate(params);
  validate(leaf);
  impl_ = std::make_unique<Impl>(leaf, params);
}
Colonisation::Colonisation(const Domain& domain, const ColonisationParams& params) {
  validate(params);
  validate(domain, params);
  if (domain.kind == DomainKind::leaf) {
    validate(domain.leaf);
    impl_ = std::make_unique<Impl>(domain.leaf, params);
  } else {
    impl_ = std::make_unique<Impl>(domain, params);  // PreparedDomain validates the domain
  }
}
Colonisation::~Colonisation() = default;
Colonisation::Colonisation(Colonisation&&) noexcept = default;
Colonisation& Colonisation::operator=(Colonisation&&) noexcept = default;

const ColonisationReport& Colonisation::step() {
  if (!done()) impl_->step();
  return impl_->rep;
}

bool Colonisation::done() const {
  const auto& r = impl_->rep;
  return r.finished || r.stalled || r.hit_max_steps || r.hit_max_nodes;
}

const ColonisationReport& Colonisation::run(const ColonisationProgress& progress) {
  while (!done()) {
    impl_->step();
    if (progress && !progress(impl_->rep.steps, impl_->rep.nodes)) throw core::Cancelled();
  }
  return impl_->rep;
}

VeinTree Colonisation::tree() const {
  VeinTree t;
  t.positions.reserve(impl_->nodes.size());
  for (const Vec3& q : impl_->nodes.points()) t.positions.push_back(impl_->to_output(q));
  t.parent = impl_->parent;
  t.birth_step = impl_->birth;
  t.anastomoses = impl_->anastomoses;
  return t;
}

std::vector<Vec3> Colonisation::sources() const {
  std::vector<Vec3> out;
  for (Index s : impl_->active) out.push_back(impl_->to_output(impl_->src[s]));
  return out;
}

Outline Colonisation::outline() const {
  if (impl_->region) return {};
  if (impl_->nonuniform) return impl_->current.outline();
  Outline o = impl_->leaf.outline;
  for (Vec2& q : o.points) q = impl_->leaf.petiole + impl_->sigma * (q - impl_->leaf.petiole);
  return o;
}

const ColonisationReport& Colonisation::report() const { return impl_->rep; }

std::size_t Colonisation::lazy_sources() const {
  std::size_t n = 0;
  for (Index s : impl_->active) n += impl_->sectors[s].lazy ? 1 : 0;
  return n;
}

std::pair<VeinTree, ColonisationReport> colonise(const Leaf& leaf, const ColonisationParams& params,
                                                 const ColonisationProgress& progress) {
  Colonisation c(leaf, params);
  c.run(progress);
  return {c.tree(), c.report()};
}

std::pair<VeinTree, ColonisationReport> colonise(const Domain& domain, const ColonisationParams& params,
                                                 const ColonisationProgress& progress) {
  Colonisation c(domain, params);
  c.run(progress);
  return {c.tree(), c.report()};
}

// ---- Checkpoints: save() and load() ----
//
// Saved: everything a later step reads that cannot be recomputed. Rebuilt: the node k-d tree (queries
// are exact with index ties, so they do not depend on how it was built), the children lists (in node
// order, as add_node makes them), the source grid (same cell size, the alive sources), the nonuniform
// Eq. 4 table and blade (from the growth steps done), the marginal growth's precomputed sources (from
// the seed; the steps done say which have been revealed), and the batch of nodes not yet merged into the
// per-source state. That per-source state (nearest node, sector bests and lune flags) is saved as it is:
// rebuilt from scratch it would equal it only up to exact distance ties.

namespace {

constexpr const char* kStateKind = "COLO";
// 2: Urquhart cells; 3: marginal growth reveals precomputed sources; 4: lazy sector modes (a state of
// version 3 loads with every source out of lazy mode: the same results, lazy mode changes only the speed)
constexpr std::uint32_t kStateVersion = 4;

void put_vec3s(core::ByteWriter& w, const std::vector<Vec3>& v) {
  std::vector<double> flat;
  flat.reserve(3 * v.size());
  for (const Vec3& q : v) flat.insert(flat.end(), {q.x(), q.y(), q.z()});
  w.put_vector(flat);
}
std::vector<Vec3> get_vec3s(core::ByteReader& r) {
  const std::vector<double> flat = r.get_vector<double>();
  std::vector<Vec3> v(flat.size() / 3);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = Vec3(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
  return v;
}
void put_vec2s(core::ByteWriter& w, const std::vector<Vec2>& v) {
  std::vector<double> flat;
  flat.reserve(2 * v.size());
  for (const Vec2& q : v) flat.insert(flat.end(), {q.x(), q.y()});
  w.put_vector(flat);
}
std::vector<Vec2> get_vec2s(core::ByteReader& r) {
  const std::vector<double> flat = r.get_vector<double>();
  std::vector<Vec2> v(flat.size() / 2);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = Vec2(flat[2 * i], flat[2 * i + 1]);
  return v;
}
void put_lists(core::ByteWriter& w, const std::vector<std::vector<Index>>& lists) {
  w.put<std::uint64_t>(lists.size());
  for (const auto& l : lists) w.put_vector(l);
}
std::vector<std::vector<Index>> get_lists(core::ByteReader& r) {
  const auto n = r.get<std::uint64_t>();
  std::vector<std::vector<Index>> lists;
  for (std::uint64_t i = 0; i < n; ++i) lists.push_back(r.get_vector<Index>());
  return lists;
}

/// Fingerprint of what the steps depend on in the parameters (not threads, max_steps, max_nodes).
std::uint64_t params_hash(const ColonisationParams& p) {
  core::ByteWriter w;
  for (double v : {p.source_birth_distance, p.vein_birth_distance, p.kill_distance, p.node_distance, p.darts_per_area,
                   p.initial_scale, p.final_scale, p.scale_step})
    w.put(v);
  w.put(static_cast<std::int32_t>(p.type));
  w.put(static_cast<std::int32_t>(p.neighbourhood));
  w.put(static_cast<std::int32_t>(p.growth));
  for (const GrowthFunction* f : {&p.growth_x, &p.growth_y}) {
    w.put_vector(f->y);
    w.put_vector(f->rate);
  }
  w.put<std::uint64_t>(p.growth_steps);
  w.put<std::uint64_t>(p.seed);
  w.put<std::uint64_t>(p.settle_steps);
  const std::string b = w.take();
  return core::fnv1a64(b.data(), b.size());
}

std::uint64_t leaf_hash(const Leaf& l, core::ByteWriter& w) {
  w.put(static_cast<std::int32_t>(DomainKind::leaf));
  put_vec2s(w, l.outline.points);
  put_vec2s(w, {l.petiole});
  put_vec2s(w, l.initial_nodes);
  put_vec2s(w, l.initial_sources);
  const std::string b = w.take();
  return core::fnv1a64(b.data(), b.size());
}

/// Fingerprint of the source domain (a leaf hashes the same whether given as Leaf or as Domain).
std::uint64_t domain_hash(const Domain& d) {
  core::ByteWriter w;
  if (d.kind == DomainKind::leaf) return leaf_hash(d.leaf, w);
  w.put(static_cast<std::int32_t>(d.kind));
  put_vec3s(w, {d.box_min, d.box_max, d.centre});
  w.put(d.radius);
  put_vec3s(w, d.mesh.vertices);
  std::vector<Index> tri;
  for (const auto& t : d.mesh.triangles) tri.insert(tri.end(), t.begin(), t.end());
  w.put_vector(tri);
  put_vec3s(w, d.initial_nodes);
  put_vec3s(w, d.initial_sources);
  const std::string b = w.take();
  return core::fnv1a64(b.data(), b.size());
}

void put_report(core::ByteWriter& w, const ColonisationReport& r) {
  for (std::size_t v : {r.steps, r.nodes, r.sources, r.sources_born, r.sources_removed, r.darts, r.loops})
    w.put<std::uint64_t>(v);
  w.put(r.scale);
  for (bool b : {r.finished, r.stalled, r.hit_max_steps, r.hit_max_nodes}) w.put<std::uint8_t>(b ? 1 : 0);
}
ColonisationReport get_report(core::ByteReader& r) {
  ColonisationReport rep;
  for (std::size_t* v :
       {&rep.steps, &rep.nodes, &rep.sources, &rep.sources_born, &rep.sources_removed, &rep.darts, &rep.loops})
    *v = static_cast<std::size_t>(r.get<std::uint64_t>());
  rep.scale = r.get<double>();
  for (bool* b : {&rep.finished, &rep.stalled, &rep.hit_max_steps, &rep.hit_max_nodes}) *b = r.get<std::uint8_t>() != 0;
  return rep;
}

}  // namespace

std::string Colonisation::save() const {
  const Impl& m = *impl_;
  core::ByteWriter setup;
  setup.put(params_hash(m.p));
  core::ByteWriter scratch;
  setup.put(m.region ? domain_hash(m.region->domain()) : leaf_hash(m.leaf, scratch));

  core::ByteWriter w;
  put_vec3s(w, m.nodes.points());
  w.put_vector(m.parent);
  w.put_vector(m.birth);
  std::vector<Index> ana;
  for (const auto& [a, b] : m.anastomoses) ana.insert(ana.end(), {a, b});
  w.put_vector(ana);
  put_vec3s(w, m.src);
  w.put_vector(m.alive);
  w.put_vector(m.tagged);
  w.put_vector(m.active);
  w.put_vector(m.near);
  w.put_vector(m.near_d2);
  put_lists(w, m.tags);
  put_lists(w, m.reached);
  std::vector<Index> best;
  std::vector<double> d2;
  std::vector<char> flags;  // six lune flags, then ready
  for (const Impl::Sectors& st : m.sectors) {
    best.insert(best.end(), st.best, st.best + 6);
    d2.insert(d2.end(), st.d2, st.d2 + 6);
    for (bool b : st.blocked) flags.push_back(b ? 1 : 0);
    flags.push_back(st.ready ? 1 : 0);
  }
  w.put_vector(best);
  w.put_vector(d2);
  w.put_vector(flags);
  {  // Urquhart cells: per source ready, window, r2max, vertex count, then vertices and labels; outs
    std::vector<char> ready;
    std::vector<double> num;  // window, r2max per source; x, y per vertex
    std::vector<std::int64_t> labels;
    std::vector<Index> counts;
    std::vector<std::vector<Index>> outs;
    for (const Impl::Urquhart& u : m.urq) {
      ready.push_back(u.ready ? 1 : 0);
      num.insert(num.end(), {u.window, u.cell.r2max});
      counts.push_back(static_cast<Index>(u.cell.poly.size()));
      outs.push_back(u.out);
    }
    for (const Impl::Urquhart& u : m.urq)
      for (const VoronoiCell::Vertex& v : u.cell.poly) {
        num.insert(num.end(), {v.x, v.y});
        labels.push_back(v.label);
      }
    w.put_vector(ready);
    w.put_vector(num);
    w.put_vector(labels);
    w.put_vector(counts);
    put_lists(w, outs);
  }
  w.put(m.grid.cell());
  w.put_string(m.rng.state());
  w.put(m.sigma);
  w.put<std::uint64_t>(m.grown);
  put_vec2s(w, m.node_mat);
  put_vec2s(w, m.src_mat);
  w.put<std::uint64_t>(m.quiet);
  w.put<Index>(m.synced);
  put_report(w, m.rep);
  {  // lazy sector modes: per source flag, backoff, retry step, anchor, slack; then the last segment length
    std::vector<char> lazy;
    std::vector<std::uint8_t> backoff;
    std::vector<std::uint32_t> retry;
    std::vector<Index> anchor;
    std::vector<double> slack;
    for (const Impl::Sectors& st : m.sectors) {
      lazy.push_back(st.lazy ? 1 : 0);
      backoff.push_back(st.backoff);
      retry.push_back(st.retry);
      anchor.push_back(st.anchor);
      slack.push_back(st.slack);
    }
    w.put_vector(lazy);
    w.put_vector(backoff);
    w.put_vector(retry);
    w.put_vector(anchor);
    w.put_vector(slack);
    w.put(m.last_D);
  }
  return core::write_chunk_file(kStateKind, kStateVersion, {{"setup", setup.take()}, {"state", w.take()}});
}

void Colonisation::restore(const std::string& bytes, const std::string& what) {
  Impl& m = *impl_;
  const core::ChunkFile f = core::read_chunk_file(bytes, kStateKind, kStateVersion, what);
  if (f.version < 2)  // the state chunk gained the Urquhart cells: an older layout cannot be read
    throw core::FileError(what + " has format version " + std::to_string(f.version) +
                          ", written by an older cellform whose colonisation state this one cannot continue; run the "
                          "script again");
  if (f.version < 3 && m.marginal)
    throw core::FileError(what + " has format version " + std::to_string(f.version) +
                          ": it grew a marginally growing leaf with darts over the whole blade, which this cellform "
                          "no longer does (it reveals precomputed sources at the margin); run the script again");
  {
    core::ByteReader r(f.at("setup", what), what);
    const auto ph = r.get<std::uint64_t>(), dh = r.get<std::uint64_t>();
    if (ph != params_hash(m.p))
      throw InvalidInput(what +
                         " was saved with other colonisation parameters (or another seed): only colonisation.threads, "
                         "max_steps and max_nodes may differ when continuing it");
    core::ByteWriter scratch;
    if (dh != (m.region ? domain_hash(m.region->domain()) : leaf_hash(m.leaf, scratch)))
      throw InvalidInput(what +
                         " was saved for another source domain (leaf, volume or surface): continue it with the "
                         "domain it was grown in");
  }
  core::ByteReader r(f.at("state", what), what);
  const std::vector<Vec3> points = get_vec3s(r);
  m.parent = r.get_vector<Index>();
  m.birth = r.get_vector<std::uint32_t>();
  const std::vector<Index> ana = r.get_vector<Index>();
  m.src = get_vec3s(r);
  m.alive = r.get_vector<char>();
  m.tagged = r.get_vector<char>();
  m.active = r.get_vector<Index>();
  m.near = r.get_vector<Index>();
  m.near_d2 = r.get_vector<double>();
  m.tags = get_lists(r);
  m.reached = get_lists(r);
  const std::vector<Index> best = r.get_vector<Index>();
  const std::vector<double> d2 = r.get_vector<double>();
  const std::vector<char> flags = r.get_vector<char>();
  const std::vector<char> u_ready = r.get_vector<char>();
  const std::vector<double> u_num = r.get_vector<double>();
  const std::vector<std::int64_t> u_labels = r.get_vector<std::int64_t>();
  const std::vector<Index> u_counts = r.get_vector<Index>();
  const std::vector<std::vector<Index>> u_outs = get_lists(r);
  const double cell = r.get<double>();
  const std::string rng = r.get_string();
  m.sigma = r.get<double>();
  m.grown = static_cast<std::size_t>(r.get<std::uint64_t>());
  m.node_mat = get_vec2s(r);
  m.src_mat = get_vec2s(r);
  m.quiet = static_cast<std::size_t>(r.get<std::uint64_t>());
  m.synced = r.get<Index>();
  m.rep = get_report(r);
  std::vector<char> lazy;
  std::vector<std::uint8_t> backoff;
  std::vector<std::uint32_t> retry;
  std::vector<Index> anchor;
  std::vector<double> slack;
  m.last_D = 0;
  if (f.version >= 4) {
    lazy = r.get_vector<char>();
    backoff = r.get_vector<std::uint8_t>();
    retry = r.get_vector<std::uint32_t>();
    anchor = r.get_vector<Index>();
    slack = r.get_vector<double>();
    m.last_D = r.get<double>();
  }

  // consistency: sizes and indices (the checksum catches damage; this catches a state of another build)
  const std::size_t n = points.size(), ns = m.src.size();
  const bool closed = m.p.type == VenationType::closed;
  bool ok =
      r.done() && n > 0 && m.parent.size() == n && m.birth.size() == n && ana.size() % 2 == 0 && m.alive.size() == ns &&
      m.tagged.size() == ns && m.near.size() == ns && m.near_d2.size() == ns && m.tags.size() == (closed ? ns : 0) &&
      m.reached.size() == (closed ? ns : 0) && best.size() == 6 * ns && d2.size() == 6 * ns && flags.size() == 7 * ns &&
      m.synced <= n && m.rep.nodes == n &&
      (m.nonuniform ? m.node_mat.size() == n && m.src_mat.size() == ns : m.node_mat.empty() && m.src_mat.empty()) &&
      cell > 0 && m.sigma > 0;
  for (Index i = 0; ok && i < n; ++i)
    ok = (m.parent[i] == kNoIndex || m.parent[i] < i) && (i == 0 || m.birth[i] >= m.birth[i - 1]);
  for (Index v : ana) ok = ok && v < n;
  for (Index v : best) ok = ok && (v == kNoIndex || v < n);
  const std::size_t nu = m.urquhart() ? ns : 0;
  std::size_t vertices = 0;
  for (Index c : u_counts) vertices += c;
  ok = ok && u_ready.size() == nu && u_counts.size() == nu && u_outs.size() == nu &&
       u_num.size() == 2 * nu + 2 * vertices && u_labels.size() == vertices;
  for (std::int64_t l : u_labels) ok = ok && l >= -1 && l < static_cast<std::int64_t>(n);
  for (const auto& l : u_outs)
    for (Index v : l) ok = ok && v < n;
  for (Index v : m.near) ok = ok && (v == kNoIndex || v < n);
  if (f.version >= 4) {
    ok = ok && lazy.size() == ns && backoff.size() == ns && retry.size() == ns && anchor.size() == ns &&
         slack.size() == ns && std::isfinite(m.last_D) && m.last_D >= 0;
    for (std::size_t s = 0; ok && s < ns; ++s)
      ok = !lazy[s] || (anchor[s] < n && std::isfinite(slack[s]) && m.p.type == VenationType::closed && !m.nonuniform);
  }
  for (std::size_t a = 0; ok && a < m.active.size(); ++a)
    ok = m.active[a] < ns && m.alive[m.active[a]] && (a == 0 || m.active[a] > m.active[a - 1]);
  for (const auto* lists : {&m.tags, &m.reached})
    for (const auto& l : *lists)
      for (Index v : l) ok = ok && v < n;
  if (ok) ok = m.rng.set_state(rng);
  if (!ok) throw core::FileError(what + " is corrupt (inconsistent colonisation state)");

  // the k-d tree as the run built it (its shape decides which boxes the sector searches skip, and so
  // the per-source sector bests, though not the neighbourhoods): nonuniform growth rebuilt it from all
  // nodes at its last growth step (at the end of step `grown`), every other node was inserted
  m.nodes.clear();
  m.witness.clear();  // laid out again from all nodes by the next darts
  std::size_t built = 0;
  if (m.nonuniform && m.grown > 0)
    while (built < n && m.birth[built] <= m.grown) ++built;
  m.nodes.assign(std::span<const Vec3>(points).first(built));
  for (std::size_t i = built; i < n; ++i) m.nodes.insert(points[i]);
  m.first_child.assign(n, kNoIndex);
  m.next_sibling.assign(n, kNoIndex);
  for (Index i = 0; i < n; ++i)
    if (m.parent[i] != kNoIndex) {
      m.next_sibling[i] = m.first_child[m.parent[i]];
      m.first_child[m.parent[i]] = i;
    }
  m.anastomoses.clear();
  for (std::size_t i = 0; i < ana.size(); i += 2) m.anastomoses.emplace_back(ana[i], ana[i + 1]);
  m.sectors.assign(ns, {});
  for (std::size_t s = 0; s < ns; ++s) {
    Impl::Sectors& st = m.sectors[s];
    for (int k = 0; k < 6; ++k) {
      st.best[k] = best[6 * s + k];
      st.d2[k] = d2[6 * s + k];
      st.blocked[k] = flags[7 * s + k] != 0;
    }
    st.ready = flags[7 * s + 6] != 0;
    if (f.version >= 4) {
      st.lazy = lazy[s] != 0;
      st.backoff = backoff[s];
      st.retry = retry[s];
      st.anchor = anchor[s];
      st.slack = slack[s];
    }
  }
  m.urq.assign(nu, {});
  for (std::size_t s = 0, at = 2 * nu, lab = 0; s < nu; ++s) {
    Impl::Urquhart& u = m.urq[s];
    u.ready = u_ready[s] != 0;
    u.window = u_num[2 * s];
    u.cell.r2max = u_num[2 * s + 1];
    for (Index k = 0; k < u_counts[s]; ++k, at += 2) u.cell.poly.push_back({u_num[at], u_num[at + 1], u_labels[lab++]});
    u.out = u_outs[s];
  }
  m.grid.reset(cell);
  for (Index s : m.active) m.grid.insert(s, m.src[s]);
  if (m.nonuniform) m.make_table();
  m.fresh_first = m.fresh_last = kNoIndex;  // forces sync_fresh to index [synced, n)
  m.sync_fresh();
  m.per_source.clear();
  m.child.clear();
  m.acc.clear();
  // the limits are those of `params`
  m.rep.hit_max_steps = m.rep.steps >= m.p.max_steps && !m.rep.finished && !m.rep.stalled;
  m.rep.hit_max_nodes = n >= m.p.max_nodes && !m.rep.finished && !m.rep.stalled;
}

Colonisation Colonisation::load(const Domain& domain, const ColonisationParams& params, const std::string& bytes,
                                const std::string& what) {
  Colonisation c(domain, params);
  c.restore(bytes, what);
  return c;
}

Colonisation Colonisation::load(const Leaf& leaf, const ColonisationParams& params, const std::string& bytes,
                                const std::string& what) {
  Colonisation c(leaf, params);
  c.restore(bytes, what);
  return c;
}

void compute_widths(VeinTree& tree, const WidthParams& w) {
  if (!(w.exponent > 0 && std::isfinite(w.exponent)))
    throw InvalidInput("widths.exponent (Murray's n) must be positive");
  if (!(w.tip_radius > 0 && std::isfinite(w.tip_radius)))
    throw InvalidInput("widths.tip_radius must be a positive radius in model units");
  if (!(w.per_node_flow >= 0 && std::isfinite(w.per_node_flow)))
    throw InvalidInput("widths.per_node_flow must be >= 0");
  const std::size_t n = tree.size();
  std::vector<std::uint32_t> children(n, 0);
  for (Index i = 0; i < n; ++i)
    if (tree.parent[i] != kNoIndex) ++children[tree.parent[i]];
  // flow in units of tip_radius^n; children always follow their parent, so one reverse pass suffices
  tree.flow.assign(n, 0.0);
  for (Index i = static_cast<Index>(n); i-- > 0;) {
    tree.flow[i] += children[i] == 0 ? 1.0 : w.per_node_flow;
    if (tree.parent[i] != kNoIndex) tree.flow[tree.parent[i]] += tree.flow[i];
  }
  tree.radius.resize(n);
  for (std::size_t i = 0; i < n; ++i) tree.radius[i] = w.tip_radius * std::pow(tree.flow[i], 1.0 / w.exponent);
  // order: the child with the largest flow continues the parent's order
  std::vector<Index> main_child(n, kNoIndex);
  for (Index i = 0; i < n; ++i) {
    const Index pa = tree.parent[i];
    if (pa == kNoIndex) continue;
    const Index m = main_child[pa];
    if (m == kNoIndex || tree.flow[i] > tree.flow[m]) main_child[pa] = i;
  }
  tree.order.assign(n, 1);
  for (Index i = 0; i < n; ++i)
    if (tree.parent[i] != kNoIndex)
      tree.order[i] = tree.order[tree.parent[i]] + (main_child[tree.parent[i]] == i ? 0 : 1);
}

}  // namespace cellform::venation
