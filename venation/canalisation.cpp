// Two-phase auxin flow and vein promotion, linear in cells and links.
#include "venation/canalisation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/errors.h"
#include "core/parallel.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cellform::venation {

void add_attributes(cells::Cells& c) {
  for (const char* name : {kFlow, kRadius, kOrder, kFlowX, kFlowY, kFlowZ}) cells::attribute(c, name);
}

bool has_attributes(const cells::Cells& c) {
  for (const char* name : {kFlow, kRadius, kOrder, kFlowX, kFlowY, kFlowZ})
    if (!c.attributes.count(name)) return false;
  return true;
}

using cells::CellType;

void validate(const Params& p) {
  auto need = [](bool ok, const std::string& name, const std::string& allowed, double got) {
    if (!ok) throw core::InvalidInput("venation." + name + " must be " + allowed + ", got " + core::number_text(got));
  };
  need(std::isfinite(p.threshold) && p.threshold > 0, "threshold", "a number > 0 (auxin units, about upstream cells)",
       p.threshold);
  need(std::isfinite(p.source) && p.source >= 0, "source", "a number >= 0", p.source);
  need(std::isfinite(p.murray_exponent) && p.murray_exponent >= 1 && p.murray_exponent <= 4, "murray_exponent",
       "a number from 1 to 4", p.murray_exponent);
  need(std::isfinite(p.radius_scale) && p.radius_scale > 0, "radius_scale", "a number > 0 (model units)",
       p.radius_scale);
  need(std::isfinite(p.min_radius) && p.min_radius >= 0 && p.min_radius <= std::numeric_limits<float>::max(),
       "min_radius", "a number from 0 to 3.4e38 (model units; the files keep radii as 32-bit numbers)", p.min_radius);
  need(p.every >= 1, "every", "a whole number >= 1 (steps)", p.every);
}

double murray_radius(double flow, const Params& p) {
  return std::max(p.min_radius, p.radius_scale * std::pow(std::max(flow, 0.0), 1.0 / p.murray_exponent));
}

namespace {

// Flows are sums of sources; the cell and vein files keep them as 32-bit floats.
constexpr double kMaxFlow = static_cast<double>(std::numeric_limits<float>::max());

bool is_vein_node(CellType t) { return t == CellType::vein || t == CellType::petiole; }

// The link graph is the symmetric closure of each cell's row: its k-nearest links (slots in order)
// and its vein parent, skipping kNoIndex, out-of-range and self entries. The breadth-first search
// must visit the neighbours of a cell x in the order of the edge list "each cell in index order, its
// row in slot order", because that order decides which cells a layer reaches first. Seen from x that
// order is: the cells i < x whose row holds x (ascending), then x's own row in slot order, then the
// cells i > x whose row holds x (ascending); repeats change nothing. Most links are mutual, so instead
// of building the whole edge list each step, every cell gets its own row re-ordered (the mutual
// neighbours below x first, ascending) and the few one-way in-links ("extras") go into a small CSR.

constexpr std::size_t kChunk = 4096;       // cells per fixed chunk of the parallel passes
constexpr std::uint8_t kUnreached = 0xff;  // layer code of a cell the search has not reached
constexpr std::uint8_t kNoLayer = 0xfe;    // matches no cell
constexpr std::uint8_t kSentinel = 0xfd;   // layer code of the padding entry n of the rows
constexpr std::size_t kAhead = 16;         // queue entries between a row's prefetch and its use

// Layer codes: 0 and 1 exactly (vein nodes and the cells next to them), then 2, 3, 4 cyclically.
// A cell of layer L has neighbours only in layers L - 1, L and L + 1, which get distinct codes.
std::uint8_t layer_code(std::size_t layer) {
  return layer < 2 ? static_cast<std::uint8_t>(layer) : static_cast<std::uint8_t>(2 + (layer - 2) % 3);
}

/// Whether cell t's row (links, then vein parent) holds x; S = link stride, or 0 for any stride.
template <int S>
bool row_holds(const Index* links, const Index* parent, std::size_t stride, Index t, Index x) {
  const Index* l = links + static_cast<std::size_t>(t) * (S > 0 ? S : stride);
#if defined(__SSE2__)
  if constexpr (S == 6) {
    const __m128i xv = _mm_set1_epi32(static_cast<int>(x));
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(l));
    const __m128i b = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(l + 4));
    const int hits = _mm_movemask_epi8(_mm_cmpeq_epi32(a, xv)) | (_mm_movemask_epi8(_mm_cmpeq_epi32(b, xv)) & 0xff);
    return (hits != 0) | (parent[t] == x);
  }
