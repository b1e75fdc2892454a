// What a cell run writes and tells of its veins: the cell and vein files, run.json's "veins", and the
// warnings and notes at its end.
#include <algorithm>
#include <iomanip>
#include <sstream>
#include <vector>

#include "app/run_internal.h"
#include "cells/surface.h"
#include "export/cell_files.h"
#include "export/vein_files.h"
#include "venation/canalisation.h"
#include "venation/vein_io.h"

namespace cellform::app {

using nlohmann::json;

namespace {

/// Notes each petiole (a root of the vein forest) that grew no vein: its catchment, the cells nearer to it
/// than to any vein, carried too little auxin.
void say_veinless_petioles(std::ostream& err, const cells::Cells& c, const venation::Params& p) {
  const std::size_t n = c.size();
  std::vector<char> has_child(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (c.vein_parent[i] < n) has_child[c.vein_parent[i]] = 1;
  // linked cells (either way): a petiole without links gets no auxin at all
  const auto stride = static_cast<std::size_t>(std::max(c.link_stride, 0));
  std::vector<char> linked(n, 0);
  for (std::size_t i = 0; i < n && c.links.size() == n * stride; ++i)
    for (std::size_t k = 0; k < stride; ++k) {
      const core::Index j = c.links[i * stride + k];
      if (j < n && j != i) linked[i] = linked[j] = 1;
    }
  const auto flow = c.attributes.find(venation::kFlow);
  const bool any_vein = std::find(c.type.begin(), c.type.end(), cells::CellType::vein) != c.type.end();
  // a pass ran and no cell carries any flow: no source at all (a petiole made after the last pass reads 0 too)
  const bool no_auxin = flow != c.attributes.end() &&
                        std::all_of(flow->second.begin(), flow->second.end(), [](double f) { return f == 0; });
  for (std::size_t i = 0; i < n; ++i) {
    if (c.type[i] != cells::CellType::petiole || c.vein_parent[i] != core::kNoIndex || has_child[i]) continue;
    const core::Vec3& q = c.position[i];
    std::ostringstream at;
    at << std::setprecision(3) << "{" << q.x() << ", " << q.y() << ", " << q.z() << "}";
    if (!linked[i]) {
      // of the linked cells: one born in the last step (the petiole's own daughter, say) is no way in yet
      double linked_nearest = std::numeric_limits<double>::infinity(), any_nearest = linked_nearest;
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i) continue;
        const double d = (c.position[j] - q).norm();
        any_nearest = std::min(any_nearest, d);
        if (linked[j]) linked_nearest = std::min(linked_nearest, d);
      }
      const double nearest = std::isfinite(linked_nearest) ? linked_nearest : any_nearest;
      err << "cellform: note: the petiole at " << at.str() << " (cell " << c.id[i]
          << ") grew no vein: it is linked to no cell, so no auxin reaches it"
          << (std::isfinite(nearest) ? std::string(std::isfinite(linked_nearest) ? " (the nearest linked cell is "
                                                                                 : " (the nearest cell is ") +
                                           core::number_text(nearest) + " model units away)"
                                     : std::string())
          << ". A petiole due at the run's last step is linked only in the next step (run longer); one farther "
             "than cells.link_range from every cell never is (place it nearer the form)\n";
      continue;
    }
    const double reached = flow != c.attributes.end() ? flow->second[i] : 0.0;
    err << "cellform: note: the petiole at " << at.str() << " (cell " << c.id[i]
        << ") grew no vein: the auxin reaching it (" << core::number_text(reached)
        << " in all) never passed venation.threshold (" << core::number_text(p.threshold) << ") in one cell beside it. "
        << (no_auxin   ? "No auxin flows anywhere: the cells make none (venation.source, or the function given for "
                         "it, is 0), and running longer does not change that\n"
            : any_vein ? "A petiole collects only the cells nearer to it than to any vein: one placed (or added at a "
                         "step) where veins already run gets few\n"
                       : "No vein has grown anywhere yet: run longer (more cells, more auxin) or lower "
                         "venation.threshold\n");
  }
}

}  // namespace

json vein_summary(const cells::Cells& c, const venation::Report& last, const json& saved) {
  if (last.cells == 0 && saved.is_object()) return saved;
  if (last.cells > 0)
    return {{"vein_cells", last.vein_cells},
            {"petiole_inflow", last.petiole_inflow},
            {"unconnected_cells", last.unconnected}};
  std::size_t veins = 0;
  double inflow = 0;
  const auto flow = c.attributes.find(venation::kFlow);
  for (std::size_t i = 0; i < c.size(); ++i) {
    veins += c.type[i] == cells::CellType::vein;
    if (c.type[i] == cells::CellType::petiole && c.vein_parent[i] == core::kNoIndex && flow != c.attributes.end())
      inflow += flow->second[i];
  }
  return {{"vein_cells", veins}, {"petiole_inflow", inflow}, {"unconnected_cells", nullptr}};
}

