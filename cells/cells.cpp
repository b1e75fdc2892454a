// Adding cells, attributes, the vein child index and reordering of the cell arrays.
#include "cells/cells.h"

#include <cassert>

namespace cellform::cells {

namespace {

template <class T>
void permute(std::vector<T>& v, const std::vector<Index>& perm) {
  std::vector<T> out;
  out.reserve(perm.size());
  for (const Index old : perm) out.push_back(v[old]);
  v.swap(out);
}

}  // namespace

Index add_cell(Cells& cells, const Vec3& position, CellType type, bool fixed) {
  const auto i = static_cast<Index>(cells.size());
  cells.position.push_back(position);
  cells.velocity.push_back(Vec3::Zero());
  cells.acceleration.push_back(Vec3::Zero());
  cells.age.push_back(0);
  cells.generation.push_back(0);
  cells.type.push_back(type);
  cells.fixed.push_back(fixed ? 1 : 0);
  cells.id.push_back(cells.next_id++);
  cells.vein_parent.push_back(kNoIndex);
  cells.links.resize(cells.size() * static_cast<std::size_t>(cells.link_stride), kNoIndex);
  for (auto& [name, values] : cells.attributes) values.resize(cells.size(), 0.0);
  return i;
}

std::vector<double>& attribute(Cells& cells, const std::string& name, double initial) {
  auto [it, inserted] = cells.attributes.try_emplace(name);
  if (inserted) it->second.assign(cells.size(), initial);
  return it->second;
}

VeinChildren vein_children(const Cells& cells) {
  const std::size_t n = cells.size();
  VeinChildren vc;
  vc.start.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Index p = cells.vein_parent[i];
    if (p != kNoIndex && p < n) ++vc.start[p + 1];
  }
  for (std::size_t i = 0; i < n; ++i) vc.start[i + 1] += vc.start[i];
  vc.child.resize(vc.start[n]);
  std::vector<Index> fill(vc.start.begin(), vc.start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {  // increasing i: children come out sorted
    const Index p = cells.vein_parent[i];
    if (p != kNoIndex && p < n) vc.child[fill[p]++] = static_cast<Index>(i);
  }
  return vc;
}

void reorder(Cells& cells, const std::vector<Index>& perm) {
  const std::size_t n = cells.size();
  assert(perm.size() == n);
  std::vector<Index> inverse(n, kNoIndex);
  for (std::size_t k = 0; k < n; ++k) inverse[perm[k]] = static_cast<Index>(k);
  auto remap = [&](Index i) { return i == kNoIndex || i >= n ? kNoIndex : inverse[i]; };

  permute(cells.position, perm);
  permute(cells.velocity, perm);
  if (cells.acceleration.size() == n) permute(cells.acceleration, perm);
  permute(cells.age, perm);
  permute(cells.generation, perm);
  permute(cells.type, perm);
  permute(cells.fixed, perm);
  permute(cells.id, perm);
  permute(cells.vein_parent, perm);
  for (Index& p : cells.vein_parent) p = remap(p);
  for (auto& [name, values] : cells.attributes) permute(values, perm);

  const std::size_t stride = static_cast<std::size_t>(cells.link_stride);
  std::vector<Index> links(n * stride);
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t j = 0; j < stride; ++j) links[k * stride + j] = remap(cells.links[perm[k] * stride + j]);
  cells.links.swap(links);
}

}  // namespace cellform::cells
