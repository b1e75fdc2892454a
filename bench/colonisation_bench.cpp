// Benchmarks of space-colonisation venation (Runions et al. 2005): vein nodes per second for whole runs.
#include <chrono>

#include "bench/bench.h"
#include "venation/colonisation.h"

namespace cellform::bench {

namespace {

/// One whole run on an ellipse of `length` x 0.66 `length` without growth: d_k = D = 1, b_s = b_v = 10,
/// rho = 0.002 darts per unit area per step (about 50,000 closed nodes at length 935). Nodes per second.
double nodes_per_second(double length, venation::VenationType type, venation::Neighbourhood nb) {
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
  const auto a = std::chrono::steady_clock::now();
  const auto [tree, report] = venation::colonise(leaf, p);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
  return static_cast<double>(tree.size()) / s;
}

using venation::Neighbourhood;
using venation::VenationType;

const Register r1{{"venation.colonisation.open.50k", "nodes/s",
                   "open space colonisation, whole run, about 50,000 nodes (ellipse 1100 long, b = 10, rho = 0.002)", 3,
                   [] { return nodes_per_second(1100, VenationType::open, Neighbourhood::exact); }}};
const Register r2{
    {"venation.colonisation.closed.exact.50k", "nodes/s",
     "closed space colonisation, exact relative neighbourhoods (Eq. 2), about 50,000 nodes (ellipse 935 long)", 3,
     [] { return nodes_per_second(935, VenationType::closed, Neighbourhood::exact); }}};
const Register r3{{"venation.colonisation.closed.urquhart.10k", "nodes/s",
                   "closed space colonisation, Urquhart approximation, about 10,000 nodes (ellipse 420 long)", 1,
                   [] { return nodes_per_second(420, VenationType::closed, Neighbourhood::urquhart); }}};

}  // namespace

}  // namespace cellform::bench