#endif
  bool found = parent[t] == x;
  for (std::size_t k = 0; k < (S > 0 ? static_cast<std::size_t>(S) : stride); ++k) found |= l[k] == x;
  return found;
}

// Per-cell row summary: how many mutual neighbours below the cell lead the row, the row's length
// (entries past it are the padding n), and whether the search must take the general path: one-way
// in-links reach the cell, or its row is full (links and a vein parent; the fast path reads only as
// many entries as there are link slots).
constexpr std::uint32_t kCountBits = 11;  // row width <= 1025
constexpr std::uint32_t kCountMask = (1u << kCountBits) - 1;
constexpr std::uint32_t kHasExtra = 1u << 31;
constexpr std::uint32_t kGeneral = 1u << 30;

/// Row of every cell of chunk `ch` in search order, the extras it sends, its vein nodes; and the
/// per-cell initial state of the search.
template <int S, class Source>
void prepare_chunk(const Cells& c, std::size_t ch, const Source& src, std::vector<double>& flow, Workspace& w) {
  const std::size_t n = c.size();
  const std::size_t stride = S > 0 ? static_cast<std::size_t>(S) : static_cast<std::size_t>(c.link_stride);
  const std::size_t width = stride + 1;
  Workspace::Chunk& out = w.chunks[ch];
  out.extra.clear();
  out.veins.clear();
  constexpr std::size_t kFixed = S > 0 ? static_cast<std::size_t>(S) + 1 : 1;
  Index lower_fixed[kFixed], rest_fixed[kFixed];
  std::vector<Index> lower_any, rest_any;
  Index* lower = lower_fixed;
  Index* rest = rest_fixed;
  if (S == 0) {
    lower_any.resize(width);
    rest_any.resize(width);
    lower = lower_any.data();
    rest = rest_any.data();
  }
  const Index* links = c.links.data();
  const Index* parent = c.vein_parent.data();
  const std::size_t end = std::min(n, (ch + 1) * kChunk);
  for (std::size_t i = ch * kChunk; i < end; ++i) {
    const Index x = static_cast<Index>(i);
    const Index* l = links + i * stride;
    Index* row = w.row.data() + i * width;
    // the mutual neighbours below x first, ascending; then the rest in slot order; then padding
    // (index n, a sentinel whose layer code matches nothing) up to the full width
    std::size_t low = 0, rest_count = 0;
    for (std::size_t k = 0; k < width; ++k) {
      const Index t = k < stride ? l[k] : parent[i];
      if (t >= n || t == x) continue;  // kNoIndex, out of range or itself
      const bool mutual = row_holds<S>(links, parent, stride, t, x);
      if (!mutual) out.extra.push_back({t, x});
      if (mutual && t < x) {
        std::size_t q = low++;
        for (; q > 0 && lower[q - 1] > t; --q) lower[q] = lower[q - 1];
        lower[q] = t;
      } else {
        rest[rest_count++] = t;
      }
    }
    for (std::size_t k = 0; k < width; ++k)  // fixed trip count when S > 0
      row[k] = k < low ? lower[k] : k - low < rest_count ? rest[k - low] : static_cast<Index>(n);
    w.row_info[i] = static_cast<std::uint32_t>(low) | static_cast<std::uint32_t>(low + rest_count) << kCountBits |
                    (low + rest_count == width ? kGeneral : 0u);
    w.downstream[i] = kNoIndex;
    if (is_vein_node(c.type[i])) {
      w.layer[i] = 0;
      w.key[i] = flow[i];  // last step's vein flow decides the first layer's choices
      out.veins.push_back(x);
    } else {
      w.layer[i] = kUnreached;
    }
    flow[i] = src(i);
  }
}

