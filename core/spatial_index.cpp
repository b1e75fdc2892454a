// Hashed uniform grid: counting-sort build, expanding-shell exact kNN.
#include "core/spatial_index.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "core/errors.h"
#include "core/parallel.h"

namespace cellform::core {

namespace {

// Keeps the k best (d2, index) pairs in ascending order; k is small (<= 32 in practice).
struct TopK {
  Index* idx;
  double* d2;
  int k;
  int n = 0;

  double worst() const { return n < k ? INFINITY : d2[n - 1]; }

  void offer(Index i, double d) {
    if (n == k && (d > d2[n - 1] || (d == d2[n - 1] && i >= idx[n - 1]))) return;
    for (int j = 0; j < n; ++j)
      if (idx[j] == i) return;  // hashed buckets may be visited twice
    int pos = n < k ? n++ : k - 1;
    while (pos > 0 && (d2[pos - 1] > d || (d2[pos - 1] == d && idx[pos - 1] > i))) {
      d2[pos] = d2[pos - 1];
      idx[pos] = idx[pos - 1];
      --pos;
    }
    d2[pos] = d;
    idx[pos] = i;
  }
};

// Squared distance summed in the order Eigen's squaredNorm() uses for a Vec3, ((x + y) + z), so that
// rows scanned from the coordinate arrays rank points exactly as (p - q).squaredNorm() does.
inline double distance2(double x, double y, double z, const Vec3& q) {
  const double dx = x - q.x(), dy = y - q.y(), dz = z - q.z();
  return dx * dx + dy * dy + dz * dz;
}

// Orders (squared distance, index) pairs as every query here does: by distance, ties by index.
inline bool before(double da, Index ia, double db, Index ib) { return da < db || (da == db && ia < ib); }

constexpr long kMaxShell = 12;  // beyond this many grid cells, scanning everything is cheaper

std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

}  // namespace

long PointGrid::coord(double v) const {
  // clamp so that huge, infinite or NaN coordinates cannot overflow the conversion (undefined behaviour)
  constexpr double kLimit = 1e15;
  const double c = v * inv_cell_ + 0.5;  // cells are centred on multiples of the size
  if (!(c > -kLimit)) return static_cast<long>(-kLimit);
  if (!(c < kLimit)) return static_cast<long>(kLimit);
  const auto t = static_cast<long>(c);  // floor(c) without a library call: truncate, then fix negatives
  return t - (c < static_cast<double>(t) ? 1 : 0);
}

// Hashed layout: blocks of 4 x 4 x 4 grid cells are hashed; the 64 cells of a block occupy consecutive
// buckets, so a query's 3 x 3 x 3 neighbourhood touches a few contiguous runs of the table instead of 27
// random ones. Dense layout: row-major buckets over the bounding box, one empty bucket for the outside.
std::size_t PointGrid::bucket_of(long ix, long iy, long iz) const {
  if (dense_) {
    const long x = ix - lo_[0], y = iy - lo_[1], z = iz - lo_[2];
    if (x < 0 || y < 0 || z < 0 || x >= dim_[0] || y >= dim_[1] || z >= dim_[2]) return outside_;
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(dim_[1]) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(dim_[0]) +
           static_cast<std::size_t>(x);
  }
  const auto h = static_cast<std::uint64_t>(ix >> 2) * 73856093ull ^ static_cast<std::uint64_t>(iy >> 2) * 19349663ull ^
                 static_cast<std::uint64_t>(iz >> 2) * 83492791ull;
  const auto local = static_cast<std::size_t>((ix & 3) | (iy & 3) << 2 | (iz & 3) << 4);
  return ((static_cast<std::size_t>(h) << 6) | local) & mask_;
}

void PointGrid::build(std::span<const Vec3> points, double cell_size) {
  if (!(cell_size > 0) || !std::isfinite(cell_size))
    throw InvalidInput("spatial grid cell size must be positive and finite, got " + std::to_string(cell_size));
  points_ = points;
  cell_size_ = cell_size;
  inv_cell_ = 1.0 / cell_size;
  const std::size_t n = points.size();

  // Dense when every point is finite and the bounding box has few grid cells per point (a sheet, a
  // blob); a sparse or unbounded set (distant clusters, NaN) is hashed instead.
  dense_ = false;
  bool finite = n > 0;
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (const Vec3& p : points) {
    if (!p.allFinite()) {
      finite = false;
      break;
    }
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  std::size_t buckets = 0;
  if (finite) {
    double cells = 1;
    for (int a = 0; a < 3; ++a) {
      lo_[a] = coord(lo[a]);  // coord() is monotone, so the box of the extremes holds every point
      dim_[a] = coord(hi[a]) - lo_[a] + 1;
      cells *= static_cast<double>(dim_[a]);
    }
    if (cells <= std::max(4096.0, 8.0 * static_cast<double>(n))) {
      dense_ = true;
      outside_ = static_cast<std::size_t>(cells);
      buckets = outside_ + 1;
    }
  }
  if (!dense_) {
    // about four buckets per point: blocks on a sheet are only partly filled
    buckets = 64;
    while (buckets < 4 * n) buckets *= 2;
    mask_ = buckets - 1;
  }
  start_.assign(buckets + 1, 0);
  bucket_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = points[i];
    bucket_[i] = static_cast<Index>(bucket_of(coord(p.x()), coord(p.y()), coord(p.z())));
    ++start_[bucket_[i] + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
  order_.resize(n);
  for (std::size_t i = 0; i < n; ++i) order_[start_[bucket_[i]]++] = static_cast<Index>(i);
  // the fill above advanced every start to the next bucket's start: shift back
  for (std::size_t b = buckets; b > 0; --b) start_[b] = start_[b - 1];
  start_[0] = 0;
  if (dense_) {
    slot_x_.resize(n);
    slot_y_.resize(n);
    slot_z_.resize(n);
    for (std::size_t s = 0; s < n; ++s) {
      const Vec3& p = points[order_[s]];
      slot_x_[s] = p.x();
      slot_y_[s] = p.y();
      slot_z_[s] = p.z();
    }
  } else {
    slot_x_.clear();
    slot_y_.clear();
    slot_z_.clear();
  }
}

int PointGrid::nearest(const Vec3& q, Index self, int k, Index* out, double* out_d2) const {
  TopK top{out, out_d2, k};
  if (k <= 0) return 0;
  const long c[3] = {coord(q.x()), coord(q.y()), coord(q.z())};
  // distance from q to the low and high faces of its own grid cell, per axis
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0.0, q[a] - (static_cast<double>(c[a]) - 0.5) * cell_size_);
    hi[a] = std::max(0.0, (static_cast<double>(c[a]) + 0.5) * cell_size_ - q[a]);
  }
  const double face = std::min({lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]});
  // distance along axis a from q to the slab of cells at offset d
  auto axis_gap = [&](int a, long d) {
    if (d > 0) return static_cast<double>(d - 1) * cell_size_ + hi[a];
    if (d < 0) return static_cast<double>(-d - 1) * cell_size_ + lo[a];
    return 0.0;
  };
  // a cell is skipped only if it is clearly farther than the k-th best (margin for rounding in coord())
  constexpr double kMargin = 1e-9;
  auto too_far = [&](double gap2) { return top.n == k && gap2 > top.worst() * (1 + kMargin); };
  auto scan_cell = [&](long dx, long dy, long dz, double gap2_xy) {
    const double gz = axis_gap(2, dz);
    if (too_far(gap2_xy + gz * gz)) return;
    const std::size_t b = bucket_of(c[0] + dx, c[1] + dy, c[2] + dz);
    for (Index s = start_[b]; s < start_[b + 1]; ++s) {
      const Index i = order_[s];
      if (i == self) continue;
      top.offer(i, (points_[i] - q).squaredNorm());
    }
  };
  auto brute_force = [&] {
    for (std::size_t i = 0; i < points_.size(); ++i)
      if (static_cast<Index>(i) != self) top.offer(static_cast<Index>(i), (points_[i] - q).squaredNorm());
    return top.n;
  };
  const std::size_t available = points_.size() - (self < points_.size() ? 1 : 0);
  if (available <= static_cast<std::size_t>(k)) return brute_force();  // every point is a result
  for (long s = 0;; ++s) {
    if (s > kMaxShell) return brute_force();  // sparse outlier
    // visit the shell of cells at Chebyshev distance exactly s from the centre cell, skipping whole
    // slabs and rows that lie beyond the current k-th distance
    for (long dx = -s; dx <= s; ++dx) {
      const double gx = axis_gap(0, dx);
      if (too_far(gx * gx)) continue;
      for (long dy = -s; dy <= s; ++dy) {
        const double gy = axis_gap(1, dy);
        const double gxy = gx * gx + gy * gy;
        if (too_far(gxy)) continue;
        const bool edge = std::abs(dx) == s || std::abs(dy) == s;
        if (edge) {
          for (long dz = -s; dz <= s; ++dz) scan_cell(dx, dy, dz, gxy);
        } else {
          scan_cell(dx, dy, -s, gxy);
          if (s > 0) scan_cell(dx, dy, s, gxy);
        }
      }
    }
    // every point outside the scanned cube is at least this far from q
    const double bound = static_cast<double>(s) * cell_size_ + face;
    if (top.n == k && top.worst() < bound * bound * (1 - kMargin)) return top.n;
  }
}