void say_late_starts(std::ostream& err, const forms::SceneDescription& scene, std::uint64_t first,
                     std::uint64_t target) {
  for (const forms::PetioleSpec& p : scene.petioles)  // said now, not found missing at the end
    if (p.step > target && p.step > first)
      err << "cellform: note: " << p.origin << "the petiole due at step " << p.step
          << " comes after the run's last step (" << target
          << "), so this run does not place it; run{steps = N}, --steps N or a resume with --steps N reaches it\n";
  // (a resume past step `every` has had its passes: its veins are there)
  if (scene.venation && target > first && target < scene.venation->every)
    err << "cellform: note: " << scene.venation_origin
        << "canalisation first runs at step venation.every = " << scene.venation->every
        << ", after the run's last step (" << target
        << "), so no vein grows in this run; lower venation.every or run longer\n";
}

void say_loose_supports(std::ostream& err, const cells::Cells& c) {
  // a support may be many fixed cells: one is held when a link either way, directly or through other fixed
  // cells, reaches a cell that moves (a search from those that touch one, over the links among fixed cells)
  if (std::none_of(c.fixed.begin(), c.fixed.end(), [](auto f) { return f != 0; })) return;  // most runs: no work
  const std::size_t n = c.size(), stride = static_cast<std::size_t>(c.link_stride);
  std::vector<std::vector<core::Index>> among(n);  // links between fixed cells, both ways
  std::vector<std::uint8_t> held(n, 0);
  std::vector<core::Index> queue;
  std::size_t fixed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    fixed += c.fixed[i] ? 1 : 0;
    for (std::size_t k = 0; k < stride; ++k) {
      const core::Index j = c.links[i * stride + k];
      if (j == core::kNoIndex || j >= n || (!c.fixed[i] && !c.fixed[j])) continue;
      if (c.fixed[i] && c.fixed[j]) {
        among[i].push_back(j);
        among[j].push_back(static_cast<core::Index>(i));
      } else if (const std::size_t f = c.fixed[i] ? i : j; !held[f]) {
        held[f] = 1;
        queue.push_back(static_cast<core::Index>(f));
      }
    }
  }
  while (!queue.empty()) {
    const core::Index f = queue.back();
    queue.pop_back();
    for (const core::Index g : among[f])
      if (!held[g]) {
        held[g] = 1;
        queue.push_back(g);
      }
  }
  std::size_t loose = 0;
  for (std::size_t i = 0; i < n; ++i) loose += c.fixed[i] && !held[i] ? 1 : 0;
  if (loose == 0 || fixed == n) return;
  err << "cellform: note: " << loose << " of the " << fixed << " fixed cells " << (loose == 1 ? "is" : "are")
      << " linked to no cell that moves, not even through other fixed cells: the sheet is not attached to "
      << (loose == 1 ? "it" : "them") << " (it came loose, or never reached " << (loose == 1 ? "it" : "them")
      << "); a weaker pull away from the supports (cells.unary) or more fixed cells keeps a sheet on them\n";
}

void say_vein_findings(std::ostream& err, const cells::Cells& c, const venation::Report& last,
                       const venation::Params& p, bool notes) {
  if (last.cells == 0) return;  // no canalisation ran in this process
  if (last.unconnected > 0)
    err << "cellform: warning: " << last.unconnected << " of " << last.cells  // at its last canalisation
        << " cells have no path through the links to a petiole: their auxin reaches no petiole and no vein grows "
           "there (a part of the form apart from every petiole, or a petiole off the sheet: place a petiole{at = "
           "...} on that part, on a cell)\n";
  if (notes) say_veinless_petioles(err, c, p);
}

