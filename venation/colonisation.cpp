// Space-colonisation venation (Runions et al. 2005): dart throwing, Eq. 1 growth, open and closed removal.
// The state is in colonisation_impl.h; new sources (darts, marginal reveal) in colonisation_sources.cpp;
// checkpoints in colonisation_state.cpp; parameter checks in colonisation_checks.cpp; widths, runs: _tree.cpp
#include "venation/colonisation.h"

#include <cmath>
#include <numbers>
#include <string>

#include "core/errors.h"
#include "venation/colonisation_impl.h"

namespace cellform::venation {

using core::InvalidInput;
using core::number_text;

double GrowthFunction::operator()(double y0) const {
  if (y0 <= y.front()) return rate.front();
  if (y0 >= y.back()) return rate.back();
  const auto i = static_cast<std::size_t>(std::upper_bound(y.begin(), y.end(), y0) - y.begin());
  const double t = (y0 - y[i - 1]) / (y[i] - y[i - 1]);
  return rate[i - 1] + t * (rate[i] - rate[i - 1]);
}

// ---- The steps of the state (declared in colonisation_impl.h) ----

Colonisation::Impl::Impl(const Leaf& l, const ColonisationParams& params)
    : leaf(l), p(params), unit(l.outline), rng(params.seed) {
  petiole = detail::lift(leaf.petiole);
  sigma = p.initial_scale;
  nonuniform = p.growth == GrowthMode::nonuniform;
  if (p.growth == GrowthMode::none || p.growth == GrowthMode::uniform) {  // the largest blade is known now
    const double top = std::max(p.initial_scale, p.growth == GrowthMode::none ? 0.0 : p.final_scale);
    detail::check_darts_per_step(p.darts_per_area * unit.area() * top * top, "the blade's area");
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
  rep.marginal_darts = precomputed.darts;
  std::vector<Vec2> seeds = leaf.initial_nodes;
  if (seeds.empty()) seeds.push_back(leaf.petiole);
  for (const Vec2& s : seeds) add_node(petiole + p.initial_scale * (detail::lift(s) - petiole), kNoIndex, 0);
  grid.reset(p.source_birth_distance * dist_factor());
  for (const Vec2& s : leaf.initial_sources) add_source(petiole + p.initial_scale * (detail::lift(s) - petiole));
  rep.scale = sigma;
  rep.nodes = nodes.size();
}

Colonisation::Impl::Impl(const Domain& d, const ColonisationParams& params)
    : p(params), rng(params.seed), region(std::in_place, d) {
  petiole = Vec3::Zero();
  sigma = 1;
  detail::check_darts_per_step(p.darts_per_area * region->dart_measure(),
                               d.kind == DomainKind::surface ? "the surface's area" : "the volume of the domain's box");
  for (const Vec3& s : d.initial_nodes) add_node(s, kNoIndex, 0);
  grid.reset(p.source_birth_distance);
  for (const Vec3& s : d.initial_sources) add_source(s);
  rep.nodes = nodes.size();
}

bool Colonisation::Impl::place_3d(Index v, Vec3& q, double D, bool cancelled) const {
  const Vec3& from = nodes.point(v);
  if (!cancelled) q = region->project(q);
  // a pull along the normal (sources all round v, as at a closed mesh's face centre) projects back next to v: as for
  // pulls that cancel, v tries its nearest influencing source (one across a thin shell projects back too: v waits)
  if (cancelled || (q - from).squaredNorm() < 0.01 * D * D || retraces(v, q)) {
    Index best = kNoIndex;
    double best_d2 = 0;
    for (std::size_t a = 0; a < active.size(); ++a) {
      const Index s = active[a];
      const double d2 = (src[s] - from).squaredNorm();
      if (d2 > 0 && influenced_by(a, v) && (best == kNoIndex || d2 < best_d2)) {  // (one on v gives no way)
        best = s;
        best_d2 = d2;
      }
    }
    if (best == kNoIndex) return false;
    q = region->project(from + D * (src[best] - from) / std::sqrt(best_d2));
  }
  return (q - from).squaredNorm() >= 0.01 * D * D;
}

void Colonisation::Impl::make_table() {
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
  current = OutlineIndex(o, grown >= p.growth_steps);  // the grid, for the darts, once the blade stays
}

void Colonisation::Impl::grow_nonuniform() {
  ++grown;
  make_table();
  std::vector<Vec3> moved(nodes.size());
  for (std::size_t i = 0; i < moved.size(); ++i) moved[i] = detail::lift(to_current(node_mat[i]));
  nodes.assign(moved);
  witness.clear();  // laid out again, with the nodes where they are now, by the next darts
  synced = static_cast<Index>(nodes.size());
  fresh.assign({}, synced);
  fresh_first = fresh_last = synced;
  grid.reset(grid.cell());
  for (Index s : active) {
    src[s] = detail::lift(to_current(src_mat[s]));
    grid.insert(s, src[s]);
    near[s] = kNoIndex;
    sectors[s].ready = false;
    sectors[s].lazy = false;
    if (!urq.empty()) urq[s].ready = false;
  }
}

Index Colonisation::Impl::add_node(const Vec3& q, Index par, std::uint32_t step_no) {
  const Index id = nodes.insert(q);
  link_node(id, par, step_no);
  return id;
}

void Colonisation::Impl::add_nodes(std::span<const Vec3> q, std::span<const Index> par, std::uint32_t step_no) {
  const auto first = static_cast<Index>(nodes.size());
  nodes.insert_batch(q);
  for (std::size_t k = 0; k < q.size(); ++k) link_node(first + static_cast<Index>(k), par[k], step_no);
}

void Colonisation::Impl::link_node(Index id, Index par, std::uint32_t step_no) {
  const Vec3& q = nodes.point(id);
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
}

void Colonisation::Impl::urquhart_update(Index s, std::vector<Index>& out, double window, PointTree::Scratch& scratch,
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

void Colonisation::Impl::sector_update(Index s, std::vector<Index>& out, bool closed, PointTree::Scratch& scratch) {
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

void Colonisation::Impl::try_lazy(Index s, Sectors& st) {
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

bool Colonisation::Impl::lazy_step(Index s, Sectors& st) {
  const Vec3& q = src[s];
  near[s] = st.anchor;  // the nearest of the nodes before `fresh` (a removal test may have looked ahead)
  near_d2[s] = (nodes.point(st.anchor) - q).squaredNorm();
  bool tie = false;
  fresh.nearest(q, near[s], near_d2[s], &tie);
  const double moved = (nodes.point(near[s]) - nodes.point(st.anchor)).norm() * (1 + 1e-12);
  const double r0 = std::sqrt(near_d2[s]);
  const double tol = tolerance(q);
  st.slack = detail::lazy_slack_after(st.slack, r0, last_D, moved, tol);
  st.anchor = near[s];
  if (tie) return false;
  if (st.slack < kLazyRenew * step_D) {
    const double t = kLazyMargin * step_D;
    if (!(near_d2[s] > t * t && nodes.margin_at_least(q, near[s], t + tol))) return false;
    st.slack = t;
  }
  return st.slack > tol;
}

bool Colonisation::Impl::reach(std::size_t a, bool closed, double dk2) {
  const Index s = active[a];
  // the new nodes lie D from older ones, which are all at least |near - s| away: beyond d_k + D none of
  // them can be within d_k (reach_far2: leaves, where a node is placed exactly D from its parent)
  const bool far = near[s] != kNoIndex && near_d2[s] > reach_far2;
  if ((!far && fresh.any_within(src[s], dk2)) || (near[s] != kNoIndex && near_d2[s] <= dk2))
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
      }  // else: the vein left the zone of influence of s, or s still pulls t but t could not grow this step
         // (a step that would retrace a segment or leave the blade): the tag goes too, or s could wait for ever
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

void Colonisation::Impl::step() {
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
  const std::size_t active_before = active.size(), nodes_before = nodes.size(), darts_before = rep.darts;

  if (marginal) {
    reveal_sources(bs2, bv2);
  } else if (!throw_darts(bs2, bv2)) {
    rep.hit_max_sources = true;  // before this step, which is not taken
    return;
  }

  // influence: S(v) for every vein node (Eq. 1 input); open: nearest node; closed: V(s), Eq. 2 and 3
  const bool closed = p.type == VenationType::closed;
  // Urquhart's window: a few times the blade's size (nonuniform: the blade as grown so far)
  const Vec3 box = nonuniform ? detail::lift(current.hi() - current.lo()) : detail::lift(unit.hi() - unit.lo());
  const double half_extent = 4 * (box.norm() + 1) * (nonuniform ? 1.0 : frame_scale());
  // lazy sectors: squared distances of nodes up to 2 half_extent apart round by far less than lazy_tol x kLazyRenew D
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
  // the per-source lists laid end to end in source order: offsets first, then copied in parallel
  infl_start.resize(active.size() + 1);
  for (std::size_t a = 0; a < active.size(); ++a)
    infl_start[a + 1] = infl_start[a] + static_cast<Index>(per_source[a].size());
  infl.resize(infl_start.back());
  infl_dir.resize(infl_start.back());
  core::parallel_for(
      active.size(), p.threads,
      [&](std::size_t first, std::size_t last) {
        for (std::size_t a = first; a < last; ++a) {
          std::copy(per_source[a].begin(), per_source[a].end(), infl.begin() + infl_start[a]);
          std::copy(per_dir[a].begin(), per_dir[a].end(), infl_dir.begin() + infl_start[a]);
        }
      },
      4096);
  synced = static_cast<Index>(nodes.size());
  acc.resize(nodes.size(), Vec3::Zero());
  child.resize(nodes.size(), kNoIndex);
  seen.resize(nodes.size(), 0);
  touched.clear();
  // sums in source order (the same bits for any thread count); each node listed once, then sorted. A leaf also
  // keeps each node's nearest influencing source (ties: the first in source order), for one Eq. 1 cannot move
  if (!region) {
    pull_source.resize(nodes.size(), kNoIndex);
    pull_d2.resize(nodes.size(), 0.0);
  }
  for (std::size_t a = 0; a < active.size(); ++a)
    for (Index k2 = infl_start[a]; k2 < infl_start[a + 1]; ++k2) {
      const Index v = infl[k2];
      if (std::isnan(infl_dir[k2].x())) continue;  // the source sits on the node: no direction
      if (!seen[v]) {
        seen[v] = 1;
        touched.push_back(v);
      }
      acc[v] += infl_dir[k2];
      if (!region) {
        const double d2 = (src[active[a]] - nodes.point(v)).squaredNorm();
        if (pull_source[v] == kNoIndex || d2 < pull_d2[v]) {
          pull_source[v] = active[a];
          pull_d2[v] = d2;
        }
      }
    }
  std::sort(touched.begin(), touched.end());
  for (Index v : touched) seen[v] = 0;
  // leaves: the new nodes enter the tree in one batch (nothing below queries it before; each v gets at most
  // one child here, so retraces() needs only the older ones); 3-D: one by one, as place_3d queries the tree
  const auto step_no = static_cast<std::uint32_t>(rep.steps + 1);
  new_pos.clear();
  new_parent.clear();
  for (Index v : touched) {
    const Vec3 n = acc[v];
    acc[v].setZero();
    const double len = n.norm();
    Vec3 q = nodes.point(v) + D * n / len;
    if (region) {
      if (!place_3d(v, q, D, !(len > 1e-9))) continue;
      if (retraces(v, q)) continue;
    } else {
      const Index s = pull_source[v];
      pull_source[v] = kNoIndex;
      // A segment stays in the blade: sources on both sides of a sinus (a lobed or toothed outline) pull a
      // node between them out of it, or a segment across the sinus from a node near it (a laser would cut the
      // vein through the outline). Marginal growth scales the margin, not the veins: an outline not
      // star-shaped about the petiole (a lobe's sinus, a barb) leaves part of a young blade outside the grown
      // one, and no vein goes there either.
      auto fits = [&](const Vec3& x) { return !retraces(v, x) && segment_in_blade(nodes.point(v), x); };
      // Sources that cancel (Eq. 1 undefined), pull v back along one of its segments (usually its Eq. 1
      // child again, which is farther from each of them than v) or out of the blade: v grows towards its
      // nearest influencing source alone, which splits the set (Figure 6k). Without it such pairs wait for
      // ever and the run stalls with sources left, as in 3-D (place_3d)
      if (!(len > 1e-9) || !fits(q)) {
        q = nodes.point(v) + D * (src[s] - nodes.point(v)) / std::sqrt(pull_d2[v]);
        if (!fits(q)) continue;
      }
    }
    if (region) {
      child[v] = add_node(q, v, step_no);
    } else {
      child[v] = static_cast<Index>(nodes.size() + new_pos.size());
      new_pos.push_back(q);
      new_parent.push_back(v);
    }
  }
  add_nodes(new_pos, new_parent, step_no);
  last_D = D;

  // removal (open) or tagging and removal (closed), with the nodes just added. near[s] is the nearest of
  // the nodes [0, synced), so only the new ones are searched for one within d_k; if there is one, the
  // nearest node is taken over all nodes (the last word on distance ties, by index), in a small disc.
  // Each source updates only its own near, tags and reached (in parallel); the removals, which touch
  // the source grid and the anastomoses, follow in source order.
  sync_fresh();
  reach_far2 = std::numeric_limits<double>::infinity();
  if (!region && !nonuniform) reach_far2 = std::pow(std::sqrt(dk2) + D * (1 + 1e-9) + lazy_tol, 2);
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
  // Progress is a new node, or sources waiting that were not (or no longer waiting). A source born where
  // the veins already reach it (kill_distance at or beyond vein_birth_distance) goes in the same step and
  // grows nothing: darts that keep landing so would otherwise keep a pattern with nothing to grow running
  // to max_steps, holding every source it ever made.
  const bool changed = nodes.size() != nodes_before || active.size() != active_before;
  quiet = (growth_over() && !changed) ? quiet + 1 : 0;
  quiet_darts = quiet > 0 ? quiet_darts + (rep.darts - darts_before) : 0;
  if (quiet >= p.settle_steps && static_cast<double>(quiet_darts) >= settle_darts()) {
    if (active.empty())
      rep.finished = true;
    else
      rep.stalled = true;
  }
  if (rep.steps >= p.max_steps && !rep.finished && !rep.stalled) rep.hit_max_steps = true;
  if (nodes.size() >= p.max_nodes && !rep.finished && !rep.stalled) rep.hit_max_nodes = true;
  if (active.size() >= p.max_sources && !rep.finished && !rep.stalled) rep.hit_max_sources = true;
}

double Colonisation::Impl::settle_darts() const {
  const double bv = p.vein_birth_distance * dist_factor();  // model units
  if (marginal || !(p.darts_per_area > 0) || !(bv > 0)) return 0;
  double discs = 0;
  if (region) {
    const bool volume = region->domain().kind != DomainKind::surface;
    discs = region->measure() / (volume ? 4 * std::numbers::pi / 3 * bv * bv * bv : std::numbers::pi * bv * bv);
  } else {  // the actual leaf, in vein segments, as draw_blade_darts throws over it
    const double area = nonuniform ? current.area() : unit.area() * sigma * sigma;
    discs = area / (std::numbers::pi * p.vein_birth_distance * p.vein_birth_distance);
  }
  return discs >= 0 ? std::min(discs, kSettleDarts) : 0.0;  // (NaN: a measure beyond double range)
}

// ---- Colonisation ----

Colonisation::Colonisation(const Leaf& leaf, const ColonisationParams& params) {
  validate(params);
  validate(leaf);
  validate(leaf, params);
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
  return r.finished || r.stalled || r.hit_max_steps || r.hit_max_nodes || r.hit_max_sources;
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

}  // namespace cellform::venation
