// Test helper: the reference algorithm of auxin canalisation for canalisation_test.cpp.
// Oracle: the straightforward two-phase algorithm (a symmetric CSR of all links, then one breadth-first
// pass to find the layers and one per layer to choose downstreams), kept verbatim as the definition of
// the semantics. The optimised canalise must reproduce it bit for bit.
#pragma once

#include <cstdint>
#include <vector>

#include "cells/simulation.h"
#include "venation/canalisation.h"

namespace cellform::venation::testing::oracle {

using cells::CellType;
using core::Index;
using core::kNoIndex;

inline bool is_vein_node(CellType t) { return t == CellType::vein || t == CellType::petiole; }

struct Result {
  venation::Report report;
  std::vector<Index> downstream;
};

inline Result canalise(cells::Cells& c, const venation::Params& p, const venation::SourceRule& source_rule) {
  const std::size_t n = c.size();
  Result result;
  venation::Report& report = result.report;
  std::vector<double>& flow = cells::attribute(c, venation::kFlow);
  std::vector<double>& radius = cells::attribute(c, venation::kRadius);
  std::vector<double>& order = cells::attribute(c, venation::kOrder);
  std::vector<double>& fx = cells::attribute(c, venation::kFlowX);
  std::vector<double>& fy = cells::attribute(c, venation::kFlowY);
  std::vector<double>& fz = cells::attribute(c, venation::kFlowZ);

  std::vector<double> src(n);
  for (std::size_t i = 0; i < n; ++i) src[i] = source_rule ? source_rule(c, static_cast<Index>(i)) : p.source;

  // symmetric adjacency (CSR): edges enumerated by source cell, link slots then vein parent
  const std::size_t stride = static_cast<std::size_t>(c.link_stride);
  std::vector<Index> adj_start(n + 1, 0), adj, next;
  auto each_edge = [&](auto&& visit) {
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t k = 0; k < stride; ++k) {
        const Index j = c.links[i * stride + k];
        if (j != kNoIndex && j < n && j != i) visit(static_cast<Index>(i), j);
      }
      const Index par = c.vein_parent[i];
      if (par != kNoIndex && par < n && par != i) visit(static_cast<Index>(i), par);
    }
  };
  each_edge([&](Index a, Index b) {
    ++adj_start[a + 1];
    ++adj_start[b + 1];
  });
  for (std::size_t i = 0; i < n; ++i) adj_start[i + 1] += adj_start[i];
  adj.resize(adj_start[n]);
  next.assign(adj_start.begin(), adj_start.end() - 1);
  each_edge([&](Index a, Index b) {
    adj[next[a]++] = b;
    adj[next[b]++] = a;
  });

  // phase 1
  std::vector<std::int32_t> layer(n, -1);
  std::vector<Index> frontier, ord;
  for (std::size_t i = 0; i < n; ++i)
    if (is_vein_node(c.type[i])) {
      layer[i] = 0;
      frontier.push_back(static_cast<Index>(i));
    }
  std::vector<Index>& downstream = result.downstream;
  downstream.assign(n, kNoIndex);
  std::vector<double> key(n);
  for (std::size_t i = 0; i < n; ++i) key[i] = is_vein_node(c.type[i]) ? flow[i] : 0.0;
  for (std::int32_t L = 0; !frontier.empty(); ++L) {
    next.clear();
    for (const Index f : frontier)
      for (Index s = adj_start[f]; s < adj_start[f + 1]; ++s) {
        const Index j = adj[s];
        if (layer[j] == -1) {
          layer[j] = L + 1;
          next.push_back(j);
        }
      }
    for (const Index j : next) {
      Index best = kNoIndex;
      double best_key = -1;
      for (Index s = adj_start[j]; s < adj_start[j + 1]; ++s) {
        const Index m = adj[s];
        if (layer[m] != L) continue;
        if (key[m] > best_key || (key[m] == best_key && m < best)) {
          best = m;
          best_key = key[m];
        }
      }
      downstream[j] = best;
      key[j] = src[j];
      if (L > 0) key[best] += src[j];
      ord.push_back(j);
    }
    frontier.swap(next);
  }
  for (std::size_t i = 0; i < n; ++i) flow[i] = src[i];
  for (auto it = ord.rbegin(); it != ord.rend(); ++it) flow[downstream[*it]] += flow[*it];

  // phase 2
  const cells::VeinChildren children = cells::vein_children(c);
  std::vector<Index> vorder;
  for (std::size_t i = 0; i < n; ++i) {
    const Index par = c.vein_parent[i];
    if (is_vein_node(c.type[i]) && (par == kNoIndex || !is_vein_node(c.type[par])))
      vorder.push_back(static_cast<Index>(i));
  }
  for (std::size_t h = 0; h < vorder.size(); ++h) {
    const Index v = vorder[h];
    for (Index s = children.start[v]; s < children.start[v + 1]; ++s)
      if (is_vein_node(c.type[children.child[s]])) vorder.push_back(children.child[s]);
  }
  for (auto it = vorder.rbegin(); it != vorder.rend(); ++it) {
    const Index par = c.vein_parent[*it];
    if (par != kNoIndex && is_vein_node(c.type[par])) flow[par] += flow[*it];
  }
  std::vector<bool> is_root(n, false);
  for (const Index v : vorder) is_root[v] = c.vein_parent[v] == kNoIndex || !is_vein_node(c.type[c.vein_parent[v]]);
  for (std::size_t i = 0; i < n; ++i) {
    const Index d = is_vein_node(c.type[i]) ? c.vein_parent[i] : downstream[i];
    core::Vec3 dir = core::Vec3::Zero();
    if (d != kNoIndex && d < n) {
      dir = c.position[d] - c.position[i];
      const double len = dir.norm();
      dir = len > 0 ? core::Vec3(dir / len) : core::Vec3::Zero();
    }
    fx[i] = dir.x();
    fy[i] = dir.y();
    fz[i] = dir.z();
    radius[i] = is_vein_node(c.type[i]) ? venation::murray_radius(flow[i], p) : 0.0;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (layer[i] == -1) {
      ++report.unconnected;
      continue;
    }
    report.total_source += src[i];
    if (c.type[i] == CellType::petiole && (c.vein_parent[i] == kNoIndex)) report.petiole_inflow += flow[i];
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (layer[i] != 1 || c.type[i] != CellType::general || flow[i] <= p.threshold) continue;
    c.type[i] = CellType::vein;
    c.vein_parent[i] = downstream[i];
    radius[i] = venation::murray_radius(flow[i], p);
    ++report.promoted;
  }
  // orders on the forest with the promoted cells as new leaves (the roots and the order of visits as
  // before promotion, as the leaves were added to it)
  const cells::VeinChildren now = cells::vein_children(c);
  for (std::size_t i = 0; i < n; ++i) order[i] = 0;
  for (const Index v : vorder) {
    const bool root = is_root[v];
    if (root) order[v] = 1;
    Index main = kNoIndex;
    for (Index s = now.start[v]; s < now.start[v + 1]; ++s) {
      const Index ch = now.child[s];
      if (!is_vein_node(c.type[ch])) continue;
      if (main == kNoIndex || flow[ch] > flow[main]) main = ch;
    }
    for (Index s = now.start[v]; s < now.start[v + 1]; ++s) {
      const Index ch = now.child[s];
      if (!is_vein_node(c.type[ch])) continue;
      order[ch] = root ? 1 : (ch == main ? order[v] : order[v] + 1);
    }
  }

  for (std::size_t i = 0; i < n; ++i) report.vein_cells += c.type[i] == CellType::vein ? 1 : 0;
  return result;
}

}  // namespace cellform::venation::testing::oracle