/// Phase 1: one breadth-first pass from the vein nodes; each cell, when taken from the queue, picks
/// its downstream among its neighbours of the previous layer (complete by then, with their flows so
/// far) and reaches its unreached neighbours. The same choices, in the same order, as finding a whole
/// layer first and then choosing for its cells in the order the search reached them.
template <int S, class Source>
void search(const Cells& c, const Source& src, Workspace& w) {
  const std::size_t width = S > 0 ? static_cast<std::size_t>(S) + 1 : static_cast<std::size_t>(c.link_stride) + 1;
  std::uint8_t* layer = w.layer.data();
  double* key = w.key.data();
  Index* queue = w.queue.data();
  const Index* extra = w.extra.data();
  w.candidates.resize(width);
  Index* cand = w.candidates.data();
  std::size_t head = 0, tail = 0;
  for (const Workspace::Chunk& ch : w.chunks)
    for (const Index v : ch.veins) queue[tail++] = v;
  std::size_t layer_end = tail, L = 0;
  std::uint8_t prev = kNoLayer, next = layer_code(1);
  // per layer code: in the previous layer? not reached yet? the code after a visit (reached -> next)
  std::array<std::uint8_t, 256> in_prev{}, unreached{}, after_visit{};
  for (std::size_t v = 0; v < 256; ++v) after_visit[v] = static_cast<std::uint8_t>(v);
  unreached[kUnreached] = 1;
  after_visit[kUnreached] = next;
  while (head < tail) {
    if (head == layer_end) {
      ++L;
      layer_end = tail;
      in_prev[prev] = 0;
      prev = layer_code(L - 1);
      next = layer_code(L + 1);
      in_prev[prev] = 1;
      after_visit[kUnreached] = next;
    }
    if (head + kAhead < tail) {  // the queue jumps around the sheet: fetch rows early (large sheets)
      const Index ahead = queue[head + kAhead];
      __builtin_prefetch(w.row.data() + static_cast<std::size_t>(ahead) * width);
      __builtin_prefetch(w.row_info.data() + ahead);
    }
    const Index x = queue[head++];
    Index best = kNoIndex;
    double best_key = -std::numeric_limits<double>::infinity();  // any flow a state holds beats it
    auto consider = [&](Index m) {
      if (key[m] > best_key || (key[m] == best_key && m < best)) {
        best = m;
        best_key = key[m];
      }
    };
    const Index* row = w.row.data() + static_cast<std::size_t>(x) * width;
    const std::uint32_t info = w.row_info[x];
    const std::size_t low = info & kCountMask, count = (info >> kCountBits) & kCountMask;
    if (!(info & (kHasExtra | kGeneral))) {
      // branch-free: neighbours are in the previous layer or not, reached or not, at random; the
      // previous-layer ones are collected and compared after the scan (their keys do not change in it)
      std::size_t nc = 0, t = tail;                           // locals: byte stores into layer cannot alias them
      const std::size_t entries = S > 0 ? width - 1 : count;  // padding visits the sentinel
      for (std::size_t k = 0; k < entries; ++k) {
        const Index m = row[k];
        const std::uint8_t lm = layer[m];
        cand[nc] = m;
        nc += in_prev[lm];
        layer[m] = after_visit[lm];
        queue[t] = m;  // room for one more than every cell
        t += unreached[lm];
      }
      tail = t;
      for (std::size_t k = 0; k < nc; ++k) consider(cand[k]);
    } else {
      auto visit = [&](Index m) {
        const std::uint8_t lm = layer[m];
        if (lm == prev) consider(m);
        if (lm == kUnreached) {
          layer[m] = next;
          queue[tail++] = m;
        }
      };
      Index e = w.extra_start[x];
      const Index e_end = w.extra_start[x + 1];
      std::size_t k = 0;
      for (;;) {  // merge the mutual neighbours below x with the one-way in-links from below x
        const bool has_row = k < low, has_extra = e < e_end && extra[e] < x;
        if (!has_row && !has_extra) break;
        if (has_row && (!has_extra || row[k] < extra[e]))
          visit(row[k++]);
        else
          visit(extra[e++]);
      }
      for (; k < count; ++k) visit(row[k]);
      for (; e < e_end; ++e) visit(extra[e]);
    }
    if (L == 0) continue;
    w.downstream[x] = best;
    key[x] = src(x);                 // x's own auxin; its upstream attaches in the next layer
    if (L > 1) key[best] += src(x);  // the chosen neighbour's flow so far grows
  }
  w.queue.resize(tail);
}