void PointGrid::nearest_all(int k, Index* out, int threads) const { nearest_all(k, out, threads, nullptr); }

void PointGrid::nearest_all(int k, Index* out, int threads, const Index* hint) const {
  if (k <= 0) return;
  if (dense_)
    nearest_all_dense(k, out, threads, hint);
  else
    nearest_all_hashed(k, out, threads);
}

void PointGrid::nearest_all_dense(int k, Index* out, int threads, const Index* hint) const {
  const std::size_t n = points_.size();
  const auto stride = static_cast<std::size_t>(k);
  constexpr double kMargin = 1e-9;
  constexpr double kMaxCells = 64;  // a query box with more grid cells goes to the general search
  // Each query scans the rows (runs of consecutive buckets along x, contiguous in order_ and the slot
  // coordinates) of a box of grid cells around it and keeps the points with squared distance <= limit.
  // The result is exact whenever at least k points besides the query pass, because the box holds every
  // point that can pass:
  // - hinted: limit = the largest squared distance to the k hinted points, the box covers that ball;
  // - otherwise: the 3 x 3 x 3 cells around the query's cell, limit = distance to the cube's nearest face.
  parallel_for(
      n, threads,
      [&](std::size_t begin, std::size_t end) {
        std::vector<double> cand_d2(256), dist(256), hint_d2(stride), scratch_d2(stride);
        std::vector<Index> sel(256), hint_id(stride);
        struct Run {
          Index first, last;
        } runs[static_cast<int>(kMaxCells)];
        for (std::size_t i = begin; i < end; ++i) {
          const Vec3 q = points_[i];
          const auto self = static_cast<Index>(i);
          Index* row = out + i * stride;
          long a0[3], a1[3];
          double limit = 0;
          bool hinted = false;
          if (hint != nullptr) {
            const Index* h = hint + i * stride;
            double b2 = 0;
            bool valid = true;
            for (std::size_t j = 0; j < stride; ++j) {
              const Index x = h[j];
              if (x >= n || x == self) {
                valid = false;
                break;
              }
              const Vec3& p = points_[x];
              hint_d2[j] = distance2(p.x(), p.y(), p.z(), q);
              hint_id[j] = x;
              b2 = std::max(b2, hint_d2[j]);
            }
            if (valid) {
              // A point p with computed |p - q|^2 <= b2 has |p_a - q_a| <= r on every axis (the relative
              // margin covers rounding, the absolute one underflow), and coord() is monotone.
              const double r = std::sqrt(b2) * (1 + kMargin) + 1e-150;
              double cells = 1;  // in double: a huge radius could overflow a product of longs
              for (int a = 0; a < 3; ++a) {
                a0[a] = std::max(coord(q[a] - r), lo_[a]);
                a1[a] = std::min(coord(q[a] + r), lo_[a] + dim_[a] - 1);
                cells *= static_cast<double>(a1[a] - a0[a] + 1);
              }
              if (cells <= kMaxCells) {
                limit = b2;
                hinted = true;
              }
            }
          }
          if (!hinted) {
            double face = INFINITY;
            for (int a = 0; a < 3; ++a) {
              const long c = coord(q[a]);
              face = std::min(face, q[a] - (static_cast<double>(c) - 0.5) * cell_size_);
              face = std::min(face, (static_cast<double>(c) + 0.5) * cell_size_ - q[a]);
              a0[a] = std::max(c - 1, lo_[a]);
              a1[a] = std::min(c + 1, lo_[a] + dim_[a] - 1);
            }
            const double bound = cell_size_ + std::max(0.0, face);
            limit = bound * bound * (1 - kMargin);
          }
          // Distances of every point in the box (vectorised per row), and how many pass. The query itself
          // lies in the box and passes (distance 0), so `passed - 1` others do.
          int nruns = 0;
          std::size_t count = 0, passed = 0;
          for (long z = a0[2]; z <= a1[2]; ++z)
            for (long y = a0[1]; y <= a1[1]; ++y) {
              const std::size_t row_start = (static_cast<std::size_t>(z - lo_[2]) * static_cast<std::size_t>(dim_[1]) +
                                             static_cast<std::size_t>(y - lo_[1])) *
                                            static_cast<std::size_t>(dim_[0]);
              const Index first = start_[row_start + static_cast<std::size_t>(a0[0] - lo_[0])];
              const Index last = start_[row_start + static_cast<std::size_t>(a1[0] - lo_[0]) + 1];
              const std::size_t len = last - first;
              if (count + len > cand_d2.size()) cand_d2.resize(2 * (count + len));
              runs[nruns++] = {first, last};
              const double *xs = slot_x_.data() + first, *ys = slot_y_.data() + first, *zs = slot_z_.data() + first;
              double* d2 = cand_d2.data() + count;
              for (std::size_t t = 0; t < len; ++t) d2[t] = distance2(xs[t], ys[t], zs[t], q);
              for (std::size_t t = 0; t < len; ++t) passed += d2[t] <= limit;
              count += len;
            }
          const std::size_t others = passed - 1;
          if (others < stride) {  // too few certain candidates (few points, an outlier): the general search
            const int found = nearest(q, self, k, row, scratch_d2.data());
            for (int j = found; j < k; ++j) row[j] = kNoIndex;
            continue;
          }
          if (hinted && others == stride) {
            // Exactly k others pass, and every hinted point passes: if the hint has no repeats, the result
            // is the hint sorted. It was sorted last step, so the insertion below is nearly free.
            for (std::size_t j = 1; j < stride; ++j) {
              const double d = hint_d2[j];
              const Index id = hint_id[j];
              std::size_t x = j;
              for (; x > 0 && before(d, id, hint_d2[x - 1], hint_id[x - 1]); --x) {
                hint_d2[x] = hint_d2[x - 1];
                hint_id[x] = hint_id[x - 1];
              }
              hint_d2[x] = d;
              hint_id[x] = id;
            }
            bool repeats = false;
            for (std::size_t j = 1; j < stride; ++j) repeats |= hint_id[j] == hint_id[j - 1];
            if (!repeats) {
              std::copy(hint_id.begin(), hint_id.begin() + static_cast<long>(stride), row);
              continue;
            }
          }
          // General case: gather the passing candidates, keep the k best by (distance, index) in the front
          // of the arrays: insertion with early reject.
          if (others > sel.size()) {
            sel.resize(2 * others);
            dist.resize(sel.size());
          }
          std::size_t m = 0, c = 0;
          for (int r = 0; r < nruns; ++r)
            for (Index s = runs[r].first; s < runs[r].last; ++s, ++c) {
              const Index id = order_[s];
              if (cand_d2[c] <= limit && id != self) {
                sel[m] = id;
                dist[m] = cand_d2[c];
                ++m;
              }
            }
          std::size_t kept = 0;
          for (std::size_t j = 0; j < m; ++j) {
            const double d = dist[j];
            const Index id = sel[j];
            if (kept == stride && !before(d, id, dist[kept - 1], sel[kept - 1])) continue;
            std::size_t x = kept < stride ? kept++ : stride - 1;
            for (; x > 0 && before(d, id, dist[x - 1], sel[x - 1]); --x) {
              dist[x] = dist[x - 1];
              sel[x] = sel[x - 1];
            }
            dist[x] = d;
            sel[x] = id;
          }
          std::copy(sel.begin(), sel.begin() + static_cast<long>(stride), row);
        }
      },
      1024);
}

