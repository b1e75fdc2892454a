// Auxin sources for marginal leaf growth (Runions et al. 2005, Section 3.3): dart throwing over the final
// blade's box, then the step at which the growing margin first reaches each accepted dart.
#include "venation/marginal_sources.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/errors.h"
#include "core/parallel.h"
#include "core/random.h"

namespace cellform::venation {

using core::InvalidInput;

namespace {

constexpr double kMaxDarts = 1e9;
constexpr double kMaxSources = 5e7;  // about 2 GB of precomputed sources at their peak (40 bytes each)
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

using core::number_text;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Dart throwing in the box [lo, hi]: `count` uniform darts in draw order, each accepted if farther than
/// `bs` from every dart accepted before it. A grid of cells at least bs wide (so a 3 x 3 block holds
/// every point within bs), with at most about as many cells as darts, lists the accepted darts; the
/// dart's own cell is searched first, where a saturated set usually rejects it.
std::vector<Vec2> throw_box_darts(const Vec2& lo, const Vec2& hi, double bs, std::size_t count, core::Rng& rng) {
  struct Node {
    double x, y;
    std::uint32_t next;  // the cell's previous point
  };
  std::vector<Node> pts;
  if (count == 0) return {};
  const Vec2 size = hi - lo;
  const double cell = std::max({bs, std::sqrt(4 * size.x() * size.y() / static_cast<double>(count)), 1e-300});
  const auto nx = static_cast<long>(std::min(std::floor(size.x() / cell) + 1, 1e9));
  const auto ny = static_cast<long>(std::min(std::floor(size.y() / cell) + 1, 1e9));
  std::vector<std::uint32_t> head(static_cast<std::size_t>(nx * ny), kNone);
  const double bs2 = bs * bs;
  auto clear = [&](long x, long y, double qx, double qy) {
    for (std::uint32_t i = head[static_cast<std::size_t>(y * nx + x)]; i != kNone; i = pts[i].next) {
      const double dx = pts[i].x - qx, dy = pts[i].y - qy;
      if (dx * dx + dy * dy <= bs2) return false;
    }
    return true;
  };
  for (std::size_t d = 0; d < count; ++d) {
    const double qx = rng.uniform(lo.x(), hi.x());
    const double qy = rng.uniform(lo.y(), hi.y());
    const long cx = std::min(static_cast<long>((qx - lo.x()) / cell), nx - 1);
    const long cy = std::min(static_cast<long>((qy - lo.y()) / cell), ny - 1);
    bool ok = clear(cx, cy, qx, qy);
    for (long y = std::max(cy - 1, 0L); ok && y <= std::min(cy + 1, ny - 1); ++y)
      for (long x = std::max(cx - 1, 0L); ok && x <= std::min(cx + 1, nx - 1); ++x)
        if (x != cx || y != cy) ok = clear(x, y, qx, qy);
    if (!ok) continue;
    const auto c = static_cast<std::size_t>(cy * nx + cx);
    pts.push_back({qx, qy, head[c]});
    head[c] = static_cast<std::uint32_t>(pts.size() - 1);
  }
  std::vector<Vec2> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) out[i] = Vec2(pts[i].x, pts[i].y);
  return out;
}

/// The outline's edges binned by the angle under which the petiole sees them, for the crossings of rays
/// from the petiole.
class RayIndex {
 public:
  RayIndex(const Outline& outline, const Vec2& petiole) : pts_(outline.points), petiole_(petiole) {
    const std::size_t n = pts_.size();
    bins_ = std::max<std::size_t>(64, 2 * n);
    std::vector<std::vector<std::uint32_t>> lists(bins_);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 a = pts_[i] - petiole, b = pts_[(i + 1) % n] - petiole;
      const double ta = std::atan2(a.y(), a.x()), tb = std::atan2(b.y(), b.x());
      double span = tb - ta;
      if (span > std::numbers::pi) span -= 2 * std::numbers::pi;
      if (span <= -std::numbers::pi) span += 2 * std::numbers::pi;
      // an edge passing (nearly) through the petiole: the half-open test decides, in every bin
      const bool all = std::abs(span) > std::numbers::pi - 0.01;
      const double from = span >= 0 ? ta : tb;
      const long b0 = all ? 0 : static_cast<long>(std::floor(bin_of(from))) - 1;
      const long b1 =
          all ? static_cast<long>(bins_) - 1 : static_cast<long>(std::floor(bin_of(from + std::abs(span)))) + 1;
      const long nb = static_cast<long>(bins_);
      for (long k = b0; k <= std::min(b1, b0 + nb - 1); ++k)
        lists[static_cast<std::size_t>(((k % nb) + nb) % nb)].push_back(static_cast<std::uint32_t>(i));
    }
    start_.assign(1, 0);
    for (const auto& l : lists) {
      edges_.insert(edges_.end(), l.begin(), l.end());
      start_.push_back(edges_.size());
    }
  }

