// Triangles of the cell sheet: 3-cliques of the link graph (for files, in one layer), oriented consistently
// flattest side first.
#include "cells/surface.h"
#include "cells/surface_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <span>

namespace cellform::cells {

bool detail::diagonals_cross(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
  const Vec3 d1 = q - p, d2 = s - r, w = p - r;
  const double a = d1.squaredNorm(), b = d1.dot(d2), c = d2.squaredNorm(), d = d1.dot(w), e = d2.dot(w);
  const double den = a * c - b * b;
  if (!(den > 1e-12 * a * c)) return false;  // parallel
  const double t1 = (b * e - c * d) / den, t2 = (a * e - b * d) / den;
  if (!(t1 > 0.02 && t1 < 0.98 && t2 > 0.02 && t2 < 0.98)) return false;
  const double gap2 = (p + t1 * d1 - (r + t2 * d2)).squaredNorm();
  return gap2 < std::min(a, c) / 16;
}

namespace {

/// Whether point k lies on segment pq, or close to it (within a quarter of its length, away from its ends):
/// then the triangle pqk is a sliver lying along the two shorter edges pk and kq.
bool splits(const Vec3& p, const Vec3& q, const Vec3& k) {
  const Vec3 d = q - p;
  const double len2 = d.squaredNorm();
  if (!(len2 > 0)) return false;
  const double t = (k - p).dot(d) / len2;
  return t > 0.02 && t < 0.98 && (p + t * d - k).squaredNorm() < len2 / 16;
}

/// `edges` (sorted, i < j) without the edges that cross a shorter one joining two of their common
/// neighbours, or pass (nearly) through a common neighbour, as a greedy triangulation decides: shortest first
/// (ties by index pair), an edge stays unless it crosses one that stayed or a neighbour linked to both
/// ends by edges that stayed lies on it. Deterministic; the result is sorted like `edges`.
std::vector<std::array<Index, 2>> uncrossed(const std::vector<Vec3>& pos,
                                            const std::vector<std::array<Index, 2>>& edges) {
  const std::size_t n = pos.size();
  struct Link {
    Index to;
    std::size_t edge;
    bool operator<(const Link& o) const { return to < o.to; }
  };
  std::vector<std::size_t> start(n + 1, 0);  // full adjacency (both directions), sorted, with edge indices
  for (const auto& e : edges) {
    ++start[e[0] + 1];
    ++start[e[1] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<Link> adj(start[n]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    adj[fill[edges[e][0]]++] = {edges[e][1], e};
    adj[fill[edges[e][1]]++] = {edges[e][0], e};
  }
  auto first = [&](Index u) { return adj.begin() + static_cast<long>(start[u]); };
  for (Index i = 0; i < n; ++i) std::sort(first(i), first(i + 1));
  std::vector<std::pair<double, std::size_t>> order(edges.size());  // shortest first, ties by index pair
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const double len2 = (pos[edges[e][0]] - pos[edges[e][1]]).squaredNorm();
    order[e] = {len2 <= std::numeric_limits<double>::max() ? len2 : std::numeric_limits<double>::infinity(), e};
  }
  std::sort(order.begin(), order.end());
  std::vector<std::size_t> rank(edges.size());
  for (std::size_t r = 0; r < order.size(); ++r) rank[order[r].second] = r;
  // First, in index order (neighbouring cells, neighbouring memory), what could remove each edge: the
  // shorter edges it crosses, and the pairs of shorter edges through a cell lying on it. Few edges have any.
  struct Blocker {
    std::size_t a, b;  // removes the edge if both were kept (a == b: one crossing edge)
  };
  std::vector<std::size_t> block_start(edges.size() + 1, 0);
  std::vector<Blocker> blockers;
  std::vector<std::array<std::size_t, 3>> common;  // (cell, its edge to i, its edge to j)
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto [i, j] = edges[e];
    common.clear();
    for (auto a = first(i), b = first(j); a != first(i + 1) && b != first(j + 1);) {
      if (a->to < b->to) {
        ++a;
      } else if (b->to < a->to) {
        ++b;
      } else {
        common.push_back({a->to, a->edge, b->edge});
        ++a;
        ++b;
      }
    }
    for (const auto& [k, ik, jk] : common)  // a cell on the edge splits it
      if (rank[ik] < rank[e] && rank[jk] < rank[e] && splits(pos[i], pos[j], pos[k])) blockers.push_back({ik, jk});
    for (std::size_t x = 0; x + 1 < common.size(); ++x) {
      const Index k = static_cast<Index>(common[x][0]);
      for (std::size_t y = x + 1; y < common.size(); ++y) {
        const Index l = static_cast<Index>(common[y][0]);
        const auto kl = std::lower_bound(first(k), first(k + 1), Link{l, 0});  // k's row is short and sorted
        if (kl != first(k + 1) && kl->to == l && rank[kl->edge] < rank[e] &&
            detail::diagonals_cross(pos[i], pos[j], pos[k], pos[l]))
          blockers.push_back({kl->edge, kl->edge});
      }
    }
    block_start[e + 1] = blockers.size();
  }
  // Then, shortest first: an edge stays unless something that stayed blocks it (the blockers are shorter,
  // so they are decided already).
  std::vector<char> kept(edges.size(), 0);
  for (const auto& [len2, e] : order) {
    bool blocked = false;
    for (std::size_t b = block_start[e]; b < block_start[e + 1] && !blocked; ++b)
      blocked = kept[blockers[b].a] && kept[blockers[b].b];
    kept[e] = blocked ? 0 : 1;
  }
  std::vector<std::array<Index, 2>> out;
  out.reserve(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (kept[e]) out.push_back(edges[e]);
  return out;
}

/// Whether triangles uvw1 and uvw2, on side uv, fold onto each other: their third corners seen from the
/// side less than 90 degrees apart round it (or a corner on the side's line). A sheet of one layer never
/// does; overlapping cliques of a crowded sheet do.
bool folded(const std::vector<Vec3>& pos, Index u, Index v, Index w1, Index w2) {
  constexpr double kCosMinFold = 0.0;  // cos 90 degrees
  const Vec3 axis = (pos[v] - pos[u]).normalized();
  auto across = [&](Index w) -> Vec3 {
    const Vec3 d = pos[w] - pos[u];
    return (d - d.dot(axis) * axis).normalized();
  };
  return !(across(w1).dot(across(w2)) < kCosMinFold);
}

/// Closes the 4-cycles of `edges` (sorted, i < j) that have no diagonal and whose four sides each border
/// at most one triangle of `tris` (a gap in the sheet the size of a cell): two triangles on the shorter
/// diagonal (ties: the smaller index pair), unless one would fold onto a side's triangle, lie over one
/// round a corner (detail::stacked_at) or cross one (another sheet passing through the quad). Appends triangles as
/// sorted triples, in a deterministic order; returns the diagonals used (sorted), the only triangle sides that are not
/// edges.
std::vector<std::array<Index, 2>> close_quads(const std::vector<Vec3>& pos,
                                              const std::vector<std::array<Index, 2>>& edges,
                                              std::vector<std::array<Index, 3>>& tris) {
  auto index = [&](Index u, Index v) -> std::size_t {  // edges.size() if not an edge
    const std::array<Index, 2> key{std::min(u, v), std::max(u, v)};
    const auto it = std::lower_bound(edges.begin(), edges.end(), key);
    return it != edges.end() && *it == key ? static_cast<std::size_t>(it - edges.begin()) : edges.size();
  };
  std::vector<std::uint8_t> uses(edges.size(), 0);
  auto use = [&](Index u, Index v) {
    std::uint8_t& c = uses[index(u, v)];
    c = static_cast<std::uint8_t>(std::min(c + 1, 255));
  };
  std::vector<Index> third(edges.size(), kNoIndex);  // the third corner of a side's one triangle
  for (const auto& t : tris) {
    use(t[0], t[1]);
    use(t[1], t[2]);
    use(t[0], t[2]);
    for (int k = 0; k < 3; ++k) third[index(t[(k + 1) % 3], t[(k + 2) % 3])] = t[k];
  }
  std::vector<std::size_t> start(pos.size() + 1, 0);  // adjacency, both directions (CSR)
  for (const auto& [a, b] : edges) {
    ++start[a + 1];
    ++start[b + 1];
  }
  for (std::size_t i = 0; i < pos.size(); ++i) start[i + 1] += start[i];
  std::vector<Index> neighbours(start.back());
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (const auto& [a, b] : edges) {
    neighbours[fill[a]++] = b;
    neighbours[fill[b]++] = a;
  }
  auto adj = [&](Index u) { return std::span<const Index>(neighbours.data() + start[u], start[u + 1] - start[u]); };
  auto open = [&](Index u, Index v) { return uses[index(u, v)] <= 1; };
  auto linked = [&](Index u, Index v) { return index(u, v) < edges.size(); };
  std::vector<std::array<Index, 4>> quads;  // 4-cycles q0-q1-q2-q3; the diagonals (q0, q2), (q1, q3) are not edges
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (uses[e] > 1) continue;
    const auto [a, b] = edges[e];
    for (const Index c : adj(b)) {
      if (c == a || linked(a, c) || !open(b, c)) continue;
      for (const Index d : adj(a)) {
        if (d == b || d == c || linked(b, d) || !linked(c, d) || !open(a, d) || !open(c, d)) continue;
        std::array<Index, 4> q{a, b, c, d};  // named from its smallest corner, then its smaller neighbour
        std::rotate(q.begin(), std::min_element(q.begin(), q.end()), q.end());
        if (q[3] < q[1]) std::swap(q[1], q[3]);
        quads.push_back(q);
      }
    }
  }
  std::sort(quads.begin(), quads.end());
  quads.erase(std::unique(quads.begin(), quads.end()), quads.end());
  double links = 0;  // the typical side: the mean link (a few small triangles must not make all others long)
  std::size_t counted = 0;
  for (const auto& [a, b] : edges)
    if (const double l = (pos[a] - pos[b]).norm(); std::isfinite(l)) links += l, ++counted;
  // nor may the quads' triangles lie over a triangle round a corner, nor cross one
  detail::SheetIndex sheet(pos, tris, counted > 0 ? links / static_cast<double>(counted) : 0.0);
  // A new triangle has the quad's diagonal, which is no link, as a side: it can only repeat a triangle of
  // another quad on the same diagonal, which `diagonals` prevents.
  std::set<std::array<Index, 2>> diagonals;  // closing diagonals used so far
  for (const auto& q : quads) {              // q[0]-q[1]-q[2]-q[3] in a cycle, diagonals (q0, q2) and (q1, q3)
    if (!open(q[0], q[1]) || !open(q[1], q[2]) || !open(q[2], q[3]) || !open(q[3], q[0])) continue;
    // a cell linked to all four corners means the cycle is a wheel already filled (or a fan around it)
    bool filled = false;
    for (const Index v : adj(q[0]))
      filled = filled || (v != q[2] && linked(v, q[1]) && linked(v, q[2]) && linked(v, q[3]));
    if (filled) continue;
    const double d02 = (pos[q[0]] - pos[q[2]]).squaredNorm(), d13 = (pos[q[1]] - pos[q[3]]).squaredNorm();
    const bool first = d02 < d13 || (d02 == d13 && std::min(q[0], q[2]) < std::min(q[1], q[3]));
    std::array<Index, 3> t1 = first ? std::array<Index, 3>{q[0], q[1], q[2]} : std::array<Index, 3>{q[1], q[2], q[3]};
    std::array<Index, 3> t2 = first ? std::array<Index, 3>{q[0], q[2], q[3]} : std::array<Index, 3>{q[1], q[3], q[0]};
    std::sort(t1.begin(), t1.end());
    std::sort(t2.begin(), t2.end());
    const std::array<Index, 2> diagonal = first ? std::array<Index, 2>{std::min(q[0], q[2]), std::max(q[0], q[2])}
                                                : std::array<Index, 2>{std::min(q[1], q[3]), std::max(q[1], q[3])};
    // a side's triangle and the new one on it must not fold onto each other (the quad is no gap then),
    // nor the two new ones on the diagonal (a quad bent or folded across it)
    bool folds = first ? folded(pos, q[0], q[2], q[1], q[3]) : folded(pos, q[1], q[3], q[2], q[0]);
    for (const auto& t : {t1, t2})
      for (int k = 0; k < 3; ++k) {
        const Index u = t[(k + 1) % 3], v = t[(k + 2) % 3];
        const std::size_t e = index(u, v);
        folds = folds || (e < edges.size() && uses[e] == 1 && folded(pos, u, v, t[k], third[e]));
      }
    if (folds || sheet.stacks(t1) || sheet.stacks(t2)) continue;
    // a diagonal another quad closed already would border four triangles
    if (diagonals.count(diagonal) || sheet.crosses(t1, {}) || sheet.crosses(t2, {})) continue;
    diagonals.insert(diagonal);
    sheet.add(t1);
    sheet.add(t2);
    tris.push_back(t1);
    tris.push_back(t2);
    for (int k = 0; k < 4; ++k) use(q[k], q[(k + 1) % 4]);
    for (const auto& t : {t1, t2})
      for (int k = 0; k < 3; ++k) {
        const std::size_t e = index(t[(k + 1) % 3], t[(k + 2) % 3]);
        if (e < edges.size()) third[e] = t[k];
      }
  }
  return {diagonals.begin(), diagonals.end()};
}

/// The triangles of `tris` (3-cliques of the edges in `up`, the CSR adjacency to larger indices of
/// `start`) that lie in one layer: at most two on any side, and those two not folded onto each other
/// (see folded: overlapping triangles, which the links of a crowded or crumpled sheet give, would be
/// non-manifold edges in a modeller), nor lying over one another round a common corner (see stacked_at),
/// nor crossing beyond one (CornerIndex::crosses_at_corner). Greedy, best first: shortest longest side
/// (ties by position in `tris`), a triangle stays unless one of its sides has two already, or one folded
/// onto it, or one stacked with it or crossing it at a corner. Keeps the order of `tris`.
void keep_one_layer(const std::vector<Vec3>& pos, const std::vector<std::size_t>& start, const std::vector<Index>& up,
                    std::vector<std::array<Index, 3>>& tris) {
  auto side = [&](Index u, Index v) {  // the edge's position in up
    const Index a = std::min(u, v), b = std::max(u, v);
    return static_cast<std::size_t>(
        std::lower_bound(up.begin() + static_cast<long>(start[a]), up.begin() + static_cast<long>(start[a + 1]), b) -
        up.begin());
  };
  std::vector<std::pair<double, std::size_t>> order(tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const Vec3 &a = pos[tris[t][0]], &b = pos[tris[t][1]], &c = pos[tris[t][2]];
    order[t] = {std::max({(a - b).squaredNorm(), (b - c).squaredNorm(), (c - a).squaredNorm()}), t};
  }
  std::sort(order.begin(), order.end());
  std::vector<std::array<Index, 2>> third(up.size(), {kNoIndex, kNoIndex});  // third corners of the kept triangles
  std::vector<std::uint8_t> keep(tris.size(), 0);
  detail::CornerIndex kept(pos.size(), tris, {});
  for (const auto& [longest, t] : order) {
    const auto& tri = tris[t];
    std::size_t e[3];
    bool ok = true;
    for (int k = 0; k < 3 && ok; ++k) {
      const Index u = tri[(k + 1) % 3], v = tri[(k + 2) % 3];
      e[k] = side(u, v);
      const auto& th = third[e[k]];
      if (th[1] != kNoIndex)
        ok = false;  // two already
      else if (th[0] != kNoIndex)
        ok = !folded(pos, u, v, tri[k], th[0]);
    }
    if (!ok || kept.stacks(pos, tri) || kept.crosses_at_corner(pos, tri)) continue;
    keep[t] = 1;
    kept.add(tri);
    for (int k = 0; k < 3; ++k) {
      auto& th = third[e[k]];
      th[th[0] == kNoIndex ? 0 : 1] = tri[k];
    }
  }
  std::size_t w = 0;
  for (std::size_t t = 0; t < tris.size(); ++t)
    if (keep[t]) tris[w++] = tris[t];
  tris.resize(w);
}

}  // namespace

Surface triangulate(const Cells& cells, bool one_layer) {
  const std::size_t n = cells.size();
  const std::size_t stride = static_cast<std::size_t>(cells.link_stride);
  Surface s;

  // Undirected edges, (i < j), sorted and unique.
  auto& edges = s.edges;
  for (std::size_t i = 0; i < n; ++i) {
    const auto a = static_cast<Index>(i);
    for (std::size_t k = 0; k < stride && i * stride + k < cells.links.size(); ++k) {
      const Index b = cells.links[i * stride + k];
      if (b != kNoIndex && b != a && b < n) edges.push_back({std::min(a, b), std::max(a, b)});
    }
    const Index p = cells.vein_parent[i];
    if (p != kNoIndex && p != a && p < n) edges.push_back({std::min(a, p), std::max(a, p)});
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

  // One layer: the edges the triangles are made of leave out long edges that cross or run along shorter
  // ones (see uncrossed); s.edges keeps every link.
  const std::vector<std::array<Index, 2>> faces_edges = one_layer ? uncrossed(cells.position, edges) : edges;

  // Adjacency to larger indices only (CSR); lists are sorted because edges are.
  std::vector<std::size_t> start(n + 1, 0);
  for (const auto& e : faces_edges) ++start[e[0] + 1];
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<Index> up(faces_edges.size());
  for (std::size_t e = 0; e < faces_edges.size(); ++e) up[e] = faces_edges[e][1];  // sorted by e[0] already

  // Triangles a < b < c: c in up(a) and up(b).
  auto& tris = s.triangles;
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t x = start[a]; x < start[a + 1]; ++x) {
      const Index b = up[x];
      auto ia = up.begin() + static_cast<long>(x) + 1, ea = up.begin() + static_cast<long>(start[a + 1]);
      auto ib = up.begin() + static_cast<long>(start[b]), eb = up.begin() + static_cast<long>(start[b + 1]);
      while (ia != ea && ib != eb) {
        if (*ia < *ib) {
          ++ia;
        } else if (*ib < *ia) {
          ++ib;
        } else {
          tris.push_back({static_cast<Index>(a), b, *ia});
          ++ia;
          ++ib;
        }
      }
    }
  }