/// Writes the cell outputs of the current state into `dir`; returns their names.
std::vector<std::string> write_outputs(const std::filesystem::path& dir, const OutputSpec& spec, const cells::Cells& c,
                                       const venation::Params* veins) {
  std::vector<std::string> names;
  if (veins) {
    const venation::VeinGraph g = venation::vein_graph(c, veins);
    if (spec.ply) {
      exporters::write_veins_ply(dir / "veins.ply", g, c);
      names.push_back("veins.ply");
    }
    if (spec.obj) {
      exporters::write_veins_obj(dir / "veins.obj", g);
      names.push_back("veins.obj");
    }
  }
  if (!spec.ply && !spec.obj) return names;  // (the surface of a dense form takes seconds to find)
  const cells::Surface surface = cells::triangulate(c);
  if (spec.ply) {
    // before the first canalisation (--steps 0): the attributes of the later files, none flowing yet, so that
    // a script's files have one layout (on a copy, made only then)
    const bool bare = veins && !c.attributes.count(venation::kFlow);
    cells::Cells placed;
    if (bare) {
      placed = c;
      venation::add_attributes(placed);
    }
    exporters::write_cells_ply(dir / "cells.ply", bare ? placed : c, surface);
    names.push_back("cells.ply");
  }
  if (spec.obj) {
    exporters::write_cells_obj(dir / "cells.obj", c, surface);
    names.push_back("cells.obj");
  }
  return names;
}

std::vector<std::string> output_names(const SceneConfig& cfg) {
  std::vector<std::string> names;
  const bool colonisation = cfg.colonisation.has_value();
  for (const std::string ext : {"ply", "obj"})
    if (ext == "ply" ? cfg.output.ply : cfg.output.obj) {
      if (!colonisation || cfg.colonisation->on_cells) names.push_back("cells." + ext);
      if (colonisation || cfg.scene.venation) names.push_back("veins." + ext);
    }
  if (colonisation && cfg.colonisation->domain.kind == venation::DomainKind::leaf) names.push_back("veins.svg");
  if (colonisation && cfg.output.png) names.push_back("veins.png");
  if (cfg.print)
    for (const std::string& f : cfg.print->formats) names.push_back("printable." + f);
  return names;
}

json draw_veins_svg(const std::filesystem::path& staging, const OutputSpec& output, const PrintSpec* print,
                    const json& printed, const std::vector<exporters::Segment>& segments,
                    const std::vector<std::array<core::Vec3, 3>>& shell, const venation::VeinTree& tree,
                    const venation::Outline& outline, std::vector<std::string>& outputs, std::ostream& err) {
  venation::SvgParams svg;
  svg.size = output.svg_size > 0 ? output.svg_size : 200;
  // svg_size 0: at the print's scale, so that a cut outline fits the printed veins; a print that failed or
  // was interrupted had its scale planned all the same (an export audit: the drawing came out at 200 mm)
  if (output.svg_size == 0 && printed.contains("scale_mm_per_unit")) {
    svg.scale = printed["scale_mm_per_unit"].get<double>();
  } else if (output.svg_size == 0 && print && !(segments.empty() && shell.empty())) {
    try {
      svg.scale = planned_print_scale(*print, segments, shell);
    } catch (const std::exception&) {  // (such a print failed already, and said why)
    }
  }
  svg.join_veins = output.svg_join_veins;
  const venation::SvgPage page = venation::write_svg(staging / "veins.svg", tree, outline, svg);
  outputs.push_back("veins.svg");
  std::error_code ec;
  err << large_svg_note(std::filesystem::file_size(staging / "veins.svg", ec), svg.join_veins);
  return {{"scale_mm_per_unit", page.scale}, {"width_mm", page.width}, {"height_mm", page.height}};
}

std::string large_svg_note(std::uintmax_t bytes, bool joined) {
  if (bytes < kLargeSvgBytes || bytes == static_cast<std::uintmax_t>(-1)) return {};
  return "cellform: note: veins.svg is " + core::number_text(std::round(static_cast<double>(bytes) / 1e6)) +
         " MB: drawing and laser-cutter programs may take minutes to open it" +
         (joined ? std::string() : "; output{svg_paths = \"veins\"} draws about half as many paths") + "\n";
}

