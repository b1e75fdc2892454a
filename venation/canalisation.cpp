// Two-phase auxin flow and vein promotion, linear in cells and links.
#include "venation/canalisation.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.h"

namespace cellform::venation {

using cells::CellType;

void validate(const Params& p) {
  auto need = [](bool ok, const std::string& name, const std::string& allowed, double got) {
    if (!ok) throw core::InvalidInput("venation." + name + " must be " + allowed + ", got " + std::to_string(got));
  };
  need(std::isfinite(p.threshold) && p.threshold > 0, "threshold", "a number > 0 (auxin units, about upstream cells)",
       p.threshold);
  need(std::isfinite(p.source) && p.source >= 0, "source", "a number >= 0", p.source);
  need(std::isfinite(p.murray_exponent) && p.murray_exponent >= 1 && p.murray_exponent <= 4, "murray_exponent",
       "a number from 1 to 4", p.murray_exponent);
  need(std::isfinite(p.radius_scale) && p.radius_scale > 0, "radius_scale", "a number > 0 (model units)",
       p.radius_scale);
  need(std::isfinite(p.min_radius) && p.min_radius >= 0, "min_radius", "a number >= 0 (model units)", p.min_radius);
  need(p.every >= 1, "every", "a whole number >= 1 (steps)", p.every);
}

double murray_radius(double flow, const Params& p) {
  return std::max(p.min_radius, p.radius_scale * std::pow(std::max(flow, 0.0), 1.0 / p.murray_exponent));
}

namespace {

bool is_vein_node(CellType t) { return t == CellType::vein || t == CellType::petiole; }

/// Symmetric adjacency from the k-nearest links and the vein parent links (CSR).
void build_adjacency(const Cells& c, Workspace& w) {
  const std::size_t n = c.size();
  const std::size_t stride = static_cast<std::size_t>(c.link_stride);
  w.adj_start.assign(n + 1, 0);
  auto each_edge = [&](auto&& visit) {
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t k = 0; k < stride; ++k) {
        const Index j = c.links[i * stride + k];
        if (j != kNoIndex && j < n && j != i) visit(static_cast<Index>(i), j);
      }
      const Index p = c.vein_parent[i];
      if (p != kNoIndex && p < n && p != i) visit(static_cast<Index>(i), p);
    }
  };
  each_edge([&](Index a, Index b) {
    ++w.adj_start[a + 1];
    ++w.adj_start[b + 1];
  });
  for (std::size_t i = 0; i < n; ++i) w.adj_start[i + 1] += w.adj_start[i];
  w.adj.resize(w.adj_start[n]);
  w.next.assign(w.adj_start.begin(), w.adj_start.end() - 1);  // fill pointers
  each_edge([&](Index a, Index b) {
    w.adj[w.next[a]++] = b;
    w.adj[w.next[b]++] = a;
  });
  // rows may hold a neighbour twice (linked both ways); harmless: choices break ties by index
}

}  // namespace

