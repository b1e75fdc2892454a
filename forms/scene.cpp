// Scene stepping: forces, attractors, integration, obstacles, division, petioles, canalisation.
#include "forms/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "core/random.h"

namespace cellform::forms {

void validate(const SceneDescription& description) {
  cells::validate(description.cells);
  if (description.venation) venation::validate(*description.venation);
  validate(description.obstacles);
  validate(description.attractors);
  for (const PetioleSpec& p : description.petioles)
    if (!p.at.allFinite()) throw core::InvalidInput("petiole.at must be a finite position");
  if (!(description.obstacle_margin >= 0) || !std::isfinite(description.obstacle_margin))
    throw core::InvalidInput("obstacle margin must be a finite number >= 0 (model units)");
}

core::Index make_petiole(cells::Cells& cells, const Vec3& at, bool fixed, double rest_length) {
  if (!at.allFinite()) throw core::InvalidInput("petiole position must be finite");
  core::Index best = core::kNoIndex;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const double d2 = (cells.position[i] - at).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = static_cast<core::Index>(i);
    }
  }
  if (best != core::kNoIndex && best_d2 > 9 * rest_length * rest_length) {
    const Vec3& near = cells.position[best];
    throw core::InvalidInput("petiole at " + core::point_text(at.x(), at.y(), at.z()) + " is " +
                             core::number_text(std::sqrt(best_d2)) + " model units from the nearest cell, at " +
                             core::point_text(near.x(), near.y(), near.z()) +
                             "; a petiole must be a cell of the form (within 3 rest lengths of one)");
  }
  if (best == core::kNoIndex || best_d2 > 0.25 * rest_length * rest_length)
    return cells::add_cell(cells, at, cells::CellType::petiole, fixed);
  cells.type[best] = cells::CellType::petiole;
  if (fixed) cells.fixed[best] = 1;          // fixed = false does not free a cell a script fixed (cell{fixed = true})
  cells.vein_parent[best] = core::kNoIndex;  // a new sink roots the veins that drain into it
  return best;
}

Scene::Scene(SceneDescription description, std::uint64_t seed)
    : desc_((validate(description), std::move(description))),
      seed_(seed),
      sim_(desc_.cells, seed),
      obstacles_(desc_.obstacles) {
  if (!desc_.obstacles.empty()) {
    // A daughter is placed half a rest length from its mother after the step's constraints. Not inside a
    // solid: there it goes to the mother's other side (a solid's nearest way out, at the next step, may cross a
    // mesh, or lead through the solid's far side); nor across a mesh, which only stops moves.
    const double margin = desc_.obstacle_margin > 0 ? desc_.obstacle_margin : 0.01 * desc_.cells.rest_length;
    sim_.rules().place = [this, margin](const cells::Cells& c, core::Index mother, const Vec3& daughter) {
      const Vec3& m = c.position[mother];
      const Vec3 here = obstacles_.stop_at_mesh(m, daughter, margin);
      if (!obstacles_.inside_solid(here, margin)) return here;
      const Vec3 there = obstacles_.stop_at_mesh(m, 2 * m - daughter, margin);
      // both inside: pushed out at the next step, unless that way out crosses a mesh (then it stays)
      return obstacles_.inside_solid(there, margin) ? here : there;
    };
  }
  if (desc_.split_along_auxin) {
    // divide along the local auxin flow; cells without flow yet split in a seeded random direction within the
    // sheet, as "tangent" (any direction left the sheet, for planarisation to pull back)
    sim_.rules().split_direction = [this](const cells::Cells& c, core::Index i) -> Vec3 {
      auto get = [&](const char* name) {
        auto it = c.attributes.find(name);
        return it == c.attributes.end() ? 0.0 : it->second[i];
      };
      const Vec3 d(get(venation::kFlowX), get(venation::kFlowY), get(venation::kFlowZ));
      if (d.squaredNorm() > 0.25) return d;
      core::StreamRng rng(core::stream_key(seed_, c.id[i], c.generation[i]));
      return cells::random_tangent(c, i, rng);
    };
  }
}