void say_sources_left(std::ostream& err, const ColonisationSpec& spec, const std::vector<core::Vec3>& sources_left,
                      const venation::Outline* outline) {
  const char* const are_left = sources_left.size() == 1 ? " auxin source is left" : " auxin sources are left";
  if (spec.domain.kind == venation::DomainKind::surface)
    err << "cellform: note: " << sources_left.size() << are_left
        << ". Besides those on a sheet the veins do not reach, a source behind a wall or fin "
           "thinner than about 3 vein segments pulls the vein node straight across it (distances are straight), "
           "whose step lands back where it was: the veins stay on one side. "
        << (spec.on_cells ? "Grow such a sheet larger (cells.rest_length) or seed each side\n"
                          : "Scale such a mesh up (surface{scale = ...}) or seed each side\n");
  if (spec.domain.kind == venation::DomainKind::volume)
    err << "cellform: note: " << sources_left.size() << are_left
        << ". A vein node that would step out of the volume is moved back to its boundary, so the veins do not "
           "cross a gap between parts of the mesh, nor pass a neck or bend narrower than a few vein segments: seed "
           "each part (volume{seeds = ...}) or scale the mesh up (volume{scale = ...})\n";
  if (!outline) return;
  const venation::OutlineIndex blade(*outline);
  const auto outside =
      static_cast<std::size_t>(std::count_if(sources_left.begin(), sources_left.end(), [&](const core::Vec3& q) {
        return !blade.contains(venation::Vec2(q.x(), q.y()));
      }));
  std::string where_left;
  if (outside > 0)
    where_left = std::to_string(outside) + " outside the grown blade, where no vein grows (" +
                 (spec.params.growth == venation::GrowthMode::marginal
                      ? std::string("the young blade covered ") + (outside == 1 ? "it" : "them") +
                            " where the grown one leaves a gap, below a lobe or tooth; growth = \"isogonic\" grows "
                            "the whole outline from the start, lobes included)"
                      : std::string("the blade moved off ") + (outside == 1 ? "it)" : "them)"));
  if (outside < sources_left.size())
    where_left += (outside > 0 ? ", " : "") + std::to_string(sources_left.size() - outside) +
                  (outside > 0 ? " inside it" : " inside the blade") + ", where no vein can step towards " +
                  (sources_left.size() - outside == 1 ? "it" : "them") +
                  " (the step would leave the blade, across a sinus, or run back along a vein)";
  err << "cellform: note: " << sources_left.size() << are_left << ": " << where_left << "\n";
}

void say_no_veins(std::ostream& err, const ColonisationSpec& spec, const venation::ColonisationReport& rep,
                  const venation::VeinTree& tree, bool stopped_before_step, bool planar) {
  if (rep.sources_born == 0 && !stopped_before_step) {  // nothing to grow towards: say why
    err << "cellform: warning: no auxin source was placed in " << rep.steps << " steps, so no vein grew (";
    if (rep.darts > 0) err << "all " << rep.darts << " darts fell within the birth distances: ";
    // marginal growth throws every step's darts at the start, over the grown blade's box, keeping those
    // birth_distance apart; none of those the margin reached was (or only one, outside the blade)
    const bool first = rep.darts == 0 && rep.marginal_darts > 0;
    if (first)
      err << (rep.marginal_darts == 1 ? "the 1 dart" : "none of the " + std::to_string(rep.marginal_darts) + " darts")
          << " thrown over the grown blade's box at the start (marginal growth) made "
          << (rep.marginal_darts == 1 ? "no source" : "a source") << " in the blade: ";
    err << (first ? "lower colonisation.birth_distance (it is " + core::number_text(spec.params.source_birth_distance) +
                        ")"
            : rep.darts == 0 ? "no dart was thrown: raise colonisation.darts"
            : rep.finished   ? "lower colonisation.birth_distance or vein_birth_distance"
                             : "raise colonisation.darts, lower colonisation.birth_distance or vein_birth_distance")
        << (planar ? ", or give the leaf room to grow" : "") << (rep.finished ? ")\n" : ", or run more steps)\n");
  } else if (rep.finished && spec.params.type == venation::VenationType::closed &&
             spec.params.kill_distance >= spec.params.vein_birth_distance &&
             std::none_of(tree.parent.begin(), tree.parent.end(), [](core::Index q) { return q != core::kNoIndex; }))
    err << "cellform: warning: " << rep.sources_born
        << " auxin sources were placed, but no vein grew: each was within colonisation.kill_distance ("
        << core::number_text(spec.params.kill_distance) << ") of the veins when it came, so it went at once "
        << "(sources come at least vein_birth_distance, " << core::number_text(spec.params.vein_birth_distance)
        << ", from the veins: make kill_distance smaller than that)\n";
}

std::vector<exporters::Segment> vein_segments(const venation::VeinTree& tree) {
  std::vector<exporters::Segment> segments;
  const auto edges = tree.edges();  // tree edges, then the loops' closing ones
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const auto [p, c] = edges[k];
    const bool closing = k + tree.anastomoses.size() >= edges.size();
    // a side branch (of the next order) starts at its own width, as veins.svg draws it: not flared
    const bool side = !closing && tree.order.size() == tree.size() && tree.order[c] != tree.order[p];
    const double rp = closing ? std::min(tree.radius[p], tree.radius[c]) : side ? tree.radius[c] : tree.radius[p];
    const double rc = closing ? rp : tree.radius[c];
    segments.push_back({tree.positions[p], tree.positions[c], rp, rc});
  }
  return segments;
}

}  // namespace cellform::app
