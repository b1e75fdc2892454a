// Benchmarks of space-colonisation venation (Runions et al. 2005): vein nodes per second for whole runs,
// the poplar of Table 1, and memory per node.
#include <malloc.h>

#include <algorithm>
#include <chrono>

#include "bench/bench.h"
#include "core/errors.h"
#include "venation/colonisation.h"

namespace cellform::bench {

namespace {

using venation::Neighbourhood;
using venation::VenationType;

/// An ellipse of `length` x 0.66 `length` without growth: d_k = D = 1, b_s = b_v = 10, rho = 0.002 darts
/// per unit area per step. Closed patterns give about 50,000 nodes at length 935 and 500,000 at 2960,
/// open ones at 1100 and 3480 (the node count grows with the area).
std::pair<venation::Leaf, venation::ColonisationParams> ellipse_run(double length, VenationType type, Neighbourhood nb,
                                                                    int threads) {
  venation::ShapeParams sp;
  sp.length = length;
  sp.width = 0.66 * length;
  venation::Leaf leaf;
  leaf.outline = venation::make_outline(sp);
  venation::ColonisationParams p;
  p.type = type;
  p.neighbourhood = nb;
  p.kill_distance = 1;
  p.node_distance = 1;
  p.source_birth_distance = p.vein_birth_distance = 10;
  p.darts_per_area = 0.002;
  p.seed = 42;
  p.threads = threads;
  return {leaf, p};
}

/// One whole run; nodes per second.
double nodes_per_second(double length, VenationType type, Neighbourhood nb, int threads = 1) {
  const auto [leaf, p] = ellipse_run(length, type, nb, threads);
  const auto a = std::chrono::steady_clock::now();
  const auto [tree, report] = venation::colonise(leaf, p);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
  return static_cast<double>(tree.size()) / s;
}

/// Heap bytes in use (glibc): small blocks plus mmapped large ones.
double heap_in_use() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd);
}

/// Peak heap in use during a closed exact run (sampled after every step and with the tree copied out),
/// above what was in use before, per vein node. Heap rather than resident memory: freed memory that
/// malloc keeps from earlier runs would hide the growth of resident memory.
double bytes_per_node(double length) {
  const auto [leaf, p] = ellipse_run(length, VenationType::closed, Neighbourhood::exact, 1);
  const double before = heap_in_use();
  double peak = before;
  venation::Colonisation c(leaf, p);
  while (!c.done()) {
    c.step();
    peak = std::max(peak, heap_in_use());
  }
  const venation::VeinTree tree = c.tree();
  peak = std::max(peak, heap_in_use());
  return (peak - before) / static_cast<double>(tree.size());
}

/// Table 1 of Runions et al. 2005, poplar (Figure 18): closed, d_k = 1, b_s = 2, L_i = 115, isogonic
/// growth to L_f = 3500 by Delta L = 9, rho = 200e-6, segment length D = 1, exact neighbourhoods. Set up
/// as the script API does (b_v = b_s, darts * 1e-6, isogonic = uniform growth, lengths = scales of an
/// outline of length 1). Outline: as examples/colonisation/poplar.lua, ovate, width 0.85, 40 small teeth.
std::pair<venation::Leaf, venation::ColonisationParams> poplar(int threads, double scale, bool lazy = true) {
  venation::ShapeParams sp;
  sp.kind = venation::ShapeKind::ovate;  // the outline of examples/colonisation/poplar.lua
  sp.length = 1;
  sp.width = 0.85;
  sp.teeth = {{0.008, 40}};
  venation::Leaf leaf;
  leaf.outline = venation::make_outline(sp);
  venation::ColonisationParams p;
  p.type = VenationType::closed;
  p.neighbourhood = Neighbourhood::exact;
  p.kill_distance = 1;
  p.source_birth_distance = p.vein_birth_distance = 2;
  p.node_distance = 1;
  p.darts_per_area = 200e-6;
  p.growth = venation::GrowthMode::uniform;
  p.initial_scale = 115 * scale;  // scale as examples/colonisation/poplar.lua's `scale`
  p.final_scale = 3500 * scale;
  p.scale_step = 9 * scale;
  p.seed = 1;
  p.threads = threads;
  p.lazy_sectors = lazy;
  return {leaf, p};
}

/// Seconds for the poplar at `scale` of Table 1's size; a run still going after `limit` seconds is
/// stopped and reported as `limit` (the full size takes far longer than a benchmark should).
double poplar_seconds(int threads, double scale, double limit, bool lazy = true) {
  const auto [leaf, p] = poplar(threads, scale, lazy);
  const auto a = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count(); };
  try {
    venation::colonise(leaf, p, [&](std::size_t, std::size_t) { return elapsed() < limit; });
  } catch (const core::Cancelled&) {
    return limit;
  }
  return elapsed();
}