void Scene::apply_petioles(std::uint64_t step) {
  std::vector<std::pair<core::Index, const PetioleSpec*>> made;  // this step's: two on one cell are one sink
  for (const PetioleSpec& p : desc_.petioles)
    if (p.step == step) try {
        const std::size_t before = sim_.cells().size();
        const core::Index i = make_petiole(sim_.cells(), p.at, p.fixed, desc_.cells.rest_length);
        const auto same = std::find_if(made.begin(), made.end(), [i](const auto& m) { return m.first == i; });
        if (same != made.end() && note_) {
          const Vec3& at = sim_.cells().position[i];
          std::string other = same->second->origin;  // "leaf.lua:3: " -> "leaf.lua:3"
          while (!other.empty() && (other.back() == ' ' || other.back() == ':')) other.pop_back();
          note_(p.origin + "the petiole at " + core::point_text(p.at.x(), p.at.y(), p.at.z()) + " (step " +
                std::to_string(step) + ") fell on the cell of " +
                (other.empty() ? std::string("an earlier petiole") : "the petiole of " + other) + ", at " +
                core::point_text(at.x(), at.y(), at.z()) +
                " (the nearest cell, within half a rest length): the two are one sink; place petioles at least a "
                "rest length apart for two");
        }
        made.emplace_back(i, &p);
        // a new cell inside a solid would stay there (and its daughters): obstacles only stop crossings
        if (sim_.cells().size() > before)
          check_outside(desc_.obstacles, {sim_.cells().position[i]}, desc_.obstacle_names, sim_.threads(), &obstacles_);
      } catch (const core::InvalidInput& e) {
        throw core::InvalidInput(p.origin + "petiole (step " + std::to_string(step) + "): " + e.what());
      }
}

void Scene::start() {
  apply_petioles(sim_.step_count());
  check_outside(desc_.obstacles, sim_.cells().position, desc_.obstacle_names, sim_.threads(), &obstacles_);
  if (!desc_.obstacles.meshes.empty()) {  // the cells' links, on a copy (the first step's, but for ties in distance)
    cells::Cells linked = sim_.cells();
    core::PointGrid grid;
    cells::update_links(linked, desc_.cells, grid, sim_.threads());
    check_links_clear(obstacles_, linked, desc_.obstacle_names, sim_.threads());
  }
  if (desc_.venation) {
    bool any = false;
    for (const cells::CellType t : sim_.cells().type) any = any || t == cells::CellType::petiole;
    if (!any)
      throw core::InvalidInput(
          desc_.venation_origin +
          "venation needs a petiole (the sink of the auxin flow) before the first step; add petiole{at = {x, y, z}}");
  }
}

cells::StepReport Scene::step() {
  const double margin = desc_.obstacle_margin > 0 ? desc_.obstacle_margin : 0.01 * desc_.cells.rest_length;
  const bool has_obstacles = !desc_.obstacles.empty();
  const int threads = sim_.threads();
  cells::StepReport report = sim_.step(
      [&](cells::Cells& c) {
        if (has_obstacles) previous_ = c.position;
        if (!desc_.attractors.empty()) apply_attractors(c, desc_.attractors);
      },
      [&](cells::Cells& c) {
        if (has_obstacles) obstacles_.apply(c, previous_, margin, threads);
      });
  apply_petioles(sim_.step_count());
  if (desc_.venation && sim_.step_count() % desc_.venation->every == 0) {
    vein_report_ = venation::canalise(sim_.cells(), *desc_.venation, source_rule_, vein_ws_, threads);
  } else if (desc_.venation && report.divisions > 0) {
    // between passes (venation.every > 1) a vein cell's daughter, a general cell, copied its mother's vein
    // radius and order: a general cell has neither
    cells::Cells& c = sim_.cells();
    const auto radius = c.attributes.find(venation::kRadius), order = c.attributes.find(venation::kOrder);
    for (std::size_t i = 0; i < c.size(); ++i)
      if (c.type[i] == cells::CellType::general) {
        if (radius != c.attributes.end()) radius->second[i] = 0;
        if (order != c.attributes.end()) order->second[i] = 0;
      }
  }
  return report;
}

}  // namespace cellform::forms