  /// Ray parameters t > 0 at which petiole + t d crosses the outline, ascending. The half-open rule of the
  /// crossing-number test counts each crossing once (also at vertices), so a point petiole + s d off the
  /// outline is inside exactly when an odd number of them exceed s.
  void crossings(const Vec2& d, std::vector<double>& t) const {
    t.clear();
    const std::size_t n = pts_.size();
    const auto b = static_cast<std::size_t>(std::floor(bin_of(std::atan2(d.y(), d.x())))) % bins_;
    for (std::size_t k = start_[b]; k < start_[b + 1]; ++k) {
      const std::uint32_t i = edges_[k];
      const Vec2 a = pts_[i] - petiole_, c = pts_[(i + 1) % n] - petiole_;
      const double sa = cross(d, a), sc = cross(d, c);
      if ((sa > 0) == (sc > 0)) continue;
      const double u = cross(a, c) / (sc - sa);
      if (u > 0) t.push_back(u);
    }
    std::sort(t.begin(), t.end());
  }

 private:
  double bin_of(double angle) const {
    return (angle + std::numbers::pi) / (2 * std::numbers::pi) * static_cast<double>(bins_);
  }
  const std::vector<Vec2>& pts_;
  Vec2 petiole_;
  std::size_t bins_ = 64;
  std::vector<std::size_t> start_;
  std::vector<std::uint32_t> edges_;
};

/// The first step k whose blade contains q, or kNone. The ray crossings give the scale intervals in which
/// q lies inside (the point of the unit outline that q corresponds to at scale sigma is petiole + (q -
/// petiole) / sigma, ray parameter 1 / sigma); the blade test itself confirms the step.
std::uint32_t entry_step(const Vec2& q, const Vec2& petiole, const RayIndex& rays, const OutlineIndex& unit,
                         const std::vector<double>& scales, std::vector<double>& t) {
  const Vec2 d = q - petiole;
  if (!(d.squaredNorm() > 0)) return kNone;  // the petiole itself: a vein node is there
  rays.crossings(d, t);
  auto inside_at = [&](std::size_t k) { return unit.contains(petiole + (q - petiole) / scales[k]); };
  // inside for ray parameters in (t[j - 1], t[j]) for j = m, m - 2, ... (t[-1] = 0): in scales, from the
  // smallest up, sigma in (1 / t[j], 1 / t[j - 1])
  for (auto j = static_cast<long>(t.size()) - 1; j >= 0; j -= 2) {
    const double lo = 1 / t[static_cast<std::size_t>(j)];
    const double hi = j >= 1 ? 1 / t[static_cast<std::size_t>(j - 1)] : std::numeric_limits<double>::infinity();
    auto k = static_cast<std::size_t>(std::lower_bound(scales.begin(), scales.end(), lo * (1 - 1e-9)) - scales.begin());
    for (; k < scales.size() && scales[k] <= hi * (1 + 1e-9); ++k)
      if (inside_at(k)) return static_cast<std::uint32_t>(k);
  }
  return kNone;
}

}  // namespace