const Register r1{{"venation.colonisation.open.50k", "nodes/s",
                   "open space colonisation, whole run, about 50,000 nodes (ellipse 1100 long, b = 10, rho = 0.002)", 3,
                   [] { return nodes_per_second(1100, VenationType::open, Neighbourhood::exact); }}};
const Register r2{
    {"venation.colonisation.closed.exact.50k", "nodes/s",
     "closed space colonisation, exact relative neighbourhoods (Eq. 2), about 50,000 nodes (ellipse 935 long)", 3,
     [] { return nodes_per_second(935, VenationType::closed, Neighbourhood::exact); }}};
const Register r2t{{"venation.colonisation.closed.exact.50k.t2", "nodes/s",
                    "as closed.exact.50k with 2 threads for the per-source neighbourhoods (same result)", 3,
                    [] { return nodes_per_second(935, VenationType::closed, Neighbourhood::exact, 2); }}};
const Register r3{{"venation.colonisation.closed.urquhart.50k", "nodes/s",
                   "closed space colonisation, Urquhart approximation, about 50,000 nodes (ellipse 935 long)", 1,
                   [] { return nodes_per_second(935, VenationType::closed, Neighbourhood::urquhart); }}};
const Register r4{{"venation.colonisation.open.500k", "nodes/s",
                   "open space colonisation, about 500,000 nodes (ellipse 3480 long); one repetition", 1,
                   [] { return nodes_per_second(3480, VenationType::open, Neighbourhood::exact); }}};
const Register r5{{"venation.colonisation.closed.exact.500k", "nodes/s",
                   "closed, exact, about 500,000 nodes (ellipse 2960 long); one repetition", 1,
                   [] { return nodes_per_second(2960, VenationType::closed, Neighbourhood::exact); }}};
const Register r6{{"venation.colonisation.closed.urquhart.500k", "nodes/s",
                   "closed, Urquhart, about 500,000 nodes (ellipse 2960 long); one repetition, slow", 1,
                   [] { return nodes_per_second(2960, VenationType::closed, Neighbourhood::urquhart); }}};
const Register r7{{"venation.colonisation.poplar", "s",
                   "Table 1 poplar (Figure 18): closed, exact, b_s = 2, isogonic growth 115 -> 3500, 2 threads; "
                   "stopped at 900 s (900 = not finished)",
                   1, [] { return poplar_seconds(2, 1.0, 900); }}};
const Register r7f{{"venation.colonisation.poplar.eager", "s",
                    "as venation.colonisation.poplar with lazy_sectors off (the same pattern); the ratio is what lazy "
                    "sectors gain at full size",
                    1, [] { return poplar_seconds(2, 1.0, 900, false); }}};
const Register r7b{{"venation.colonisation.poplar.0.2", "s",
                    "the same at scale 0.2 (leaf 23 -> 700), the default of examples/colonisation/poplar.lua", 3,
                    [] { return poplar_seconds(2, 0.2, 900); }}};
const Register r7c{{"venation.colonisation.poplar.0.5", "s",
                    "the same at scale 0.5 (leaf 57.5 -> 1750): between 0.2 and full size the time grows far faster "
                    "than the nodes, because sources wait in the fast-growing tip (see docs/benchmarks.md)",
                    1, [] { return poplar_seconds(2, 0.5, 900); }}};
const Register r7d{{"venation.colonisation.poplar.0.7", "s",
                    "the same at scale 0.7 (leaf 80.5 -> 2450); most sources wait far from the veins", 1,
                    [] { return poplar_seconds(2, 0.7, 900); }}};
const Register r7e{{"venation.colonisation.poplar.0.7.eager", "s",
                    "as poplar.0.7 with lazy_sectors off: every source updates its six sector bests every step "
                    "(the same pattern; the ratio is what lazy sectors gain)",
                    1, [] { return poplar_seconds(2, 0.7, 900, false); }}};
const Register r8{{"venation.colonisation.memory.50k", "bytes/node",
                   "peak heap in use during a closed exact run of about 50,000 nodes (with its tree), per node", 1,
                   [] { return bytes_per_node(935); }}};
const Register r9{{"venation.colonisation.memory.500k", "bytes/node",
                   "the same for about 500,000 nodes: equal to memory.50k when memory is linear in nodes", 1,
                   [] { return bytes_per_node(2960); }}};

}  // namespace

}  // namespace cellform::bench