/// Exact sequential sum of `count` copies of s (from 0) when every partial sum is representable.
bool exact_multiple(double s, std::size_t count, double& sum) {
  if (!(s > 0) || !std::isfinite(s)) return false;
  int e = 0;
  double m = std::ldexp(std::frexp(s, &e), 53);  // s's significand as an integer
  while (std::fmod(m, 2.0) == 0) m /= 2;
  if (m * static_cast<double>(count) >= 0x1p53) return false;
  sum = s * static_cast<double>(count);
  return true;
}

template <class Source>
Report run(Cells& c, const Params& p, const Source& src, bool uniform, Workspace& w, int threads) {
  const std::size_t n = c.size();
  const std::size_t width = static_cast<std::size_t>(c.link_stride) + 1;
  Report report;
  report.cells = n;
  std::vector<double>& flow = cells::attribute(c, kFlow);
  std::vector<double>& radius = cells::attribute(c, kRadius);
  std::vector<double>& order = cells::attribute(c, kOrder);
  std::vector<double>& fx = cells::attribute(c, kFlowX);
  std::vector<double>& fy = cells::attribute(c, kFlowY);
  std::vector<double>& fz = cells::attribute(c, kFlowZ);

  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  w.chunks.resize(chunks);
  w.row.resize(n * width);
  w.layer.resize(n + 1);
  w.key.resize(n);
  w.downstream.resize(n);
  w.row_info.resize(n);
  w.queue.resize(n + 1);
  core::parallel_for(
      chunks, threads,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t ch = b; ch < e; ++ch)
          if (c.link_stride == 6)
            prepare_chunk<6>(c, ch, src, flow, w);
          else
            prepare_chunk<0>(c, ch, src, flow, w);
      },
      1);

  // one-way in-links by target; sources stay ascending (chunks in order, cells in order within).
  // Counts go to start[t + 2] so that filling through start[t + 1] leaves start[t] = first of t.
  w.extra_start.assign(n + 2, 0);
  for (const Workspace::Chunk& ch : w.chunks)
    for (const auto& [t, s] : ch.extra) ++w.extra_start[t + 2];
  for (std::size_t i = 0; i <= n; ++i) w.extra_start[i + 1] += w.extra_start[i];
  w.extra.resize(w.extra_start[n + 1]);
  for (const Workspace::Chunk& ch : w.chunks)
    for (const auto& [t, s] : ch.extra) {
      w.extra[w.extra_start[t + 1]++] = s;
      w.row_info[t] |= kHasExtra | kGeneral;
    }

  w.layer[n] = kSentinel;
  if (c.link_stride == 6)
    search<6>(c, src, w);
  else
    search<0>(c, src, w);

  // final flows of non-vein cells: reverse breadth-first order, each adds its total downstream
  std::size_t veins = 0;
  for (const Workspace::Chunk& ch : w.chunks) veins += ch.veins.size();
  for (std::size_t q = w.queue.size(); q-- > veins;) {
    const Index x = w.queue[q];
    flow[w.downstream[x]] += flow[x];
  }

  // Phase 2: through the vein forest (vein nodes only), tips to petioles.
  const Index* vnode = w.queue.data();  // the vein nodes in index order
  w.vein_id.resize(n);
  for (std::size_t a = 0; a < veins; ++a) w.vein_id[vnode[a]] = static_cast<Index>(a);
  auto vein_parent = [&](Index v) -> Index {  // parent if it is a vein node, else kNoIndex (a root)
    const Index par = c.vein_parent[v];
    return par != kNoIndex && par < n && is_vein_node(c.type[par]) ? par : kNoIndex;
  };
  w.vein_start.assign(veins + 1, 0);
  for (std::size_t a = 0; a < veins; ++a) {
    const Index par = vein_parent(vnode[a]);
    if (par != kNoIndex) ++w.vein_start[w.vein_id[par] + 1];
  }
  for (std::size_t a = 0; a < veins; ++a) w.vein_start[a + 1] += w.vein_start[a];
  w.vein_child.resize(w.vein_start[veins]);
  w.vein_fill.assign(w.vein_start.begin(), w.vein_start.end() - 1);
  w.vein_order.clear();
  for (std::size_t a = 0; a < veins; ++a) {  // ascending: children come out sorted
    const Index par = vein_parent(vnode[a]);
    if (par != kNoIndex)
      w.vein_child[w.vein_fill[w.vein_id[par]]++] = static_cast<Index>(a);
    else
      w.vein_order.push_back(static_cast<Index>(a));  // roots, ascending
  }
  const std::size_t roots = w.vein_order.size();  // (promotion below may hang a root on a new vein cell)
  // breadth-first from the roots gives parents before children
  for (std::size_t h = 0; h < w.vein_order.size(); ++h) {
    const Index a = w.vein_order[h];
    for (Index s = w.vein_start[a]; s < w.vein_start[a + 1]; ++s) w.vein_order.push_back(w.vein_child[s]);
  }
  for (std::size_t h = w.vein_order.size(); h-- > 0;) {
    const Index v = vnode[w.vein_order[h]];
    const Index par = vein_parent(v);
    if (par != kNoIndex) flow[par] += flow[v];
  }

  // Per cell: flow direction and radius of the state before promotion; then promotion of the cells
  // next to a vein (layer 1) whose flow passes the threshold. Each cell writes only its own slots and
  // reads vein nodes, which this pass does not change.
  core::parallel_for(
      chunks, threads,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t ch = b; ch < e; ++ch) {
          Workspace::Chunk& out = w.chunks[ch];
          out.promoted = out.vein_cells = out.unconnected = 0;
          out.promoted_cells.clear();
          const std::size_t end = std::min(n, (ch + 1) * kChunk);
          for (std::size_t i = ch * kChunk; i < end; ++i) {
            const bool vein = is_vein_node(c.type[i]);
            const Index d = vein ? c.vein_parent[i] : w.downstream[i];
            Vec3 dir = Vec3::Zero();
            if (d != kNoIndex && d < n) {
              dir = c.position[d] - c.position[i];
              const double len = dir.norm();
              dir = len > 0 ? Vec3(dir / len) : Vec3::Zero();
            }
            fx[i] = dir.x();
            fy[i] = dir.y();
            fz[i] = dir.z();
            if (vein) {
              radius[i] = murray_radius(flow[i], p);
              out.vein_cells += c.type[i] == CellType::vein;
              continue;
            }
            radius[i] = 0.0;
            order[i] = 0;
            const std::uint8_t l = w.layer[i];
            out.unconnected += l == kUnreached;
            if (l != 1 || c.type[i] != CellType::general || flow[i] <= p.threshold) continue;
            c.type[i] = CellType::vein;
            c.vein_parent[i] = w.downstream[i];
            radius[i] = murray_radius(flow[i], p);
            out.promoted_cells.push_back(static_cast<Index>(i));
            ++out.promoted;
            ++out.vein_cells;
          }
        }
      },
      1);
  for (const Workspace::Chunk& ch : w.chunks) {
    report.promoted += ch.promoted;
    report.vein_cells += ch.vein_cells;
    report.unconnected += ch.unconnected;
  }

  // Orders of the forest as it is now, the cells just promoted being new leaves of it: the roots' children
  // are primary; at every other vein node the child of the largest flow (ties: the smaller index) continues
  // its order and the others start the next. (Ordered before promotion, a promoted cell took its parent's
  // order, though a child of larger flow had it: two primaries at one fork until the next step.)
  w.promoted_start.assign(veins + 1, 0);
  for (const Workspace::Chunk& ch : w.chunks)
    for (const Index x : ch.promoted_cells) ++w.promoted_start[w.vein_id[c.vein_parent[x]] + 1];
  for (std::size_t a = 0; a < veins; ++a) w.promoted_start[a + 1] += w.promoted_start[a];
  w.promoted_child.resize(w.promoted_start[veins]);
  w.vein_fill.assign(w.promoted_start.begin(), w.promoted_start.end() - 1);
  for (const Workspace::Chunk& ch : w.chunks)  // chunks in order, cells ascending: children come out sorted
    for (const Index x : ch.promoted_cells) w.promoted_child[w.vein_fill[w.vein_id[c.vein_parent[x]]]++] = x;
  for (std::size_t a = 0; a < veins; ++a) order[vnode[a]] = 0;
  for (std::size_t h = 0; h < w.vein_order.size(); ++h) {
    const Index a = w.vein_order[h], v = vnode[a];
    const bool root = h < roots;
    if (root) order[v] = 1;
    Index main = kNoIndex;
    auto consider = [&](Index ch) {
      if (main == kNoIndex || flow[ch] > flow[main] || (flow[ch] == flow[main] && ch < main)) main = ch;
    };
    for (Index s = w.vein_start[a]; s < w.vein_start[a + 1]; ++s) consider(vnode[w.vein_child[s]]);
    for (Index s = w.promoted_start[a]; s < w.promoted_start[a + 1]; ++s) consider(w.promoted_child[s]);
    auto assign = [&](Index ch) { order[ch] = root ? 1 : (ch == main ? order[v] : order[v] + 1); };
    for (Index s = w.vein_start[a]; s < w.vein_start[a + 1]; ++s) assign(vnode[w.vein_child[s]]);
    for (Index s = w.promoted_start[a]; s < w.promoted_start[a + 1]; ++s) assign(w.promoted_child[s]);
  }

  // report: conservation at the petioles, summed in index order
  if (!uniform || !exact_multiple(src(0), n - report.unconnected, report.total_source))
    for (std::size_t i = 0; i < n; ++i)
      if (w.layer[i] != kUnreached) report.total_source += src(i);
  for (std::size_t a = 0; a < veins; ++a) {
    const Index v = vnode[a];
    if (c.type[v] == CellType::petiole && c.vein_parent[v] == kNoIndex) report.petiole_inflow += flow[v];
  }
  return report;
}

