// The check command over exporters::check_mesh.
#include "app/check.h"

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/run.h"
#include "core/errors.h"
#include "export/mesh_check.h"
#include "export/mesh_read.h"
#include "export/stand.h"
#include "export/thickness.h"

namespace cellform::app {

namespace {

bool walled(const exporters::MeshReport& r) {
  return r.boundary_edges == 0 && r.nonmanifold_edges == 0 && r.consistently_oriented && r.misnested_parts == 0;
}

}  // namespace

int check_command(const std::filesystem::path& file, bool json, double min_wall, std::ostream& out, std::ostream& err) {
  exporters::MeshReport r;
  exporters::ThicknessReport th;
  exporters::MeshFileNotes notes;
  exporters::Stand stand;
  double cut_to_stand = 0;
  try {
    const exporters::PrintableMesh mesh = exporters::read_mesh(file, notes);
    r = exporters::check_mesh(mesh);
    // a wall has an inside only where the surfaces are closed and face one way (an open sheet's rays
    // cross its folds); two solids that touch at a corner still have walls
    if (walled(r)) th = exporters::wall_thickness(mesh);
    // standing means something for one solid piece (each of several stands or not)
    if (r.solid() && r.pieces == 1) {
      stand = exporters::stand_on_bed(mesh);
      if (exporters::falls(stand)) cut_to_stand = exporters::base_cut_to_stand(mesh, exporters::kFootTip);
    }
  } catch (const std::exception& e) {
    err << "cellform: " << core::error_text(e) << "\n";
    if (json)  // a program reading the report gets one too
      out << nlohmann::json({{"file", file.string()}, {"printable", false}, {"error", core::error_text(e)}})
                 .dump(2, ' ', false, nlohmann::json::error_handler_t::replace)
          << "\n";
    return usage;
  }
  // pieces, pockets, a volume and walls mean something only where the surfaces bound a solid the right way round
  const bool solid = r.solid();
  // --min-wall: the 1st percentile by area (single rays can cut a junction's corner), measured
  const bool thin = min_wall > 0 && !(th.samples > 0 && th.p01 >= min_wall);
  const std::string thin_text =
      !thin ? ""
      : th.samples > 0
          ? "walls thinner than --min-wall " + core::number_text(min_wall) +
                " over more than 1% of the surface (1% of it is thinner than " + core::number_text(th.p01) +
                "; a cellform print's walls are up to about a voxel, print.voxel_size, thinner than twice "
                "print.min_radius (veins) or print.shell_thickness (a shell))"
          : "walls not measured, so not known to be at least --min-wall " + core::number_text(min_wall);
  const bool printable = r.printable() && !thin;
  std::vector<std::string> problems = r.problems();
  if (thin) problems.push_back(thin_text);
  if (json) {
    // a thickness no ray measured is null, not 0
    auto measured = [&](double x) { return th.samples > 0 ? nlohmann::json(x) : nlohmann::json(nullptr); };
    nlohmann::json genus = nlohmann::json::array();  // null for a part that is no closed manifold
    for (const int g : r.genus) genus.push_back(g < 0 ? nlohmann::json(nullptr) : nlohmann::json(g));
    nlohmann::json j = {
        {"file", file.string()},
        {"printable", printable},
        {"min_wall", min_wall > 0 ? nlohmann::json(min_wall) : nlohmann::json(nullptr)},
        // the keys say mm, as cellform's printable files are; a mesh in other units (cells.ply is in
        // model units) keeps them
        {"units", "the file's own: the *_mm fields are millimetres for cellform's printable.* files"},
        {"problems", problems},
        {"triangles", r.triangles},
        {"vertices", r.vertices},
        // as run.json's print.parts: solid pieces, each with the cavities inside it; a surface's volume
        // sign means solid or pocket only on a closed, oriented mesh
        {"parts", solid ? nlohmann::json(r.pieces) : nlohmann::json(nullptr)},
        {"surfaces", r.parts},  // connected surfaces: a piece's outer wall and each cavity's wall count
        {"cavities", solid ? nlohmann::json(r.cavities) : nlohmann::json(nullptr)},
        {"boundary_edges", r.boundary_edges},
        {"nonmanifold_edges", r.nonmanifold_edges},
        {"nonmanifold_vertices", r.nonmanifold_vertices},
        {"consistently_oriented", r.consistently_oriented},
        {"misoriented_shells", r.nesting_tested ? nlohmann::json(r.misnested_parts) : nlohmann::json(nullptr)},
        {"self_intersections", r.intersections_tested ? nlohmann::json(r.self_intersections) : nlohmann::json(nullptr)},
        {"degenerate_triangles", r.degenerate_triangles},
        // STL only: stored facet normals against the winding (the verdict goes by the winding, as slicers do)
        {"stl_normals_against_winding",
         notes.normals_checked ? nlohmann::json(notes.normals_against_winding) : nlohmann::json(nullptr)},
        {"stl_padding_bytes", notes.stl_padding},  // binary STL: bytes after the last facet, ignored (0 otherwise)
        {"stl_count_zero", notes.stl_count_zero},  // binary STL whose header says 0 triangles, read by its size
        {"volume_mm3", solid ? nlohmann::json(r.volume) : nlohmann::json(nullptr)},
        {"area_mm2", r.area},
        {"bbox_min_mm", {r.bbox_min.x(), r.bbox_min.y(), r.bbox_min.z()}},
        {"bbox_max_mm", {r.bbox_max.x(), r.bbox_max.y(), r.bbox_max.z()}},
        {"genus", genus},
        {"wall_thickness_mm",
         {{"min", measured(th.min)},
          {"min_at",
           th.samples > 0 ? nlohmann::json({th.min_at.x(), th.min_at.y(), th.min_at.z()}) : nlohmann::json(nullptr)},
          {"p01", measured(th.p01)},
          {"median", measured(th.median)},
          {"samples", th.samples},
          {"missed", th.missed},
          {"given_up", th.given_up},
          // why no ray was cast: the surfaces are open, branch, or face both ways
          {"not_measured", walled(r) ? nlohmann::json(nullptr) : nlohmann::json("the surfaces bound no solid")}}},
        // on the plane of its lowest point, as a slicer lays it (null unless one solid piece)
        {"stand",
         !stand.measured
             ? nlohmann::json(nullptr)
             : nlohmann::json(
                   {{"footprint_mm2", stand.footprint_area},
                    {"tip_angle_deg", stand.tip_angle},
                    {"settle_angle_deg", stand.settle_angle},
                    {"centre_of_mass_mm",
                     {stand.centre_of_mass.x(), stand.centre_of_mass.y(), stand.centre_of_mass.z()}},
                    {"cut_to_stand_mm", cut_to_stand > 0 ? nlohmann::json(cut_to_stand) : nlohmann::json(nullptr)}})}};
    out << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
  } else {
    // the verdict, with its reasons, heads the report (summary() ends with it)
    const std::string summary = r.summary();
    const std::size_t last = summary.rfind('\n', summary.size() - 2) + 1;
    out << file.string() << ": "
        << (thin && r.printable() ? "NOT printable: " + thin_text + "\n" : summary.substr(last))
        << summary.substr(0, last);
    if (thin && !r.printable()) out << "also: " << thin_text << "\n";
    if (th.samples > 0)
      out << "wall thickness (in the file's units; cellform prints are in mm): 1% of the surface is thinner than "
          << th.p01 << ", median " << th.median << "; shortest ray " << th.min << " near (" << th.min_at.x() << ", "
          << th.min_at.y() << ", " << th.min_at.z() << ")\n";
    else if (!walled(r))
      out << "wall thickness: not measured (the surfaces bound no solid: a wall has no inside to cross)\n";
    else if (th.given_up > 0)
      out << "wall thickness: not measured (no ray that was followed left the solid through another wall)\n";
    else
      out << "wall thickness: not measurable (no ray from the surface left the solid through another wall)\n";
    if (stand.measured) {
      const bool rocks = stand.margin <= 0 && !exporters::falls(stand);
      const auto degrees = [](double a) {  // to a tenth
        const double tenth = std::round(a * 10) / 10;
        return core::number_text(tenth) + (tenth == 1 ? " degree" : " degrees");
      };
      if (stand.margin > 0)
        out << "stands on the bed (the plane of its lowest point): tips over when tilted " << degrees(stand.tip_angle)
            << "; ";
      else if (rocks)
        out << "rocks " << degrees(stand.settle_angle)
            << " onto more of its underside from the plane of its lowest point, where it does not stand: ";
      else
        out << "does NOT stand by itself on the bed (the plane of its lowest point): ";
      out << "its centre of mass (" << stand.centre_of_mass.x() << ", " << stand.centre_of_mass.y() << ", "
          << stand.centre_of_mass.z() << ") lies " << std::abs(stand.margin)
          << (stand.margin > 0 ? " inside" : " beyond") << " the edge of its footprint (area " << stand.footprint_area
          << ": the convex hull of what lies within " << exporters::kFirstLayer << " of the bed, a first layer in mm)"
          << (rocks ? ""
                    : (std::round(stand.settle_angle * 10) == 0
                           ? "; tipped over that edge it comes to rest at once"
                           : "; tipped over that edge it rolls " + degrees(stand.settle_angle) + " before it rests"))
          << "\n";
      if (exporters::falls(stand))
        out << "  "
            << (cut_to_stand > 0 ? "a cut of " + core::number_text(std::ceil(cut_to_stand * 10 - 1e-9) / 10) +
                                       " off the bottom (in a cellform print, added to its print.flat_base) leaves a "
                                       "foot that tips only past " +
                                       core::number_text(exporters::kFootTip) + " degrees"
                                 : "no cut off its lower half leaves, in one piece, a foot that tips only past " +
                                       core::number_text(exporters::kFootTip) + " degrees")
            << "\n";
    }
    if (th.given_up > 0)
      out << "  (" << th.given_up << " of the rays were given up where very many triangles meet at one spot)\n";
    if (notes.stl_padding > 0)
      out << "note: " << notes.stl_padding << (notes.stl_padding == 1 ? " byte" : " bytes")
          << " after the last facet of the binary STL were ignored (padding, as most slicers take it)\n";
    if (notes.stl_count_zero)
      out << "note: the binary STL's header says 0 triangles: the " << r.triangles
          << " facets that fill the file were read (some exporters leave the count unset; a program that trusts it "
             "reads nothing: export it again, or save it from a program that reads it so)\n";
    if (notes.normals_against_winding > 0)
      out << "warning: " << notes.normals_against_winding << " of the " << notes.stored_normals
          << " stored facet normals point against their triangle's winding (the check, and most slicers, go by the "
             "winding; a tool that trusts the stored normals sees those facets inside out)\n";
  }
  return printable ? ok : failure;
}

}  // namespace cellform::app
