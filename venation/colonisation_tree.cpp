// Space colonisation: whole runs in one call, and the vein tree's edges and Murray widths (computed once,
// at the end, from the veinlets towards the base).
#include <cmath>

#include "core/errors.h"
#include "venation/colonisation_impl.h"

namespace cellform::venation {

using core::InvalidInput;

std::vector<std::pair<Index, Index>> VeinTree::edges() const {
  std::vector<std::pair<Index, Index>> e;
  for (Index i = 0; i < parent.size(); ++i)
    if (parent[i] != kNoIndex) e.emplace_back(parent[i], i);
  e.insert(e.end(), anastomoses.begin(), anastomoses.end());
  return e;
}

VeinTree with_stems(const VeinTree& tree, const std::vector<Vec3>& anchors, double min_length) {
  std::vector<Index> roots;
  for (Index i = 0; i < tree.size(); ++i)
    if (tree.parent[i] == kNoIndex) roots.push_back(i);
  if (roots.size() != anchors.size())
    throw InvalidInput("with_stems: " + std::to_string(anchors.size()) + " anchors for " +
                       std::to_string(roots.size()) + " roots");
  VeinTree out;
  std::vector<Index> stem_of(tree.size(), kNoIndex);
  for (std::size_t k = 0; k < roots.size(); ++k)
    if ((anchors[k] - tree.positions[roots[k]]).norm() > min_length) {
      stem_of[roots[k]] = static_cast<Index>(out.positions.size());
      out.positions.push_back(anchors[k]);
      out.parent.push_back(kNoIndex);
      out.birth_step.push_back(0);
    }
  const auto shift = static_cast<Index>(out.positions.size());
  for (Index i = 0; i < tree.size(); ++i) {
    out.positions.push_back(tree.positions[i]);
    out.parent.push_back(tree.parent[i] != kNoIndex ? tree.parent[i] + shift : stem_of[i]);
    out.birth_step.push_back(i < tree.birth_step.size() ? tree.birth_step[i] : 0);
  }
  for (const auto& [a, b] : tree.anastomoses) out.anastomoses.emplace_back(a + shift, b + shift);
  return out;
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

std::size_t independent_cycles(const VeinTree& tree) {
  const std::size_t n = tree.size();
  std::vector<Index> up(n);  // union-find: a node's representative
  for (std::size_t i = 0; i < n; ++i) up[i] = static_cast<Index>(i);
  auto find = [&](Index x) {
    while (up[x] != x) x = up[x] = up[up[x]];
    return x;
  };
  std::size_t cycles = 0;
  auto join = [&](Index a, Index b) {
    if (a >= n || b >= n) return;
    a = find(a);
    b = find(b);
    if (a == b)
      ++cycles;  // the edge closes a cycle
    else
      up[std::max(a, b)] = std::min(a, b);
  };
  for (std::size_t i = 0; i < n; ++i)
    if (tree.parent[i] != kNoIndex) join(static_cast<Index>(i), tree.parent[i]);
  for (const auto& [a, b] : tree.anastomoses) join(a, b);
  return cycles;
}

}  // namespace cellform::venation