void PointGrid::nearest_all_hashed(int k, Index* out, int threads) const {
  const std::size_t n = points_.size();
  const auto stride = static_cast<std::size_t>(k);
  constexpr std::size_t kCapacity = 512;  // candidates gathered per grid cell; more falls back to nearest()
  constexpr double kMargin = 1e-9;
  // Slots of order_ are grouped by bucket, so consecutive slots mostly share a grid cell: the points of
  // its 3 x 3 x 3 neighbourhood are gathered once and every query in the cell selects from them.
  parallel_for(
      n, threads,
      [&](std::size_t begin, std::size_t end) {
        std::vector<Index> cand(kCapacity), sel(kCapacity);
        std::vector<Vec3> cand_pos(kCapacity);
        std::vector<double> dist(kCapacity), scratch_d2(stride);
        std::size_t count = 0;
        bool overflow = false, have = false;
        long cell[3] = {0, 0, 0};
        for (std::size_t slot = begin; slot < end; ++slot) {
          const Index i = order_[slot];
          const Vec3& q = points_[i];
          const long c[3] = {coord(q.x()), coord(q.y()), coord(q.z())};
          Index* row = out + static_cast<std::size_t>(i) * stride;
          if (!have || c[0] != cell[0] || c[1] != cell[1] || c[2] != cell[2]) {
            // The 27 cells lie in at most 8 blocks; only if two of those blocks share a hash slot can a
            // bucket repeat, and only then are repeated buckets looked for.
            std::size_t slots[8];
            int ns = 0;
            for (long bx : {(c[0] - 1) >> 2, (c[0] + 1) >> 2})
              for (long by : {(c[1] - 1) >> 2, (c[1] + 1) >> 2})
                for (long bz : {(c[2] - 1) >> 2, (c[2] + 1) >> 2}) slots[ns++] = bucket_of(bx << 2, by << 2, bz << 2);
            bool collide = false;
            for (int x = 0; x < ns; ++x)
              for (int y = x + 1; y < ns; ++y) {
                // identical block coordinates give identical slots: not a collision
                const bool same_block = ((x ^ y) & 4 ? ((c[0] - 1) >> 2) == ((c[0] + 1) >> 2) : true) &&
                                        ((x ^ y) & 2 ? ((c[1] - 1) >> 2) == ((c[1] + 1) >> 2) : true) &&
                                        ((x ^ y) & 1 ? ((c[2] - 1) >> 2) == ((c[2] + 1) >> 2) : true);
                if (!same_block && slots[x] == slots[y]) collide = true;
              }
            std::size_t seen[27];
            int nseen = 0;
            count = 0;
            overflow = false;
            for (long dx = -1; dx <= 1; ++dx)
              for (long dy = -1; dy <= 1; ++dy)
                for (long dz = -1; dz <= 1; ++dz) {
                  const std::size_t b = bucket_of(c[0] + dx, c[1] + dy, c[2] + dz);
                  if (collide) {
                    bool repeat = false;
                    for (int j = 0; j < nseen; ++j) repeat = repeat || seen[j] == b;
                    if (repeat) continue;
                    seen[nseen++] = b;
                  }
                  const Index first = start_[b], last = start_[b + 1];
                  if (count + (last - first) > kCapacity) {
                    overflow = true;
                    continue;
                  }
                  for (Index s = first; s < last; ++s) {
                    cand[count] = order_[s];
                    cand_pos[count] = points_[order_[s]];
                    ++count;
                  }
                }
            cell[0] = c[0], cell[1] = c[1], cell[2] = c[2];
            have = true;
          }
          bool done = false;
          if (!overflow) {
            // Only points closer than `bound` can be accepted (farther ones may be beaten by points outside
            // the gathered cube), so only those are kept and sorted.
            double face = INFINITY;
            for (int a = 0; a < 3; ++a) {
              face = std::min(face, q[a] - (static_cast<double>(c[a]) - 0.5) * cell_size_);
              face = std::min(face, (static_cast<double>(c[a]) + 0.5) * cell_size_ - q[a]);
            }
            const double bound = cell_size_ + std::max(0.0, face);
            const double limit = bound * bound * (1 - kMargin);
            std::size_t m = 0;
            for (std::size_t j = 0; j < count; ++j) {
              const double d = (cand_pos[j] - q).squaredNorm();
              sel[m] = cand[j];
              dist[m] = d;
              m += (d < limit) & (cand[j] != i);  // branch-free compaction
            }
            if (m >= stride) {
              // keep the k best by (distance, index) in the front of the arrays: insertion with early reject
              std::size_t kept = 0;
              for (std::size_t j = 0; j < m; ++j) {
                const double d = dist[j];
                const Index id = sel[j];
                if (kept == stride && (d > dist[kept - 1] || (d == dist[kept - 1] && id > sel[kept - 1]))) continue;
                std::size_t x = kept < stride ? kept++ : stride - 1;
                while (x > 0 && (dist[x - 1] > d || (dist[x - 1] == d && sel[x - 1] > id))) {
                  dist[x] = dist[x - 1];
                  sel[x] = sel[x - 1];
                  --x;
                }
                dist[x] = d;
                sel[x] = id;
              }
              std::copy(sel.begin(), sel.begin() + static_cast<long>(stride), row);
              done = true;
            }
          }
          if (!done) {  // far neighbours, few points or a crowded cell: the general search
            const int found = nearest(q, i, k, row, scratch_d2.data());
            for (int j = found; j < k; ++j) row[j] = kNoIndex;
          }
        }
      },
      1024);
}

