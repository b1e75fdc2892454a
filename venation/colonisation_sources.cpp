// Space colonisation: where the auxin sources come from (Runions et al. 2005, Section 3.1): darts thrown
// into the blade or a 3-D domain each step, or, under marginal growth, the precomputed sources the blade
// reaches; both tested against the birth distances b_s and b_v; and, in closed patterns, the loops a
// source's removal closes. Members of Colonisation::Impl.
#include <algorithm>
#include <cmath>

#include "venation/colonisation_impl.h"

namespace cellform::venation {

namespace {

/// A point of the box [lo, hi] in the plane z = 0: y drawn first, then x (the order g++ took them in when
/// they were two arguments of one call, which C++ leaves open).
Vec3 box_dart(core::Rng& rng, const Vec3& lo, const Vec3& hi) {
  const double y = rng.uniform(lo.y(), hi.y());
  const double x = rng.uniform(lo.x(), hi.x());
  return Vec3(x, y, 0.0);
}

}  // namespace

bool Colonisation::Impl::throw_darts(double bs2, double bv2) {
  const core::Rng rng_before = rng;
  const std::size_t darts_before = rep.darts;
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
  const std::size_t sources_before = src.size(), active_before = active.size();
  for (std::size_t d = 0; d < darts.size(); ++d) {
    ++rep.darts;
    // a survivor can only be too close to a dart accepted earlier in this step
    if (!dart_ok[d] || (src.size() > sources_before && grid.any_within(darts[d], bs2, src))) continue;
    if (active.size() >= p.max_sources) {  // one more would pass the limit: the step is not taken
      rep.sources_wanted = active_before + static_cast<std::size_t>(std::count(dart_ok.begin(), dart_ok.end(), 1));
      drop_sources_from(sources_before, active_before);
      rng = rng_before;
      rep.darts = darts_before;
      return false;
    }
    add_source(darts[d]);
  }
  return true;
}

void Colonisation::Impl::update_witness(double bv) {
  if (region || !(bv > 0)) return;  // no b_v test to speed up
  const double fs = p.growth == GrowthMode::marginal ? std::max(frame_scale(), p.final_scale) : frame_scale();
  Vec3 lo = nonuniform ? detail::lift(current.lo()) : Vec3(petiole + fs * (detail::lift(unit.lo()) - petiole));
  Vec3 hi = nonuniform ? detail::lift(current.hi()) : Vec3(petiole + fs * (detail::lift(unit.hi()) - petiole));
  lo -= Vec3(bv, bv, 0);
  hi += Vec3(bv, bv, 0);
  const std::size_t cap = std::max<std::size_t>(std::size_t{1} << 20, 8 * nodes.size());
  bool relayout = !witness.covers(lo, hi);
  if (!relayout && witness.cell() > bv) relayout = !witness_capped || cap >= 2 * witness_cap;
  // The map of covered cells settles queries of b_v at least its radius, so it is laid only once the growth
  // is over (b_v then stays; while it shrinks, the map would be of no use from the next step): then the grid
  // is laid again with it. The darts of a grown blade are thousands a step, for thousands of steps while
  // the last gaps fill, and most land in a covered cell.
  const double cover = growth_over() ? bv : 0;
  if (!relayout && cover != witness_cover) relayout = true;
  if (!relayout) return;
  witness.reset(lo, hi, 0.7 * bv, cap, cover);
  witness_cover = cover;
  witness_cap = cap;
  witness_capped = witness.cell() > 0.7 * bv;
  if (witness.empty()) return;  // no grid could be laid (a blade beyond double range)
  for (Index i = 0; i < nodes.size(); ++i) witness.insert(i, nodes.point(i));
}

void Colonisation::Impl::draw_blade_darts() {
  const double area = nonuniform ? current.area() : unit.area() * sigma * sigma;  // of the actual leaf
  const double expected = p.darts_per_area * area;
  detail::check_darts_per_step(expected, "the blade's area", rep.steps + 1);
  auto count = static_cast<std::size_t>(std::floor(expected));
  if (rng.uniform() < expected - std::floor(expected)) ++count;
  const double fs = frame_scale();
  const Vec3 lo = nonuniform ? detail::lift(current.lo()) : Vec3(petiole + fs * (detail::lift(unit.lo()) - petiole));
  const Vec3 hi = nonuniform ? detail::lift(current.hi()) : Vec3(petiole + fs * (detail::lift(unit.hi()) - petiole));
  if (p.threads == 1) {  // one at a time: nothing drawn in vain, nothing to rewind
    for (std::size_t d = 0; d < count; ++d) {
      Vec3 q;
      do q = box_dart(rng, lo, hi);
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
    for (Vec3& q : cand) q = box_dart(rng, lo, hi);
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

void Colonisation::Impl::reveal_sources(double bs2, double bv2) {
  const std::span<const Vec2> entering = precomputed.entering(rep.steps);
  darts.clear();
  for (const Vec2& q : entering) darts.push_back(detail::lift(q));
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

void Colonisation::Impl::drop_sources_from(std::size_t first, std::size_t active_before) {
  for (std::size_t s = first; s < src.size(); ++s) grid.erase(static_cast<Index>(s), src[s]);
  rep.sources_born -= src.size() - first;
  src.resize(first);
  if (nonuniform) src_mat.resize(first);
  alive.resize(first);
  tagged.resize(first);
  near.resize(first);
  near_d2.resize(first);
  sectors.resize(first);
  if (urquhart()) urq.resize(first);
  if (p.type == VenationType::closed) {
    tags.resize(first);
    reached.resize(first);
  }
  active.resize(active_before);
}

void Colonisation::Impl::add_source(const Vec3& q) {
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

void Colonisation::Impl::close_source(Index s, double D) {
  auto& r = reached[s];
  std::sort(r.begin(), r.end());
  r.erase(std::unique(r.begin(), r.end()), r.end());
  // the nodes within 3 segments of each other are joined, not only those near the first (with a kill
  // distance of 2 or more, two later veins near each other were left apart); a vein's neighbours, and a
  // pair another source joined already, need no edge
  std::vector<Vec3> at;
  for (const Index v : r) at.push_back(nodes.point(v));
  for (const auto& [j, i] : detail::closing_pairs(at, 3 * D)) {
    const Index a = r[j], b = r[i];
    if (parent[a] == b || parent[b] == a || !loop_keys.insert(loop_key(a, b)).second) continue;
    anastomoses.emplace_back(a, b);
    ++rep.loops;
  }
  tags[s].clear();
  tags[s].shrink_to_fit();
  r.clear();
  r.shrink_to_fit();
  remove_source(s);
}

}  // namespace cellform::venation
