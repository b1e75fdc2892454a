// Checkpoint bytes of the cell arrays: a small header, then every array as raw machine bytes.
#include "cells/serialize.h"

#include "core/errors.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/chunk_file.h"

namespace cellform::cells {

namespace {

constexpr char kMagic[8] = {'C', 'F', 'C', 'E', 'L', 'L', 'S', '1'};
constexpr std::uint32_t kVersion = 1;

std::vector<double> flatten(const std::vector<Vec3>& v) {
  std::vector<double> out(v.size() * 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) out[i * 3 + k] = v[i][k];
  return out;
}

std::vector<Vec3> unflatten(const std::vector<double>& v) {
  std::vector<Vec3> out(v.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = Vec3(v[i * 3], v[i * 3 + 1], v[i * 3 + 2]);
  return out;
}

}  // namespace

std::string save(const Cells& cells) {
  core::ByteWriter w;
  w.put(kMagic);
  w.put<std::uint32_t>(kVersion);
  w.put<std::uint64_t>(cells.size());
  w.put<std::int32_t>(cells.link_stride);
  w.put<std::uint64_t>(cells.next_id);
  w.put_vector(flatten(cells.position));
  w.put_vector(flatten(cells.velocity));
  w.put_vector(flatten(cells.acceleration));
  w.put_vector(cells.age);
  w.put_vector(cells.generation);
  std::vector<std::uint8_t> type(cells.type.size());
  for (std::size_t i = 0; i < type.size(); ++i) type[i] = static_cast<std::uint8_t>(cells.type[i]);
  w.put_vector(type);
  w.put_vector(cells.fixed);
  w.put_vector(cells.id);
  w.put_vector(cells.vein_parent);
  w.put_vector(cells.links);
  w.put<std::uint64_t>(cells.attributes.size());
  for (const auto& [name, values] : cells.attributes) {
    w.put_string(name);
    w.put_vector(values);
  }
  return w.take();
}

Cells load(const std::string& bytes, const std::string& what) {
  core::ByteReader r(bytes, what);
  char magic[8];
  for (char& c : magic) c = r.get<char>();
  if (std::memcmp(magic, kMagic, 8) != 0) throw core::FileError(what + " does not hold cellform cells");
  const auto version = r.get<std::uint32_t>();
  if (version != kVersion)
    throw core::FileError(what + " has cells format version " + std::to_string(version) + "; this cellform reads " +
                          std::to_string(kVersion));
  auto bad = [&](const std::string& why) { return core::FileError(what + " is corrupt (" + why + ")"); };
  Cells c;
  const auto n = r.get<std::uint64_t>();
  c.link_stride = r.get<std::int32_t>();
  c.next_id = r.get<std::uint64_t>();
  if (c.link_stride < 1 || c.link_stride > 1024) throw bad("link stride " + std::to_string(c.link_stride));
  if (n >= kNoIndex) throw bad("too many cells");
  // ids count the cells ever made; far below 2^64, so those made after a resume cannot wrap round
  if (c.next_id > std::uint64_t{1} << 62) throw bad("next cell id " + std::to_string(c.next_id) + " out of range");
  c.position = unflatten(r.get_vector<double>());
  c.velocity = unflatten(r.get_vector<double>());
  c.acceleration = unflatten(r.get_vector<double>());
  c.age = r.get_vector<std::uint32_t>();
  c.generation = r.get_vector<std::uint32_t>();
  const auto type = r.get_vector<std::uint8_t>();
  c.fixed = r.get_vector<std::uint8_t>();
  c.id = r.get_vector<std::uint64_t>();
  c.vein_parent = r.get_vector<Index>();
  c.links = r.get_vector<Index>();
  const auto attributes = r.get<std::uint64_t>();
  for (std::uint64_t a = 0; a < attributes; ++a) {
    std::string name = r.get_string();
    auto values = r.get_vector<double>();
    const std::string shown = core::printable(name.substr(0, 64)) + (name.size() > 64 ? "..." : "");
    if (values.size() != n) throw bad("attribute '" + shown + "' has the wrong length");
    // every attribute (auxin flow, its direction, vein radius and order) is finite in a state a run
    // wrote; a NaN flow would leave a cell next to a vein without a downstream choice
    for (const double v : values)
      if (!std::isfinite(v)) throw bad("non-finite value of attribute '" + shown + "'");
    c.attributes[std::move(name)] = std::move(values);
  }
  if (!r.done()) throw bad("trailing data");
  if (c.position.size() != n || c.velocity.size() != n || c.acceleration.size() != n || c.age.size() != n ||
      c.generation.size() != n || type.size() != n || c.fixed.size() != n || c.id.size() != n ||
      c.vein_parent.size() != n || c.links.size() != n * static_cast<std::uint64_t>(c.link_stride))
    throw bad("array lengths disagree");
  c.type.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (type[i] > static_cast<std::uint8_t>(CellType::vein)) throw bad("unknown cell type");
    c.type[i] = static_cast<CellType>(type[i]);
    if (c.vein_parent[i] != kNoIndex && c.vein_parent[i] >= n) throw bad("vein parent out of range");
    if (c.id[i] >= c.next_id) throw bad("cell id not below next id");
    if (!c.position[i].allFinite() || !c.velocity[i].allFinite()) throw bad("non-finite cell position or velocity");
  }
  for (const Index l : c.links)
    if (l != kNoIndex && l >= n) throw bad("link out of range");
  // the vein parents form a forest, as canalisation makes them: a cell its own ancestor would pull on itself
  // (the vein forces) and walks from it would never end
  std::vector<std::uint8_t> state(n, 0);  // 0 unseen, 1 on the walk from the current cell, 2 reaches a root
  for (std::size_t i = 0; i < n; ++i) {
    Index j = static_cast<Index>(i);
    for (; j != kNoIndex && state[j] == 0; j = c.vein_parent[j]) state[j] = 1;
    if (j != kNoIndex && state[j] == 1)
      throw bad("the vein parents of cell " + std::to_string(c.id[j]) + " lead back to it");
    for (j = static_cast<Index>(i); j != kNoIndex && state[j] == 1; j = c.vein_parent[j]) state[j] = 2;
  }
  return c;
}

}  // namespace cellform::cells