// Calls visit(i) for every point i within `radius` of q but `self`, each once, until visit returns false.
// In the hashed layout several grid cells share a bucket: a point is taken only at its own grid cell, so
// none is seen twice and no list of those found is needed.
template <class Visit>
void PointGrid::for_each_within(const Vec3& q, double radius, Index self, Visit&& visit) const {
  const double r2 = radius * radius;
  // the box a little wider than the ball: q +- radius is rounded, and a point exactly at the radius
  // (squared distances equal) may lie just past the rounded bound, in the next grid cell
  auto pad = [&](double c) { return radius + 4 * std::numeric_limits<double>::epsilon() * (std::abs(c) + radius); };
  const long lo[3] = {coord(q.x() - pad(q.x())), coord(q.y() - pad(q.y())), coord(q.z() - pad(q.z()))};
  const long hi[3] = {coord(q.x() + pad(q.x())), coord(q.y() + pad(q.y())), coord(q.z() + pad(q.z()))};
  // cell count in double: the product of three long extents can overflow for a huge radius
  const double cells = static_cast<double>(hi[0] - lo[0] + 1) * static_cast<double>(hi[1] - lo[1] + 1) *
                       static_cast<double>(hi[2] - lo[2] + 1);
  if (!(cells <= static_cast<double>(start_.size()))) {
    for (std::size_t i = 0; i < points_.size(); ++i)
      if (static_cast<Index>(i) != self && (points_[i] - q).squaredNorm() <= r2 && !visit(static_cast<Index>(i)))
        return;
    return;
  }
  for (long ix = lo[0]; ix <= hi[0]; ++ix)
    for (long iy = lo[1]; iy <= hi[1]; ++iy)
      for (long iz = lo[2]; iz <= hi[2]; ++iz) {
        const std::size_t b = bucket_of(ix, iy, iz);
        for (Index s = start_[b]; s < start_[b + 1]; ++s) {
          const Index i = order_[s];
          const Vec3& p = points_[i];
          if (i == self || (p - q).squaredNorm() > r2) continue;
          if (!dense_ && (coord(p.x()) != ix || coord(p.y()) != iy || coord(p.z()) != iz)) continue;
          if (!visit(i)) return;
        }
      }
}