std::vector<double> marginal_scales(double initial_scale, double final_scale, double scale_step) {
  std::vector<double> s{initial_scale};
  if (!(final_scale > initial_scale)) return s;
  if (!(scale_step > 0) || (final_scale - initial_scale) / scale_step > kMaxGrowthSteps)
    throw InvalidInput("colonisation.scale_step is too small: marginal growth from " + number_text(initial_scale) +
                       " to " + number_text(final_scale) + " would take more than 10^7 steps");
  // the same expression as the simulation's step, so the values are the same bits
  while (s.back() < final_scale) {
    const double next = std::min(final_scale, s.back() + scale_step);
    if (!(next > s.back()))  // a step below the rounding of the scale: it would never arrive
      throw InvalidInput("colonisation.scale_step is too small: " + number_text(scale_step) +
                         " does not change the leaf scale " + number_text(s.back()) + " in double precision");
    s.push_back(next);
  }
  return s;
}

MarginalSources precompute_marginal_sources(const Outline& outline, const Vec2& petiole,
                                            const std::vector<double>& scales, const MarginalSourceParams& p) {
  MarginalSources out;
  out.start.assign(scales.size() + 1, 0);
  if (scales.empty()) return out;
  const OutlineIndex unit(outline);
  const double big = scales.back();
  const Vec2 lo = petiole + big * (unit.lo() - petiole), hi = petiole + big * (unit.hi() - petiole);
  const double expected = p.darts_per_area * static_cast<double>(scales.size()) * (hi - lo).prod();
  if (!(expected <= kMaxDarts))
    throw InvalidInput(
        "colonisation.darts: marginal growth precomputes its sources by throwing rho x steps x (area of the "
        "final blade's box) = " +
        number_text(expected) + " darts, more than 10^9; use fewer darts, fewer steps or a smaller leaf");
  // accepted darts are at least b_s apart: at most about one per sqrt(3)/2 b_s^2 of the box (hexagonal
  // packing, +1 per row and column for the edges), and never more than the darts
  const Vec2 size = hi - lo;
  const double packed = (size.x() / p.birth_distance + 1) * (size.y() / p.birth_distance + 1) * 1.1547;
  const double most = std::min(expected, packed);
  if (!(most <= kMaxSources))
    throw InvalidInput(
        "colonisation.birth_distance: marginal growth precomputes its sources over the final blade, "
        "and b_s = " +
        number_text(p.birth_distance) + " with " + number_text(expected) + " darts could place up to " +
        number_text(most) + " of them, more than 5 x 10^7; use a larger birth distance, fewer darts or a smaller leaf");
  core::Rng rng(core::stream_key(p.seed, 0x6d617267696e616cull));  // "marginal": not the step darts' stream
  auto count = static_cast<std::size_t>(std::floor(expected));
  if (rng.uniform() < expected - std::floor(expected)) ++count;
  out.darts = count;
  const std::vector<Vec2> pts = throw_box_darts(lo, hi, p.birth_distance, count, rng);
  out.accepted = pts.size();

  const RayIndex rays(outline, petiole);
  std::vector<std::uint32_t> entry(pts.size());
  core::parallel_for(
      pts.size(), p.threads,
      [&](std::size_t first, std::size_t last) {
        std::vector<double> t;
        for (std::size_t i = first; i < last; ++i) entry[i] = entry_step(pts[i], petiole, rays, unit, scales, t);
      },
      1024);
  // counting sort by entry step, stable: dart order within a step
  for (std::uint32_t e : entry)
    if (e != kNone) ++out.start[e + 1];
  for (std::size_t k = 1; k < out.start.size(); ++k) out.start[k] += out.start[k - 1];
  out.points.resize(out.start.back());
  std::vector<std::size_t> at(out.start.begin(), out.start.end() - 1);
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (entry[i] != kNone) out.points[at[entry[i]]++] = pts[i];
  return out;
}

}  // namespace cellform::venation