/// Refuses a radius_scale that makes the Murray radius of `max_flow` (no cell's flow exceeds the total
/// source) overflow the files' 32-bit radii.
void check_radius_range(double max_flow, const Params& p) {
  const double r = murray_radius(max_flow, p);
  if (!(r <= kMaxFlow))
    throw core::InvalidInput("venation.radius_scale (" + core::number_text(p.radius_scale) +
                             ") gives vein radii up to " + core::number_text(r) + " for the flow of " +
                             core::number_text(max_flow) +
                             " this step can carry (the files keep radii as 32-bit numbers, at most 3.4e38); "
                             "use a smaller radius_scale");
}

}  // namespace

Report canalise(Cells& c, const Params& p, const SourceRule& source_rule, Workspace& w, int threads) {
  const std::size_t n = c.size();
  if (c.link_stride < 0 || c.link_stride > 1024 || c.links.size() != n * static_cast<std::size_t>(c.link_stride))
    throw core::InvalidInput("venation needs 0 to 1024 links per cell (cells.link_stride), got " +
                             std::to_string(c.link_stride));
  if (std::find(c.type.begin(), c.type.end(), CellType::petiole) == c.type.end())
    throw core::InvalidInput(
        "venation needs at least one petiole cell (the sink of the auxin flow); add petiole{at = {x, y, z}}");
  if (!source_rule) {
    const double s = p.source;
    if (!(s * static_cast<double>(n) * 2 <= kMaxFlow))
      throw core::InvalidInput("venation.source (" + core::number_text(s) + ") times " + std::to_string(n) +
                               " cells overflows the flow (the files keep flows as 32-bit numbers, at most 3.4e38); "
                               "use a smaller source strength");
    check_radius_range(s * static_cast<double>(n), p);
    return run(
        c, p, [s](std::size_t) { return s; }, true, w, threads);
  }
  // the rule may be impure (a script): called serially, in index order
  std::vector<double>& src = w.source;
  src.resize(n);
  double total = 0;  // the flows are partial sums of the sources: their total must stay finite
  for (std::size_t i = 0; i < n; ++i) {
    const double s = source_rule(c, static_cast<Index>(i));
    if (!std::isfinite(s) || s < 0)
      throw core::InvalidInput("venation.source must give a finite number >= 0 for every cell; cell " +
                               std::to_string(c.id[i]) + " got " + core::number_text(s));
    total += s;
    if (!(2 * total <= kMaxFlow))
      throw core::InvalidInput(
          "venation.source: the sources add up beyond the range of the files' 32-bit flows "
          "(3.4e38) at cell " +
          std::to_string(c.id[i]) + ", which gave " + core::number_text(s) + "; use smaller source strengths");
    src[i] = s;
  }
  check_radius_range(total, p);
  const double* s = src.data();
  return run(
      c, p, [s](std::size_t i) { return s[i]; }, false, w, threads);
}