  std::vector<std::array<Index, 2>> sides = faces_edges;  // every triangle side (and edges without one), sorted
  if (one_layer) {
    keep_one_layer(cells.position, start, up, tris);
    const std::vector<std::array<Index, 2>> diagonals = close_quads(cells.position, faces_edges, tris);
    std::sort(tris.begin(), tris.end());
    const auto middle = sides.insert(sides.end(), diagonals.begin(), diagonals.end());
    std::inplace_merge(sides.begin(), middle, sides.end());
  }

  // Triangles around each side: (side index, triangle) pairs sorted by side. The sides are the links the
  // triangles use, and the diagonals of closed quads, which are not links.
  auto edge_index = [&](Index u, Index v) {  // every side is there
    const std::array<Index, 2> key{std::min(u, v), std::max(u, v)};
    return static_cast<std::size_t>(std::lower_bound(sides.begin(), sides.end(), key) - sides.begin());
  };
  std::vector<std::pair<std::size_t, std::size_t>> incidence;
  incidence.reserve(tris.size() * 3);
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) incidence.push_back({edge_index(tris[t][k], tris[t][(k + 1) % 3]), t});
  std::sort(incidence.begin(), incidence.end());
  std::vector<std::size_t> inc_start(sides.size() + 1, 0);
  for (const auto& [e, t] : incidence) ++inc_start[e + 1];
  for (std::size_t e = 0; e < sides.size(); ++e) inc_start[e + 1] += inc_start[e];

  // Does triangle t traverse u -> v?
  auto has_directed = [&](std::size_t t, Index u, Index v) {
    for (int k = 0; k < 3; ++k)
      if (tris[t][k] == u && tris[t][(k + 1) % 3] == v) return true;
    return false;
  };

  // Orientation: a walk over manifold sides (exactly two triangles), each new triangle made to run the
  // shared side the other way from the one it is reached from. Where a sheet cannot be oriented (its
  // triangles overlap where it crowds or buckles, so that some cycle of them comes back flipped), the walk
  // leaves a seam: two neighbours facing opposite ways. Flattest first (by the cosine between the two
  // normals once the newcomer is made consistent, in kFlatLevels steps from -1 to 1; nearly a maximum
  // spanning tree of the triangles' dual graph) puts every seam on about the sharpest fold of its cycle
  // instead of in the middle of a flat sheet, where a breadth-first walk could meet itself. Seeds in index
  // order keep their sorted orientation, and each level is first in, first out, so the result is
  // deterministic.
  std::vector<Vec3> unit_normal(tris.size());  // as each triangle runs now (negated when it is turned)
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const auto& c = tris[t];
    const Vec3 nv = (cells.position[c[1]] - cells.position[c[0]]).cross(cells.position[c[2]] - cells.position[c[0]]);
    const double len = nv.norm();
    unit_normal[t] = len > 0 ? Vec3(nv / len) : Vec3::Zero();
  }
  struct Reach {
    std::size_t tri;  // the newcomer
    Index u, v;       // the side as the reaching triangle runs it
  };
  constexpr int kFlatLevels = 64;
  std::vector<std::vector<Reach>> level(kFlatLevels + 1);  // by flatness, each read from `head` on
  std::vector<std::size_t> head(kFlatLevels + 1, 0);
  int top = -1;  // no level above holds a Reach not yet read
  std::vector<std::uint8_t> seen(tris.size(), 0);
  std::vector<std::size_t> component;  // the triangles the walk from one seed reached
  auto reach_from = [&](std::size_t t) {
    const Vec3 nt = unit_normal[t];
    for (int k = 0; k < 3; ++k) {
      const Index u = tris[t][k], v = tris[t][(k + 1) % 3];
      const std::size_t e = edge_index(u, v);
      if (inc_start[e + 1] - inc_start[e] != 2) continue;  // boundary or non-manifold side
      for (std::size_t x = inc_start[e]; x < inc_start[e + 1]; ++x) {
        const std::size_t o = incidence[x].second;
        if (o == t || seen[o]) continue;
        const double c = has_directed(o, u, v) ? -nt.dot(unit_normal[o]) : nt.dot(unit_normal[o]);
        // (a NaN, from coordinates so large the cross product overflows, goes to the lowest level)
        const int l = c > -1 ? std::min(static_cast<int>((std::min(c, 1.0) + 1) * (kFlatLevels / 2)), kFlatLevels) : 0;
        level[static_cast<std::size_t>(l)].push_back({o, u, v});
        top = std::max(top, l);
      }
    }
  };
  for (std::size_t seed = 0; seed < tris.size(); ++seed) {
    if (seen[seed]) continue;
    seen[seed] = 1;
    component.assign(1, seed);
    reach_from(seed);
    while (top >= 0) {
      const auto lt = static_cast<std::size_t>(top);
      if (head[lt] == level[lt].size()) {  // drained: go down a level
        level[lt].clear();
        head[lt] = 0;
        --top;
        continue;
      }
      const Reach r = level[lt][head[lt]++];
      if (seen[r.tri]) continue;
      if (has_directed(r.tri, r.u, r.v)) {
        std::swap(tris[r.tri][1], tris[r.tri][2]);
        unit_normal[r.tri] = -unit_normal[r.tri];
      }
      seen[r.tri] = 1;
      component.push_back(r.tri);
      reach_from(r.tri);
    }
    // Which side faces out, by one score that changes with the shape by little steps, so that a growing
    // sheet's frames keep their faces (a test of its holes' loops against the area, then of a volume's size,
    // taken one way then the other as the coral grew, turned it inside out every few frames: two holes meeting
    // at a cell made one long loop; an export audit). Its terms: the area vector's upward part as a fraction
    // of the area (1 for a flat sheet facing up, 0 for a closed one), plus the volume held about the centroid,
    // outward, as a fraction of a ball's of that area (1 for a ball, about 1 for a hemisphere, 0 for a flat or
    // evenly ruffled sheet), weighed by how closed the piece is: 1 less its area vector's length as a fraction
    // of its area (1 closed, 1/2 a hemisphere, 0 a flat sheet; a closed surface's area vector is 0 however its
    // holes' edges run). So a closed or nearly closed piece faces out, an open sheet up (a leaf's normals point
    // to the sky, a small fragment of a ruffled sheet's too), and a spherical bowl out from about a hemisphere
    // on. Where the score is 0 (a vertical sheet: both terms), by the area vector: +z, then +y, then +x.
    Vec3 centre = Vec3::Zero();
    for (const std::size_t t : component)
      centre += cells.position[tris[t][0]] + cells.position[tris[t][1]] + cells.position[tris[t][2]];
    centre /= 3.0 * static_cast<double>(component.size());
    double volume = 0, area = 0;      // six times the signed volume about the centre; the area
    Vec3 area_vector = Vec3::Zero();  // twice the vector area
    for (const std::size_t t : component) {
      const Vec3 a = cells.position[tris[t][0]] - centre, b = cells.position[tris[t][1]] - centre,
                 c = cells.position[tris[t][2]] - centre;
      volume += a.dot(b.cross(c));
      const Vec3 normal = (b - a).cross(c - a);
      area_vector += normal;
      area += normal.norm() / 2;
    }
    constexpr double kBall = 0.0940315;  // a ball's volume over its area^1.5: (4/3 pi) / (4 pi)^1.5
    const double closed = std::max(0.0, 1 - area_vector.norm() / (2 * area));
    const double held = volume / 6 / (kBall * std::pow(area, 1.5)), upward = area_vector.z() / (2 * area);
    const double score = closed * held + upward;
    bool flip = false;
    if (std::abs(score) > 1e-6)
      flip = score < 0;
    else
      for (int axis : {2, 1, 0})
        if (std::abs(area_vector[axis]) > 1e-6 * area_vector.norm()) {
          flip = area_vector[axis] < 0;
          break;
        }
    if (flip)
      for (const std::size_t t : component) std::swap(tris[t][1], tris[t][2]);
  }

  if (one_layer) detail::fill_small_holes(cells.position, sides, inc_start, incidence, tris);
  return s;
}

std::vector<std::array<Index, 3>> covering_triangles(const Cells& cells) {
  std::vector<std::array<Index, 3>> out = triangulate(cells, false).triangles;
  auto sorted = [](std::array<Index, 3> t) {
    std::sort(t.begin(), t.end());
    return t;
  };
  std::vector<std::array<Index, 3>> have;  // corner sets, sorted
  have.reserve(out.size());
  for (const auto& t : out) have.push_back(sorted(t));
  std::sort(have.begin(), have.end());
  for (const auto& t : triangulate(cells, true).triangles)
    if (!std::binary_search(have.begin(), have.end(), sorted(t))) out.push_back(t);
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a[0] < b[0]; });
  return out;
}

}  // namespace cellform::cells