Report canalise(Cells& c, const Params& p, const SourceRule& source_rule, Workspace& w, int threads) {
  (void)threads;
  const std::size_t n = c.size();
  Report report;
  std::vector<double>& flow = cells::attribute(c, kFlow);
  std::vector<double>& radius = cells::attribute(c, kRadius);
  std::vector<double>& order = cells::attribute(c, kOrder);
  std::vector<double>& fx = cells::attribute(c, kFlowX);
  std::vector<double>& fy = cells::attribute(c, kFlowY);
  std::vector<double>& fz = cells::attribute(c, kFlowZ);

  bool any_petiole = false;
  for (std::size_t i = 0; i < n; ++i) any_petiole = any_petiole || c.type[i] == CellType::petiole;
  if (!any_petiole)
    throw core::InvalidInput(
        "venation needs at least one petiole cell (the sink of the auxin flow); add petiole{at = {x, y, z}}");

  // sources
  std::vector<double>& src = w.source;
  src.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!source_rule) {
      src[i] = p.source;
      continue;
    }
    const double s = source_rule(c, static_cast<Index>(i));
    if (!std::isfinite(s) || s < 0)
      throw core::InvalidInput("venation.source must give a finite number >= 0 for every cell; cell " +
                               std::to_string(c.id[i]) + " got " + std::to_string(s));
    src[i] = s;
  }

  build_adjacency(c, w);

  // Phase 1: breadth-first layers outward from the vein nodes.
  w.layer.assign(n, -1);
  w.frontier.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (is_vein_node(c.type[i])) {
      w.layer[i] = 0;
      w.frontier.push_back(static_cast<Index>(i));
    }
  std::vector<Index>& downstream = w.downstream;
  downstream.assign(n, kNoIndex);
  // the flow so far of each cell of the previous layer; for vein nodes, last step's vein flow
  std::vector<double>& key = w.key;
  key.resize(n);
  for (std::size_t i = 0; i < n; ++i) key[i] = is_vein_node(c.type[i]) ? flow[i] : 0.0;
  w.order.clear();
  for (std::int32_t L = 0; !w.frontier.empty(); ++L) {
    w.next.clear();
    for (const Index f : w.frontier)
      for (Index s = w.adj_start[f]; s < w.adj_start[f + 1]; ++s) {
        const Index j = w.adj[s];
        if (w.layer[j] == -1) {
          w.layer[j] = L + 1;
          w.next.push_back(j);
        }
      }
    for (const Index j : w.next) {
      Index best = kNoIndex;
      double best_key = -1;
      for (Index s = w.adj_start[j]; s < w.adj_start[j + 1]; ++s) {
        const Index m = w.adj[s];
        if (w.layer[m] != L) continue;
        if (key[m] > best_key || (key[m] == best_key && m < best)) {
          best = m;
          best_key = key[m];
        }
      }
      downstream[j] = best;
      key[j] = src[j];                 // j's own auxin; its upstream attaches in the next layer
      if (L > 0) key[best] += src[j];  // the chosen neighbour's flow so far grows
      w.order.push_back(j);
    }
    w.frontier.swap(w.next);
  }

  // final flows of non-vein cells: reverse breadth-first order, each adds its total downstream
  for (std::size_t i = 0; i < n; ++i) flow[i] = src[i];
  for (auto it = w.order.rbegin(); it != w.order.rend(); ++it) flow[downstream[*it]] += flow[*it];

  // Phase 2: through the veins, tips to petioles. Vein flow already holds own source + drained cells.
  const cells::VeinChildren children = cells::vein_children(c);
  w.frontier.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const Index par = c.vein_parent[i];
    if (is_vein_node(c.type[i]) && (par == kNoIndex || !is_vein_node(c.type[par])))
      w.frontier.push_back(static_cast<Index>(i));
  }
  // breadth-first from the roots gives parents before children
  std::vector<Index>& vorder = w.next;
  vorder.clear();
  for (const Index r : w.frontier) vorder.push_back(r);
  for (std::size_t h = 0; h < vorder.size(); ++h) {
    const Index v = vorder[h];
    for (Index s = children.start[v]; s < children.start[v + 1]; ++s)
      if (is_vein_node(c.type[children.child[s]])) vorder.push_back(children.child[s]);
  }
  for (auto it = vorder.rbegin(); it != vorder.rend(); ++it) {
    const Index v = *it;
    const Index par = c.vein_parent[v];
    if (par != kNoIndex && is_vein_node(c.type[par])) flow[par] += flow[v];
  }

  // orders: roots' children are primary; the largest-flow child continues its parent's order
  for (std::size_t i = 0; i < n; ++i) order[i] = 0;
  for (const Index v : vorder) {
    const Index par = c.vein_parent[v];
    const bool root = par == kNoIndex || !is_vein_node(c.type[par]);
    if (root) order[v] = 1;
    Index main = kNoIndex;
    for (Index s = children.start[v]; s < children.start[v + 1]; ++s) {
      const Index ch = children.child[s];
      if (!is_vein_node(c.type[ch])) continue;
      if (main == kNoIndex || flow[ch] > flow[main]) main = ch;
    }
    for (Index s = children.start[v]; s < children.start[v + 1]; ++s) {
      const Index ch = children.child[s];
      if (!is_vein_node(c.type[ch])) continue;
      order[ch] = root ? 1 : (ch == main ? order[v] : order[v] + 1);
    }
  }

  // flow directions and radii (of the state before promotion)
  for (std::size_t i = 0; i < n; ++i) {
    const Index d = is_vein_node(c.type[i]) ? c.vein_parent[i] : downstream[i];
    Vec3 dir = Vec3::Zero();
    if (d != kNoIndex && d < n) {
      dir = c.position[d] - c.position[i];
      const double len = dir.norm();
      dir = len > 0 ? Vec3(dir / len) : Vec3::Zero();
    }
    fx[i] = dir.x();
    fy[i] = dir.y();
    fz[i] = dir.z();
    radius[i] = is_vein_node(c.type[i]) ? murray_radius(flow[i], p) : 0.0;
  }

  // report: conservation at the petioles
  for (std::size_t i = 0; i < n; ++i) {
    if (w.layer[i] == -1) {
      ++report.unconnected;
      continue;
    }
    report.total_source += src[i];
    if (c.type[i] == CellType::petiole && (c.vein_parent[i] == kNoIndex)) report.petiole_inflow += flow[i];
  }

  // promotion: cells adjacent to a vein (layer 1) whose flow passes the threshold
  for (std::size_t i = 0; i < n; ++i) {
    if (w.layer[i] != 1 || c.type[i] != CellType::general || flow[i] <= p.threshold) continue;
    c.type[i] = CellType::vein;
    c.vein_parent[i] = downstream[i];
    radius[i] = murray_radius(flow[i], p);
    order[i] = order[downstream[i]] > 0 ? order[downstream[i]] : 1;
    ++report.promoted;
  }
  for (std::size_t i = 0; i < n; ++i) report.vein_cells += c.type[i] == CellType::vein ? 1 : 0;
  return report;
}

VeinGraph vein_graph(const Cells& c) {
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
    g.radius.push_back(radius ? (*radius)[i] : 0.0);
    g.order.push_back(order ? static_cast<int>((*order)[i]) : 0);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Index par = c.vein_parent[i];
    if (node[i] != 0xffffffffu && par != kNoIndex && par < n && node[par] != 0xffffffffu)
      g.edges.push_back({node[i], node[par]});
  }
  return g;
}

}  // namespace cellform::venation