VeinGraph vein_graph(const Cells& c, const Params* params) {
  VeinGraph g;
  const std::size_t n = c.size();
  std::vector<std::uint32_t> node(n, 0xffffffffu);
  auto attr = [&](const char* name) -> const std::vector<double>* {
    auto it = c.attributes.find(name);
    return it == c.attributes.end() ? nullptr : &it->second;
  };
  const auto* flow = attr(kFlow);
  const auto* radius = attr(kRadius);
  const auto* order = attr(kOrder);
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_vein_node(c.type[i])) continue;
    node[i] = static_cast<std::uint32_t>(g.cell.size());
    g.cell.push_back(static_cast<Index>(i));
    g.position.push_back(c.position[i]);
    g.flow.push_back(flow ? (*flow)[i] : 0.0);
    g.radius.push_back(radius ? (*radius)[i] : params ? murray_radius(0.0, *params) : 0.0);
    const Index par = c.vein_parent[i];
    const bool root = par == kNoIndex || par >= n || !is_vein_node(c.type[par]);
    g.order.push_back(order ? static_cast<int>((*order)[i]) : root ? 1 : 0);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Index par = c.vein_parent[i];
    if (node[i] != 0xffffffffu && par != kNoIndex && par < n && node[par] != 0xffffffffu)
      g.edges.push_back({node[i], node[par]});
  }
  return g;
}

}  // namespace cellform::venation