void PointGrid::within(const Vec3& q, double radius, Index self, std::vector<Index>& out) const {
  for_each_within(q, radius, self, [&](Index i) {
    out.push_back(i);
    return true;
  });
}

int PointGrid::count_within(const Vec3& q, double radius, Index self, int limit) const {
  int count = 0;
  if (limit <= 0) return 0;
  for_each_within(q, radius, self, [&](Index) { return ++count < limit; });
  return count;
}

std::vector<Index> spatial_order(std::span<const Vec3> points, double cell_size) {
  if (points.empty()) return {};
  // non-finite points (a diverging run) are sorted last instead of converting NaN to an integer
  Vec3 lo = Vec3::Constant(INFINITY);
  for (const Vec3& p : points)
    if (p.allFinite()) lo = lo.cwiseMin(p);
  std::vector<std::uint64_t> key(points.size());
  constexpr double kMaxCell = 0x1fffff;  // 21 bits per axis
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      key[i] = ~0ull;
      continue;
    }
    std::uint64_t k = 0;
    for (int a = 0; a < 3; ++a) {
      const double c = std::min(kMaxCell, std::floor((points[i][a] - lo[a]) / cell_size));
      k |= spread_bits(static_cast<std::uint64_t>(std::max(0.0, c))) << a;
    }
    key[i] = k;
  }
  std::vector<Index> perm(points.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::stable_sort(perm.begin(), perm.end(), [&](Index a, Index b) { return key[a] < key[b]; });
  return perm;
}

}  // namespace cellform::core
